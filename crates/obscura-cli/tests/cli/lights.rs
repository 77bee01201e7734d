//! `obscura lights` and SSDO: interleaved shading against every light, lights files, the
//! furnace test, SSDO against AO on the Cornell box, bad input.

use super::*;

#[test]
fn lights_compares_interleaved_shading_with_every_light() {
    let d = scratch("lights");
    let md = d.join("lights.md");
    let out = obscura(&[
        "lights",
        "--width",
        "160",
        "--height",
        "96",
        "--count",
        "64",
        "--periods",
        "2,4",
        "--runs",
        "1",
        "--out-dir",
        s(&d),
        "--markdown",
        s(&md),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let table = String::from_utf8_lossy(&out.stdout);
    for n in [2, 4] {
        let merged = table_error(&table, &format!("{n}×{n} interleaved + merge"));
        let layered = table_error(&table, &format!("{n}×{n} layered + merge"));
        let raw = table_error(&table, &format!("{n}×{n} interleaved, no merge"));
        let (Some(merged), Some(layered), Some(raw)) = (merged, layered, raw) else {
            panic!("rows for {n}×{n} missing: {table}");
        };
        // The same lights per pixel either way; the merge is what brings the error down.
        assert!((merged - layered).abs() < 1e-3, "{table}");
        assert!(
            merged < 0.5 * raw,
            "{n}×{n}: merged {merged}, raw {raw}: {table}"
        );
    }
    // The pictures: the merged image is closer to every light's than the raw one.
    let read = |name: &str| image::open(d.join(name)).unwrap().to_rgb8();
    let all = read("courtyard-all.png");
    assert_eq!(all.dimensions(), (160, 96));
    let distance = |img: &image::RgbImage| -> f64 {
        img.pixels()
            .zip(all.pixels())
            .map(|(a, b)| {
                (0..3)
                    .map(|c| (a[c] as f64 - b[c] as f64).powi(2))
                    .sum::<f64>()
            })
            .sum()
    };
    let (merged, raw) = (read("courtyard-4x4.png"), read("courtyard-4x4-raw.png"));
    assert!(distance(&merged) < 0.25 * distance(&raw));
    let text = std::fs::read_to_string(&md).unwrap();
    assert!(
        text.contains("courtyard-4x4.png") && text.contains("every light"),
        "{text}"
    );
}

#[test]
fn lights_rejects_bad_input() {
    for (args, message) in [
        (&["--periods", "3"][..], "--periods"),
        (&["--count", "0"][..], "--count"),
        (&["--count", "4096"][..], "--count"),
        (&["--width", "0"][..], "--width"),
        (&["--runs", "0"][..], "--runs"),
        (&["--view", "nosuch"][..], "unknown view"),
    ] {
        let mut all = vec!["lights"];
        all.extend_from_slice(args);
        let out = obscura(&all);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} should fail");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(
            err.contains(message),
            "{args:?}: expected `{message}` in {err}"
        );
    }
}

#[test]
fn lights_reads_a_lights_file_and_refuses_bad_ones() {
    let d = scratch("lights-file");
    let good = d.join("lights.json");
    std::fs::write(
        &good,
        r#"{"lights": [
            {"position": [0, 2, 0], "colour": [1, 0.8, 0.6], "range": 8},
            {"position": [3, 1, 2], "colour": [0.2, 0.4, 1], "range": 5},
            {"position": [-3, 1, -2], "colour": [1, 1, 1], "range": 6}
        ]}"#,
    )
    .unwrap();
    let out = obscura(&[
        "lights",
        "--lights-file",
        s(&good),
        "--width",
        "96",
        "--height",
        "64",
        "--periods",
        "2",
        "--runs",
        "1",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(table.starts_with("3 lights, 96x64"), "{table}");
    for (name, text, message) in [
        ("missing.json", None, "cannot read lights file"),
        ("notjson.json", Some("[{"), "is not JSON"),
        ("object.json", Some(r#"{"x": 1}"#), "expected an array"),
        ("empty.json", Some("[]"), "0 lights"),
        (
            "short.json",
            Some(r#"[{"position": [0, 1], "colour": [1, 1, 1], "range": 1}]"#),
            "light 0: `position`",
        ),
        (
            "range.json",
            Some(r#"[{"position": [0, 1, 2], "colour": [1, 1, 1], "range": 0}]"#),
            "light 0: PointLight",
        ),
        (
            "colour.json",
            Some(r#"[{"position": [0, 1, 2], "colour": [1, -1, 1], "range": 2}]"#),
            "a colour in [0, 1e20] and a range in [1e-15, 1e18]",
        ),
    ] {
        let path = d.join(name);
        if let Some(t) = text {
            std::fs::write(&path, t).unwrap();
        }
        let out = obscura(&["lights", "--lights-file", s(&path), "--runs", "1"]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{name} should fail");
        assert!(!err.contains("panicked"), "{name}: {err}");
        assert!(
            err.contains(message),
            "{name}: expected `{message}` in {err}"
        );
        assert!(
            !err.contains("adapter:"),
            "{name}: failed after starting GPU work: {err}"
        );
    }
    std::fs::remove_dir_all(d).unwrap();
}

/// The built-in scene is white (no materials): under a constant sky L every open surface
/// reflects L, and where occluders hide the sky they bounce L back (their own albedo 1 ×
/// L), so the whole image stays near L (a furnace): SSDO's direct light and its bounce
/// must add up. Checked on the 8-bit sRGB image of L = 0.5 (sRGB 188).
#[test]
fn render_writes_ssdo_colour_images_that_pass_a_furnace_test() {
    let d = scratch("ssdo");
    let (ao, png, exr) = (d.join("ao.png"), d.join("ssdo.png"), d.join("ssdo.exr"));
    // One 192×108 SSDO render of the built-in scene under `env`, with `extra` arguments.
    let ssdo = |image: &Path, env: &str, extra: &[&str]| {
        let mut args = vec![
            "render", "--width", "192", "--height", "108", "--runs", "1", "--out",
        ];
        args.extend([s(&ao), "--ssdo", s(image), "--env", env]);
        args.extend(extra);
        let out = obscura(&args);
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "{err}");
        err
    };
    // The green channel of the surface pixels (red > 0), sorted.
    let surface = |image: &image::RgbImage| {
        let mut v: Vec<u8> = image.pixels().filter(|p| p[0] > 0).map(|p| p[1]).collect();
        v.sort_unstable();
        v
    };
    let err = ssdo(&png, "constant:0.5,0.5,0.5", &[]);
    assert!(err.contains("ssdo:") && err.contains("median"), "{err}");
    let img = image::open(&png).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (192, 108));
    let surface_values = surface(&img);
    let n = surface_values.len();
    assert!(n > 192 * 108 / 2, "{n} surface pixels");
    let (p05, p50, p95) = (
        surface_values[n / 20],
        surface_values[n / 2],
        surface_values[n - n / 20 - 1],
    );
    assert!(
        (184..=192).contains(&p50) && p05 >= 160 && p95 <= 215,
        "surface values 5%/50%/95%: {p05}/{p50}/{p95}, want about 188"
    );
    // With a guard band of 16 px (the G-buffer, its albedo and SSDO's bounce cover it; the
    // image is the view's): the same size, and still a furnace.
    let banded = d.join("banded.png");
    ssdo(&banded, "constant:0.5,0.5,0.5", &["--guard-band", "16"]);
    let with_band = image::open(&banded).unwrap().to_rgb8();
    assert_eq!(with_band.dimensions(), (192, 108));
    let band_surface = surface(&with_band);
    let nb = band_surface.len();
    assert!(
        nb.abs_diff(n) * 100 <= n && (184..=192).contains(&band_surface[nb / 2]),
        "with a band: {nb} surface pixels (without: {n}), median {}",
        band_surface[nb / 2]
    );
    // The same sky as an equirectangular Radiance map: the same image.
    let map = d.join("grey.hdr");
    image::Rgb32FImage::from_pixel(128, 64, image::Rgb([0.5, 0.5, 0.5]))
        .save(&map)
        .unwrap();
    let from_map = d.join("from-map.png");
    ssdo(&from_map, s(&map), &[]);
    let twin = image::open(&from_map).unwrap().to_rgb8();
    let most = img
        .pixels()
        .zip(twin.pixels())
        .map(|(a, b)| a[1].abs_diff(b[1]))
        .max()
        .unwrap();
    assert!(
        most <= 1,
        "a constant map differs from the constant sky by {most}"
    );
    // A gradient sky to linear EXR: brighter facing up than facing sideways.
    let out = obscura(&[
        "render",
        "--width",
        "96",
        "--height",
        "54",
        "--runs",
        "1",
        "--out",
        s(&ao),
        "--ssdo",
        s(&exr),
        "--env",
        "gradient:1,1,1:0,0,0",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let f = image::open(&exr).unwrap().to_rgb32f();
    assert_eq!(f.dimensions(), (96, 54));
    assert!(f
        .pixels()
        .all(|p| p.0.iter().all(|v| v.is_finite() && *v >= 0.0)));
    // The floor (bottom centre) faces up: 1/2 + 1/2 · ⅔ ≈ 0.83 where open.
    let floor = f.get_pixel(60, 50).0[0];
    assert!((0.6..0.95).contains(&floor), "floor {floor}");
    std::fs::remove_dir_all(d).unwrap();
}

#[test]
fn ssdo_rejects_bad_input() {
    let d = scratch("ssdo-bad");
    let ao = d.join("ao.png");
    let bad_map = d.join("sky.hdr");
    std::fs::write(&bad_map, b"not an image").unwrap();
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec!["--ssdo".into(), s(&d.join("x.jpg")).into()],
            "writes .png or .exr",
        ),
        (
            vec![
                "--ssdo".into(),
                s(&d.join("x.png")).into(),
                "--env".into(),
                "purple".into(),
            ],
            "equirectangular",
        ),
        (
            vec![
                "--ssdo".into(),
                s(&d.join("x.png")).into(),
                "--env".into(),
                s(&bad_map).into(),
            ],
            "cannot read the environment map",
        ),
        (
            vec![
                "--ssdo".into(),
                s(&d.join("x.png")).into(),
                "--env".into(),
                "constant:1,nan,1".into(),
            ],
            "finite",
        ),
        (
            vec![
                "--ssdo".into(),
                s(&d.join("x.png")).into(),
                "--resolution".into(),
                "half".into(),
            ],
            "--resolution full",
        ),
    ];
    for (extra, want) in cases {
        let mut args = vec!["render", "--width", "64", "--height", "48", "--out", s(&ao)];
        args.extend(extra.iter().map(String::as_str));
        let out = obscura(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(err.contains(want), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(!d.join("x.png").exists() && !d.join("x.jpg").exists());
        assert!(!ao.exists(), "{args:?} wrote the AO before refusing");
    }
    let out = obscura(&["eval", "--ssdo", "--view", "cornell", "--albedo-scale", "2"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("--albedo-scale"),
        "{err}"
    );
    std::fs::remove_dir_all(d).unwrap();
}

/// On the Cornell box (red and green walls) SSDO with its bounce is closer to the ray
/// tracer extended to the same sky and one bounce than AO multiplied onto the sky's light.
#[test]
fn eval_ssdo_beats_ao_times_the_environment_on_the_cornell_box() {
    let d = scratch("eval-ssdo");
    let (report, cache) = (d.join("report"), d.join("cache"));
    let out = eval_cornell(
        &[
            "--ssdo",
            "--modes",
            "randomized",
            "--width",
            "160",
            "--height",
            "100",
            "--rays",
            "256",
            "--runs",
            "1",
        ],
        &report,
        None,
        &cache,
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let md = std::fs::read_to_string(report.join("index.md")).unwrap();
    let rmse = |variant: &str| -> f64 {
        md.lines()
            .find(|l| {
                l.starts_with("| cornell |") && l.split('|').nth(3).map(str::trim) == Some(variant)
            })
            .and_then(|l| l.split('|').nth(4))
            .and_then(|c| c.trim().parse().ok())
            .unwrap_or_else(|| panic!("no {variant} row in {md}"))
    };
    let (ao, bounce) = (
        rmse("AO × E(n)"),
        rmse("SSDO + bounce, 2 slices, 2×2 interleaved + merge"),
    );
    assert!(bounce > 0.0 && bounce < 0.2, "{md}");
    assert!(bounce < ao, "SSDO + bounce {bounce} against AO × E(n) {ao}");
    assert!(report.join("cornell-truth.png").exists());
    std::fs::remove_dir_all(d).unwrap();
}
