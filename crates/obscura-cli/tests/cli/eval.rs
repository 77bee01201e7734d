//! `obscura eval`: the report, the JSON and the cached reference, the default's row, half
//! resolution, images scored from elsewhere, bad input.

use super::*;

#[test]
fn eval_writes_report_json_and_caches_the_reference() {
    let d = scratch("eval");
    let (report, json, cache) = (d.join("report"), d.join("q.json"), d.join("cache"));
    let args = [
        "--width", "64", "--height", "40", "--rays", "16", "--runs", "1",
    ];
    let run = || eval_cornell(&args, &report, Some(&json), &cache);
    let out = run();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("mean standard error"), "{err}");
    let md = std::fs::read_to_string(report.join("index.md")).unwrap();
    for e in ["gtao", "hbao", "vo", "vao", "sao", "vo-area", "bitmask"] {
        assert!(
            md.contains(&format!("| {e} screen-space reference |")),
            "{md}"
        );
        for m in ["randomized", "deinterleaved2", "deinterleaved4"] {
            assert!(md.contains(&format!("| {e} {m} |")), "{md}");
            let pic = image::open(report.join(format!("cornell-{e}-{m}-error.png"))).unwrap();
            assert_eq!(
                (pic.width(), pic.height()),
                (32, 20),
                "pictures at half size"
            );
        }
    }
    assert!(report.join("quality-vs-time.svg").exists());
    // The frontier: every one of the 21 variants and the default frame listed once, the
    // fastest on it.
    let front = &md[md
        .find("### Quality-versus-time frontier")
        .expect("frontier")..];
    let listed: Vec<&str> = front
        .lines()
        .filter(|l| l.ends_with("**frontier** |") || l.contains("| beaten by "))
        .collect();
    assert_eq!(listed.len(), 22, "{front}");
    assert!(listed[0].ends_with("**frontier** |"), "{front}");
    assert!(report.join("frontier.svg").exists());
    let j = std::fs::read_to_string(&json).unwrap();
    // White baseline + 7 screen-space references + 7 estimators × 3 modes + the default
    // frame (no flag picked the variants).
    let records = j.matches("\"view\": \"cornell\", \"variant\"").count();
    assert_eq!(records, 30, "{j}");
    assert_eq!(j.matches("\"estimator\": \"gtao\"").count(), 5, "{j}");
    // Every estimate has its sampling error against its screen-space reference.
    assert_eq!(j.matches("\"screen_rmse\": null").count(), 8, "{j}");
    // Its sampling bias is its bias minus its screen-space reference's (same pixels), to
    // the JSON's rounding, and the report lists every estimate's.
    let v: serde_json::Value = serde_json::from_str(&j).unwrap();
    let records = v["records"].as_array().unwrap();
    let bias_of = |view: &serde_json::Value, variant: &str| {
        records
            .iter()
            .find(|r| &r["view"] == view && r["variant"] == variant)
            .and_then(|r| r["bias"].as_f64())
            .unwrap()
    };
    let mut checked = 0;
    for r in records.iter().filter(|r| r["screen_bias"].is_number()) {
        let est = r["estimator"].as_str().unwrap();
        let want = r["bias"].as_f64().unwrap()
            - bias_of(&r["view"], &format!("{est} screen-space reference"));
        let got = r["screen_bias"].as_f64().unwrap();
        assert!(
            (got - want).abs() <= 2e-5,
            "{}: {got} vs {want}",
            r["variant"]
        );
        checked += 1;
    }
    assert_eq!(checked, 22, "{j}");
    // ꟻLIP on every record, in [0, 1]; the default frame is marked; its pictures include
    // its ꟻLIP map and its pattern error.
    for r in records {
        let f = r["flip"].as_f64().unwrap();
        assert!((0.0..=1.0).contains(&f), "{r}");
    }
    let defaults: Vec<_> = records.iter().filter(|r| r["default"] == true).collect();
    assert_eq!(defaults.len(), 1, "{j}");
    assert_eq!(defaults[0]["variant"], "default");
    assert!(defaults[0]["screen_flip"].as_f64().unwrap() > 0.0);
    for stem in ["default-flip", "default-pattern", "gtao-randomized-flip"] {
        assert!(
            report.join(format!("cornell-{stem}.png")).exists(),
            "{stem}"
        );
    }
    assert!(md.contains("ꟻLIP against the truth"), "{md}");
    let sampling = &md[md.find("### Sampling bias").expect("sampling bias")..];
    assert_eq!(
        sampling
            .lines()
            .filter(|l| l.ends_with("| cornell |"))
            .count(),
        22,
        "{sampling}"
    );
    // The second run finds the reference in the cache.
    let again = run();
    assert!(String::from_utf8_lossy(&again.stderr).contains("reference: cached"));
    std::fs::remove_dir_all(d).unwrap();
}

/// eval's default row is what the input's users get: GTAO with the renderer's normals, the
/// depth-map estimator (the bitmask) with normals from the depth.
#[test]
fn eval_default_row_follows_the_input() {
    let d = scratch("eval-default-input");
    for (normals, estimator) in [("gbuffer", "gtao"), ("reconstruct", "bitmask")] {
        let (report, json) = (d.join(normals), d.join(format!("{normals}.json")));
        let args = [
            "--width",
            "48",
            "--height",
            "32",
            "--rays",
            "8",
            "--runs",
            "1",
            "--no-screen-reference",
            "--normals",
            normals,
        ];
        let out = eval_cornell(&args, &report, Some(&json), &d.join("cache"));
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        let defaults: Vec<_> = v["records"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|r| r["default"] == true)
            .collect();
        assert_eq!(defaults.len(), 1, "{normals}");
        assert_eq!(defaults[0]["variant"], "default");
        assert_eq!(defaults[0]["estimator"], estimator, "{normals}");
    }
    std::fs::remove_dir_all(d).unwrap();
}

/// Below full resolution a variant is compared with the full-resolution one of the same
/// preset, although High's counts differ there (3 × 6 crowded at full resolution in the
/// 2×2 layout, 4 × 4 even at half): its "RMSE vs full res" is a number; the
/// full-resolution variant's own row has none.
#[test]
fn eval_compares_half_resolution_with_the_same_presets_full_resolution() {
    let d = scratch("eval-full-of");
    let (report, json, cache) = (d.join("report"), d.join("q.json"), d.join("cache"));
    let args = [
        "--width",
        "64",
        "--height",
        "40",
        "--rays",
        "16",
        "--runs",
        "1",
        "--estimators",
        "gtao",
        "--modes",
        "deinterleaved2",
        "--resolutions",
        "full,half",
        "--denoise",
        "none",
        "--no-screen-reference",
        "--no-pictures",
    ];
    let out = eval_cornell(&args, &report, Some(&json), &cache);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v = read_json(&json);
    let half = record(&v, "gtao deinterleaved2 half checkerboard bilateral");
    let full = record(&v, "gtao deinterleaved2");
    assert!(full["full_rmse"].is_null(), "{full}");
    let vs_full = half["full_rmse"]
        .as_f64()
        .expect("half resolution has RMSE vs full");
    // RMSE over one mask is a distance between images: half resolution's distance to the
    // full-resolution image obeys the triangle inequality with both distances to the
    // truth. It fails if the comparison picked another image (white, another preset).
    let (a, b) = (
        half["rmse"].as_f64().unwrap(),
        full["rmse"].as_f64().unwrap(),
    );
    assert!(
        vs_full > 0.0 && vs_full >= (a - b).abs() - 1e-6 && vs_full <= a + b + 1e-6,
        "half vs full {vs_full}, against the truth {a} and {b}: {half}"
    );
    std::fs::remove_dir_all(d).unwrap();
}

/// `eval --score-images`: AO images made elsewhere get the same metrics as the variants.
/// Analytic checks: a white 16-bit image scores exactly what the "white (no AO)" row does;
/// a uniform 0.5 (8-bit 128/255) has that row's RMSE structure shifted: its bias is the
/// white row's minus (1 − 128/255). Missing, mis-sized and absent folders are refused.
#[test]
fn eval_scores_images_made_elsewhere() {
    let d = scratch("eval-images");
    let (white, grey, json, cache) = (
        d.join("white"),
        d.join("grey"),
        d.join("q.json"),
        d.join("cache"),
    );
    std::fs::create_dir_all(&white).unwrap();
    std::fs::create_dir_all(&grey).unwrap();
    let (w, h) = (64u32, 40u32);
    image::ImageBuffer::<image::Luma<u16>, _>::from_pixel(w, h, image::Luma([65535u16]))
        .save(white.join("cornell.png"))
        .unwrap();
    image::ImageBuffer::<image::Luma<u8>, _>::from_pixel(w, h, image::Luma([128u8]))
        .save(grey.join("cornell.png"))
        .unwrap();
    let dirs = format!("{},{}", s(&white), s(&grey));
    let args = [
        "--width",
        "64",
        "--height",
        "40",
        "--rays",
        "16",
        "--runs",
        "1",
        "--estimators",
        "gtao",
        "--modes",
        "deinterleaved2",
        "--no-screen-reference",
        "--score-images",
        &dirs,
    ];
    let out = eval_cornell(&args, &d.join("report"), Some(&json), &cache);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let v = read_json(&json);
    let row = |variant: &str| {
        v["records"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["variant"] == variant)
            .unwrap_or_else(|| panic!("no row {variant}: {v}"))
            .clone()
    };
    let (none, wi, gr) = (row("white (no AO)"), row("image white"), row("image grey"));
    for k in ["rmse", "bias", "band_rmse", "ssim"] {
        assert_eq!(none[k], wi[k], "{k}");
    }
    let shift = 1.0 - 128.0 / 255.0;
    let want = none["bias"].as_f64().unwrap() - shift;
    assert!(
        (gr["bias"].as_f64().unwrap() - want).abs() < 2e-4,
        "{gr} vs {want}"
    );
    assert!(
        gr["median_ms"].is_null() && gr["estimator"] == "image",
        "{gr}"
    );
    let md = std::fs::read_to_string(d.join("report").join("index.md")).unwrap();
    assert!(md.contains("| image grey |"), "{md}");
    // A one-channel (Y) EXR of the same grey, a common way to store grey AO, scores as the
    // 8-bit PNG does; an EXR whose AO leaves [0, 1] is refused.
    let exr_dir = |name: &str, value: f32| {
        let dir = d.join(name);
        std::fs::create_dir_all(&dir).unwrap();
        let y = exr::prelude::AnyChannel::new(
            "Y",
            exr::prelude::FlatSamples::F32(vec![value; (w * h) as usize]),
        );
        let channels = exr::prelude::AnyChannels::sort(exr::prelude::SmallVec::from_vec(vec![y]));
        use exr::prelude::WritableImage as _;
        exr::prelude::Image::from_channels((w as usize, h as usize), channels)
            .write()
            .to_file(dir.join("cornell.exr"))
            .unwrap();
        dir
    };
    let y = exr_dir("ygrey", 128.0 / 255.0);
    let (yjson, yargs) = (d.join("y.json"), s(&y).to_string());
    let mut with_y = args.to_vec();
    let last = with_y.len() - 1;
    with_y[last] = &yargs;
    let out = eval_cornell(&with_y, &d.join("report-y"), Some(&yjson), &cache);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let yv = read_json(&yjson);
    let yrow = yv["records"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["variant"] == "image ygrey")
        .unwrap_or_else(|| panic!("no row image ygrey: {yv}"))
        .clone();
    for k in ["rmse", "bias"] {
        let (a, b) = (yrow[k].as_f64().unwrap(), gr[k].as_f64().unwrap());
        assert!((a - b).abs() < 1e-6, "{k}: Y EXR {a}, PNG {b}");
    }
    for (name, value) in [("bright", 5.0), ("negative", -1.0)] {
        let dir = exr_dir(name, value);
        let mut bad = args.to_vec();
        let text = s(&dir).to_string();
        bad[last] = &text;
        let out = eval_cornell(&bad, &d.join("report-bad"), None, &cache);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{name}: {err}");
        assert!(err.contains("AO must be in [0, 1]"), "{name}: {err}");
        assert!(
            !d.join("report-bad").exists(),
            "{name}: refused before any work"
        );
    }
    // A view without an image, an image of the wrong size, and no folder at all.
    let empty = d.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let small = d.join("small");
    std::fs::create_dir_all(&small).unwrap();
    image::ImageBuffer::<image::Luma<u8>, _>::from_pixel(8, 8, image::Luma([255u8]))
        .save(small.join("cornell.png"))
        .unwrap();
    for (dir, says) in [
        (
            s(&empty).to_string(),
            "has no `cornell.png` or `cornell.exr`",
        ),
        (s(&small).to_string(), "is 8x8; eval renders 64x40"),
        (s(&d.join("nowhere")).to_string(), "is not a folder"),
    ] {
        let mut bad = args.to_vec();
        let last = bad.len() - 1;
        bad[last] = &dir;
        let out = eval_cornell(&bad, &d.join("report2"), None, &cache);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains(says), "{says}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    // --export-views: the cameras and radii a peer renders the same views with, and no
    // tracing (no cache is made).
    let views = d.join("views.json");
    let cache2 = d.join("cache2");
    let out = eval_cornell(
        &["--export-views", s(&views), "--radius", "30"],
        &d.join("report3"),
        None,
        &cache2,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v = read_json(&views);
    let c = &v["views"][0];
    assert_eq!(v["views"].as_array().unwrap().len(), 1);
    assert_eq!(c["name"], "cornell");
    assert_eq!(c["eye"], serde_json::json!([278.0, 273.0, -800.0]));
    assert_eq!(c["target"], serde_json::json!([278.0, 273.0, 0.0]));
    assert_eq!(
        (c["fov_y_deg"].as_f64(), c["radius"].as_f64()),
        (Some(39.0), Some(30.0))
    );
    assert_eq!(
        (c["width"].as_u64(), c["height"].as_u64()),
        (Some(640), Some(400))
    );
    let (near, far) = (c["near"].as_f64().unwrap(), c["far"].as_f64().unwrap());
    assert!(0.0 < near && near < 800.0 && far > 800.0, "{c}");
    assert!(
        c["scene"].as_str().unwrap().ends_with("cornell_box.obj"),
        "{c}"
    );
    assert!(!cache2.exists(), "nothing traced");
    std::fs::remove_dir_all(d).unwrap();
}

#[test]
fn eval_rejects_bad_input() {
    for (args, msg) in [
        (&["eval"][..], "choose what to evaluate"),
        (&["eval", "--view", "nowhere"][..], "unknown view"),
        (&["eval", "--view", "cornell", "--rays", "0"][..], "--rays"),
        (&["eval", "--scene", "/no/such.glb"][..], "/no/such.glb"),
        (
            &["eval", "--view", "cornell", "--radius=-1"][..],
            "--radius",
        ),
        (
            &[
                "eval",
                "--view",
                "cornell",
                "--presets",
                "low",
                "--splits",
                "4x4",
            ][..],
            "cannot be used with",
        ),
        (
            &["eval", "--view", "cornell", "--presets", "extreme"][..],
            "--presets",
        ),
        (
            &["eval", "--view", "cornell", "--frames", "8,0"][..],
            "0 is not in 1..=1000",
        ),
        (
            &[
                "eval",
                "--view",
                "cornell",
                "--frames",
                "1,8",
                "--history",
                "0",
            ][..],
            "'0' for '--history <HISTORY>': 0 is not in 2..=256",
        ),
        (
            &["eval", "--view", "cornell", "--sensor-noise", "0"][..],
            "--sensor-noise does nothing here",
        ),
        (
            &[
                "eval",
                "--view",
                "cornell",
                "--sensor",
                "kinect",
                "--sensor-noise=-1",
            ][..],
            "--sensor-noise must be in 0..=10",
        ),
        (
            &[
                "eval", "--view", "cornell", "--sensor", "kinect", "--frames", "1,8",
            ][..],
            "--sensor evaluates single frames",
        ),
        (
            &[
                "eval",
                "--view",
                "cornell",
                "--guard-bands",
                "0,16",
                "--sensor",
                "kinect",
            ][..],
            "--guard-bands evaluates a renderer's clean depth",
        ),
        (
            &["eval", "--view", "cornell", "--guard-bands", "2000"][..],
            "2000 is not in 0..=1024",
        ),
        (
            &["eval", "--view", "cornell", "--second-layer", "--msaa"][..],
            "--second-layer evaluates clean single-sampled depth",
        ),
        (
            &[
                "eval",
                "--view",
                "cornell",
                "--second-layer",
                "--estimators",
                "gtao",
            ][..],
            "--second-layer does nothing here",
        ),
    ] {
        let out = obscura(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && !err.contains("panicked"),
            "{args:?}: {err}"
        );
        assert!(err.contains(msg), "{args:?}: expected `{msg}` in {err}");
    }
}
