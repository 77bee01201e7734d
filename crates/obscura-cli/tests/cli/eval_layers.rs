//! `obscura eval` beyond one raster frame: traced depth, guard bands, a second layer,
//! accumulated frames, bent normals, sensor noise.

use super::*;

/// `eval --traced-depth`: the estimators read the ray tracer's exact depth instead of the
/// raster's. Since obscura-scene rasterizes reversed-Z the two agree: on the bunny view at
/// 320 × 200 the screen-space reference scored RMSE 0.0254 and bias −0.0060 on both when
/// written; with the standard convention (far/near 10⁴) the raster's was 0.0265 and
/// −0.0078, its steps read as slopes by the near samples. They must stay within 0.0005.
/// Refused with a guard band or accumulated frames.
#[test]
fn eval_takes_the_traced_depth() {
    let d = scratch("eval-traced-depth");
    let run = |extra: &[&str]| {
        let args = [
            &["--width", "320", "--height", "200", "--rays", "32"],
            extra,
        ]
        .concat();
        let (v, err) = eval_view_logged(
            &d,
            "bunny",
            &[&args[..], &["--estimators", "gtao"]].concat(),
        );
        let said = err.contains("depth: the ray tracer's (--traced-depth)");
        (record(&v, "gtao screen-space reference"), said)
    };
    let ((raster, raster_said), (traced, traced_said)) = (run(&[]), run(&["--traced-depth"]));
    assert!(
        traced_said && !raster_said,
        "the traced depth is used only when asked"
    );
    let of = |r: &serde_json::Value, k: &str| r[k].as_f64().unwrap();
    assert!(
        (of(&traced, "rmse") - of(&raster, "rmse")).abs() <= 5e-4
            && (of(&traced, "bias") - of(&raster, "bias")).abs() <= 5e-4,
        "traced {traced} against the raster's {raster}"
    );
    for extra in [["--guard-bands", "0,16"], ["--frames", "4"]] {
        let out = obscura(&[&["eval", "--traced-depth"], &extra[..]].concat());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains("--traced-depth"),
            "{err}"
        );
    }
    std::fs::remove_dir_all(d).unwrap();
}

/// `eval --msaa --guard-bands 0,16`: the multisampled depth rasterized with the band, a
/// variant per band, and on Sponza (whose arcade runs off the view's sides) the band
/// lowers the error against the MSAA truth.
#[test]
fn eval_takes_guard_bands_with_msaa_depth() {
    let d = scratch("eval-guard-msaa");
    let v = eval_view(
        &d,
        "sponza",
        &[
            "--width",
            "64",
            "--height",
            "40",
            "--rays",
            "8",
            "--estimators",
            "gtao",
            "--msaa",
            "--guard-bands",
            "0,16",
            "--no-screen-reference",
        ],
    );
    let rmse = |variant: &str| record(&v, variant)["rmse"].as_f64().unwrap();
    let (bare, banded) = (
        rmse("gtao deinterleaved2 g0"),
        rmse("gtao deinterleaved2 g16"),
    );
    assert!(banded < bare, "band {banded} against none {bare}");
    std::fs::remove_dir_all(d).unwrap();
}

/// `eval --guard-bands 0,16 --frames 1,3`: each variant and each screen-space reference
/// once per band, labelled; a variant's sampling bias is measured against the screen-space
/// reference of its own band (its bias minus that reference's, to the JSON's rounding); the
/// band changes the AO, of accumulated frames on the orbit too.
#[test]
fn eval_runs_each_guard_band_against_its_own_reference() {
    let d = scratch("eval-guard");
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
        "randomized",
        "--guard-bands",
        "0,16",
        "--frames",
        "1,3",
        "--no-pictures",
    ];
    // Sponza: its arcade runs off the view's sides (the Cornell box's walls continue flat
    // beyond its edges, so a band changes nothing there).
    let scenes = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/scenes");
    let mut all = vec!["eval", "--view", "sponza", "--scenes-dir", scenes];
    all.extend_from_slice(&args);
    all.extend([
        "--report",
        s(&report),
        "--cache",
        s(&cache),
        "--json",
        s(&json),
    ]);
    let out = obscura(&all);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let v = read_json(&json);
    let bias = |variant: &str| record(&v, variant)["bias"].as_f64().unwrap();
    for g in ["g0", "g16"] {
        let variant = format!("gtao randomized {g}");
        let want = bias(&variant) - bias(&format!("gtao {g} screen-space reference"));
        let got = record(&v, &variant)["screen_bias"].as_f64().unwrap();
        assert!((got - want).abs() <= 2e-5, "{variant}: {got} vs {want}");
    }
    assert_ne!(
        bias("gtao g0 screen-space reference"),
        bias("gtao g16 screen-space reference"),
        "the band changes the reference"
    );
    // Accumulated frames with a band: still and orbit, on the banded raster.
    let orbit = |variant: &str| record(&v, variant)["orbit_rmse"].as_f64().unwrap();
    let (bare, banded) = (
        orbit("gtao randomized ×3 g0"),
        orbit("gtao randomized ×3 g16"),
    );
    assert!(
        bare > 0.0 && banded > 0.0 && bare != banded,
        "{bare} {banded}"
    );
    std::fs::remove_dir_all(d).unwrap();
}

/// `eval --second-layer --frames 1,2`: each full-resolution bitmask variant beside its twin
/// with a second layer ("L2"), each against its own screen-space reference (its bias minus
/// that reference's, to the JSON's rounding); the second layer lowers the error on Sponza,
/// whose columns stand before walls, and the peel is reported; accumulated frames with a
/// second layer (peeled every orbit frame) differ from those without it.
#[test]
fn eval_second_layer_runs_beside_one_layer() {
    let d = scratch("eval-second");
    let (json, cache) = (d.join("q.json"), d.join("cache"));
    let scenes = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/scenes");
    let out = obscura(&[
        "eval",
        "--view",
        "sponza",
        "--scenes-dir",
        scenes,
        "--width",
        "96",
        "--height",
        "60",
        "--rays",
        "64",
        "--runs",
        "1",
        "--estimators",
        "bitmask",
        "--modes",
        "deinterleaved2",
        "--second-layer",
        "--frames",
        "1,2",
        "--cache",
        s(&cache),
        "--json",
        s(&json),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("second layer peeled at t1"), "{err}");
    let v = read_json(&json);
    let field = |variant: &str, f: &str| record(&v, variant)[f].as_f64().unwrap();
    for (variant, screen) in [
        ("bitmask deinterleaved2", "bitmask screen-space reference"),
        (
            "bitmask deinterleaved2 L2",
            "bitmask L2 screen-space reference",
        ),
    ] {
        let want = field(variant, "bias") - field(screen, "bias");
        let got = field(variant, "screen_bias");
        assert!((got - want).abs() <= 2e-5, "{variant}: {got} vs {want}");
    }
    let (one, two) = (
        field("bitmask deinterleaved2", "rmse"),
        field("bitmask deinterleaved2 L2", "rmse"),
    );
    assert!(two < one, "the second layer: {two} against {one}");
    let orbit = |variant: &str| record(&v, variant)["orbit_rmse"].as_f64().unwrap();
    let (one, two) = (
        orbit("bitmask deinterleaved2 ×2"),
        orbit("bitmask deinterleaved2 L2 ×2"),
    );
    assert!(one > 0.0 && two > 0.0 && one != two, "orbits {one} {two}");
    std::fs::remove_dir_all(d).unwrap();
}

/// `eval --frames 1,3,5`: single frames and accumulated ones in one run and one frontier.
/// A ×3 variant that joins the 5-frame orbit two frames in scores exactly as it does alone
/// (`--frames 3`: the same three cameras, a cut before the first); single frames have no
/// orbit but its last two frames' flicker, above the accumulated frames'; the frontier shows
/// the moving camera's error.
#[test]
fn eval_puts_single_and_accumulated_frames_in_one_frontier() {
    let d = scratch("eval-frames");
    let cache = d.join("cache");
    let run = |frames: &str, tag: &str| -> (String, serde_json::Value) {
        let (report, json) = (
            d.join(format!("report-{tag}")),
            d.join(format!("{tag}.json")),
        );
        let out = eval_cornell(
            &[
                "--estimators",
                "gtao",
                "--modes",
                "randomized",
                "--frames",
                frames,
                "--orbit-step",
                "3",
                "--width",
                "64",
                "--height",
                "40",
                "--rays",
                "16",
                "--runs",
                "1",
                "--no-screen-reference",
                "--no-pictures",
            ],
            &report,
            Some(&json),
            &cache,
        );
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let md = std::fs::read_to_string(report.join("index.md")).unwrap();
        let j = std::fs::read_to_string(&json).unwrap();
        (md, serde_json::from_str(&j).unwrap())
    };
    let (md, all) = run("1,3,5", "all");
    let (_, alone) = run("3", "alone");
    let single = record(&all, "gtao randomized");
    assert_eq!(single["frames"], 1);
    assert!(single["orbit_rmse"].is_null(), "{single}");
    // On the moving camera a single frame's pattern stays on the screen while the surface
    // moves under it; accumulation averages it over frames: less flicker beyond the truth's.
    let moving = |r: &serde_json::Value| r["orbit_flicker"].as_f64().unwrap();
    let (one, five) = (moving(&single), moving(&record(&all, "gtao randomized ×5")));
    assert!(
        five < one && five > 0.0,
        "orbit flicker: ×5 {five}, single {one}"
    );
    for (n, r) in [
        (3, record(&all, "gtao randomized ×3")),
        (5, record(&all, "gtao randomized ×5")),
    ] {
        assert_eq!(r["frames"], n);
        assert!(r["orbit_rmse"].as_f64().unwrap() > 0.0, "{r}");
    }
    let (joined, own) = (
        record(&all, "gtao randomized ×3"),
        record(&alone, "gtao randomized ×3"),
    );
    for k in ["rmse", "orbit_rmse", "flicker", "orbit_flicker"] {
        let (a, b) = (joined[k].as_f64().unwrap(), own[k].as_f64().unwrap());
        // The JSON's 5 decimals: one rounding step apart at most.
        assert!((a - b).abs() <= 1.5e-5, "{k}: {a} joined, {b} alone");
    }
    // The orbit's last frame differs from the still camera's (the camera moved 6°–12°).
    assert_ne!(joined["orbit_rmse"], joined["rmse"]);
    let front = &md[md
        .find("### Quality-versus-time frontier")
        .expect("frontier")..];
    assert!(
        front.contains("| variant | RMSE | moving | bias | ms | |"),
        "{front}"
    );
    let listed: Vec<&str> = front
        .lines()
        .filter(|l| l.ends_with("**frontier** |") || l.contains("| beaten by "))
        .collect();
    assert_eq!(listed.len(), 3, "{front}");
    let row = listed
        .iter()
        .find(|l| l.starts_with("| gtao randomized |"))
        .unwrap();
    assert!(
        row.contains("| – |"),
        "a single frame has no moving figure: {row}"
    );
    std::fs::remove_dir_all(d).unwrap();
}

/// `eval --bent-normals`: GTAO's full-resolution variants get their bent normals scored
/// against the ray tracer's (numbers in the JSON, a table in the report), and where the
/// traced AO shows occlusion GTAO's bent normal is nearer the traced one than the surface
/// normal is (Cornell box, randomized, 256 rays; 12° against 20° at 160×100).
#[test]
fn eval_scores_bent_normals_against_the_ray_tracer() {
    let d = scratch("eval-bent");
    let (report, json, cache) = (d.join("report"), d.join("q.json"), d.join("cache"));
    let out = eval_cornell(
        &[
            "--estimators",
            "gtao,hbao",
            "--modes",
            "randomized",
            "--bent-normals",
            "--width",
            "128",
            "--height",
            "80",
            "--rays",
            "256",
            "--runs",
            "1",
            "--no-screen-reference",
            "--no-pictures",
        ],
        &report,
        Some(&json),
        &cache,
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let v = read_json(&json);
    let of = |variant: &str, field: &str| record(&v, variant)[field].clone();
    for variant in ["gtao randomized", "hbao randomized"] {
        let deg = |field| of(variant, field).as_f64().unwrap();
        for field in [
            "bent_deg",
            "normal_deg",
            "bent_occluded_deg",
            "normal_occluded_deg",
        ] {
            assert!(
                (0.0..90.0).contains(&deg(field)),
                "{variant} {field}: {}",
                deg(field)
            );
        }
        assert!(
            deg("bent_occluded_deg") < deg("normal_occluded_deg"),
            "{variant} occluded: bent {} vs normal {}",
            deg("bent_occluded_deg"),
            deg("normal_occluded_deg")
        );
    }
    let md = std::fs::read_to_string(report.join("index.md")).unwrap();
    let table = &md[md.find("### Bent normals").expect("bent normals table")..];
    assert!(
        table.contains("| gtao randomized |") && table.contains("| hbao randomized |"),
        "{table}"
    );
    std::fs::remove_dir_all(d).unwrap();
}

/// `eval --sensor` reconstructs the normals from the sensor-like depth unless `--normals
/// gbuffer` asks for the G-buffer's: then the normals obscura uses are exactly the clean
/// run's (the same angle to the traced bent normals, within float noise), and the
/// reconstructed ones are not.
#[test]
fn eval_sensor_takes_the_gbuffer_normals_when_asked() {
    let d = scratch("eval-sensor-normals");
    let cache = d.join("cache");
    let normal_deg = |extra: &[&str], tag: &str| -> f64 {
        let (report, json) = (
            d.join(format!("report-{tag}")),
            d.join(format!("{tag}.json")),
        );
        let mut args = vec![
            "--estimators",
            "gtao",
            "--modes",
            "randomized",
            "--bent-normals",
            "--width",
            "96",
            "--height",
            "60",
            "--rays",
            "32",
            "--runs",
            "1",
            "--no-screen-reference",
            "--no-pictures",
        ];
        args.extend_from_slice(extra);
        let out = eval_cornell(&args, &report, Some(&json), &cache);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{extra:?}: {err}");
        record(&read_json(&json), "gtao randomized")["normal_deg"]
            .as_f64()
            .unwrap()
    };
    let clean = normal_deg(&[], "clean");
    let given = normal_deg(&["--sensor", "kinect", "--normals", "gbuffer"], "given");
    let reconstructed = normal_deg(&["--sensor", "kinect"], "reconstructed");
    assert!((given - clean).abs() < 0.01, "{given} vs {clean}");
    assert!(
        (reconstructed - clean).abs() > 0.1,
        "{reconstructed} vs {clean}"
    );
    std::fs::remove_dir_all(d).unwrap();
}
