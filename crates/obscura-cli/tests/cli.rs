//! The `obscura` executable end to end: a small render, and bad input that must end in a
//! clear message, a non-zero exit, no panic and no output file.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn obscura(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_obscura"))
        .args(args)
        .output()
        .expect("the obscura binary runs")
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("obscura-cli-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn render_writes_ao_depth_and_normal_images() {
    let d = scratch("ok");
    let (ao, depth, normals) = (d.join("ao.png"), d.join("depth.png"), d.join("n.png"));
    let out = obscura(&[
        "render",
        "--width",
        "192",
        "--height",
        "108",
        "--runs",
        "1",
        "--out",
        s(&ao),
        "--depth-out",
        s(&depth),
        "--normals-out",
        s(&normals),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("adapter:") && err.contains("median"),
        "progress and timing on stderr: {err}"
    );
    let img = image::open(&ao).unwrap().to_luma8();
    assert_eq!(img.dimensions(), (192, 108));
    let (lo, hi) = img
        .pixels()
        .fold((255u8, 0u8), |(lo, hi), p| (lo.min(p[0]), hi.max(p[0])));
    assert!(
        hi == 255 && lo < 200,
        "AO image should range from occluded to open: {lo}..{hi}"
    );
    assert_eq!(
        image::open(&normals).unwrap().to_rgb8().dimensions(),
        (192, 108)
    );
    assert_eq!(
        image::open(&depth).unwrap().to_luma8().dimensions(),
        (192, 108)
    );
    let leftovers: Vec<_> = std::fs::read_dir(&d)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .to_string_lossy()
                .contains(".tmp-")
        })
        .collect();
    assert!(leftovers.is_empty());
    std::fs::remove_dir_all(d).unwrap();
}

/// The High preset's samples follow the layout and resolution (`AoOptions::with_preset`):
/// 3 × 5 steps at march exponent 1.3 where the lattice is at most 2 pixels (the default
/// 2×2 at full resolution), 4 × 4 even steps at half resolution in the 2×2 layout; counts
/// given by hand march evenly unless --march-exponent is given.
#[test]
fn render_takes_the_presets_samples_for_its_layout_and_resolution() {
    let d = scratch("preset-samples");
    let ao = d.join("ao.png");
    for (extra, want) in [
        (
            &[][..],
            "3 directions x 5 steps (30 samples/pixel), march exponent 1.3, deinterleaved2",
        ),
        (
            &["--resolution", "half"][..],
            "4 directions x 4 steps (32 samples/pixel), deinterleaved2",
        ),
        (
            &["--mode", "randomized", "--resolution", "half"][..],
            "3 directions x 5 steps (30 samples/pixel), march exponent 1.3, randomized",
        ),
        (
            &["--steps", "7"][..],
            "3 directions x 7 steps (42 samples/pixel), deinterleaved2",
        ),
        (
            &["--steps", "7", "--march-exponent", "1.5"][..],
            "3 directions x 7 steps (42 samples/pixel), march exponent 1.5",
        ),
        (
            &["--estimator", "hbao"][..],
            "hbao 8 directions x 4 steps (32 samples/pixel), deinterleaved2",
        ),
    ] {
        let mut args = vec![
            "render",
            "--width",
            "64",
            "--height",
            "40",
            "--runs",
            "1",
            "--out",
            s(&ao),
        ];
        args.extend_from_slice(extra);
        let out = obscura(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{extra:?}: {err}");
        assert!(err.contains(want), "{extra:?}: want `{want}` in {err}");
    }
    std::fs::remove_dir_all(d).unwrap();
}

/// Runs `args` (with `--out DIR/ao.png` appended) and checks the failure contract.
/// `render --msaa`: the scene's depth rasterized with 4× MSAA and resolved by obscura gives
/// the same AO as the single-sampled render away from silhouettes (mean |difference| below
/// 0.01 over the picture, which is mostly interior), and `--orbit` refuses it.
#[test]
fn render_msaa_resolves_multisampled_depth() {
    let d = scratch("msaa");
    let (single, msaa) = (d.join("single.npy"), d.join("msaa.npy"));
    let size = [
        "--width",
        "160",
        "--height",
        "90",
        "--runs",
        "1",
        "--normals",
        "reconstruct",
    ];
    for (path, extra) in [(&single, None), (&msaa, Some("--msaa"))] {
        let mut args = vec!["render"];
        args.extend(size);
        args.extend(["--out", s(path)]);
        args.extend(extra);
        let out = obscura(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{err}");
        if extra.is_some() {
            assert!(
                err.contains("4x MSAA"),
                "stderr names the MSAA input: {err}"
            );
        }
    }
    let (a, b) = (read_npy_f32(&single, 90, 160), read_npy_f32(&msaa, 90, 160));
    assert_eq!(a.len(), 160 * 90);
    let mean = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).sum::<f32>() / a.len() as f32;
    // 0.015: measured 0.0082 with every sample on the layers' 2-pixel lattice and 0.0116
    // with the near field at full resolution, whose nearest samples read the silhouettes'
    // resolved depths pixel by pixel.
    assert!(mean < 0.015, "mean |single − MSAA| = {mean}");
    assert!(
        a.iter().zip(&b).any(|(x, y)| x != y),
        "the MSAA path ran (silhouettes differ)"
    );
    assert_fails(
        "msaa-orbit",
        &["render", "--msaa", "--orbit", "10", "--out-dir", s(&d)],
        "--msaa renders a still camera",
    );
}

/// `render --guard-band 24`, with single-sampled and with 4x MSAA depth: the scene
/// rasterized 24 px beyond each side, the AO of the image's own size; the band darkens the
/// image's edges (the band's occluders), where the mean difference is larger than in the
/// middle.
#[test]
fn render_guard_band_keeps_the_size_and_darkens_the_edges() {
    let d = scratch("guard");
    // Single-sampled, and 4x MSAA depth that obscura resolves.
    for msaa in [false, true] {
        let (plain, banded) = (d.join("plain.npy"), d.join("banded.npy"));
        for (path, band) in [(&plain, "0"), (&banded, "24")] {
            let mut args = vec![
                "render",
                "--width",
                "160",
                "--height",
                "90",
                "--runs",
                "1",
                // The randomized layout's 4×4 patterns repeat every 4 pixels, so a 24 px band
                // leaves them where they were under the view (the 2×2 layout's per-pixel
                // turn follows the AO grid, which the band moves).
                "--mode",
                "randomized",
                "--guard-band",
                band,
                "--out",
                s(path),
            ];
            if msaa {
                args.push("--msaa");
            }
            let out = obscura(&args);
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(out.status.success(), "{err}");
            if band != "0" {
                let said = if msaa {
                    "4x MSAA (obscura resolves it; normals reconstructed), and a guard band of 24 px"
                } else {
                    "guard band of 24 px (208x138 rasterized)"
                };
                assert!(err.contains(said), "{err}");
            }
        }
        let (a, b) = (
            read_npy_f32(&plain, 90, 160),
            read_npy_f32(&banded, 90, 160),
        );
        assert_eq!((a.len(), b.len()), (160 * 90, 160 * 90));
        let mean_diff = |inside: &dyn Fn(usize, usize) -> bool| {
            let (mut sum, mut n) = (0.0, 0);
            for y in 0..90 {
                for x in 0..160 {
                    if inside(x, y) {
                        sum += (a[y * 160 + x] - b[y * 160 + x]).abs();
                        n += 1;
                    }
                }
            }
            sum / n as f32
        };
        let edge = mean_diff(&|x, y| x < 4 || y < 4 || x >= 156 || y >= 86);
        let middle = mean_diff(&|x, y| (40..120).contains(&x) && (25..65).contains(&y));
        assert!(
            edge > 2.0 * middle && edge > 1e-3,
            "msaa {msaa}: edge {edge}, middle {middle}"
        );
    }
}

/// `render --estimator bitmask --second-layer`: a second layer peeled behind the first
/// only adds occluders, so the AO never rises (1e-5) and falls somewhere by more than 0.02;
/// the peel is reported. Without the bitmask the options are refused before any output.
#[test]
fn render_second_layer_only_darkens() {
    let d = scratch("second");
    let (one, two) = (d.join("one.npy"), d.join("two.npy"));
    for (path, second) in [(&one, false), (&two, true)] {
        let mut args = vec![
            "render",
            "--width",
            "160",
            "--height",
            "90",
            "--runs",
            "1",
            "--estimator",
            "bitmask",
            "--denoise",
            "none",
            "--out",
            s(path),
        ];
        if second {
            args.push("--second-layer");
        }
        let out = obscura(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{err}");
        assert_eq!(err.contains("second layer: peeled"), second, "{err}");
    }
    let (a, b) = (read_npy_f32(&one, 90, 160), read_npy_f32(&two, 90, 160));
    let rises = a.iter().zip(&b).filter(|(a, b)| **b > **a + 1e-5).count();
    let most = a.iter().zip(&b).map(|(a, b)| a - b).fold(0.0, f32::max);
    assert!(
        rises == 0 && most > 0.02,
        "{rises} pixels rise; largest fall {most}"
    );
    let refused = d.join("refused.png");
    let out = obscura(&["render", "--second-layer", "--out", s(&refused)]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("second_layer") && !err.contains("panicked"),
        "{err}"
    );
    assert!(!refused.exists());
    assert_fails(
        "second-msaa",
        &["render", "--second-layer", "--msaa"],
        "cannot be used with",
    );
    std::fs::remove_dir_all(d).unwrap();
}

/// Runs `render --orbit 20` of the built-in scene at 96×64 for `frames` frames under
/// `--budget-ms budget` (and `control`, or the default controller), checks that it
/// succeeded and wrote the last frame and the plot, and returns stderr and budget.csv's
/// rows split at the commas (the header skipped).
fn budget_orbit(
    name: &str,
    budget: &str,
    frames: u32,
    control: Option<&str>,
) -> (String, Vec<Vec<String>>) {
    let d = scratch(name);
    let frames_arg = frames.to_string();
    let out_png = d.join("ao.png");
    let mut args = vec![
        "render",
        "--width",
        "96",
        "--height",
        "64",
        "--orbit",
        "20",
        "--frames",
        &frames_arg,
        "--out-dir",
        s(&d),
        "--out",
        s(&out_png),
        "--budget-ms",
        budget,
    ];
    if let Some(c) = control {
        args.extend(["--budget-control", c]);
    }
    let out = obscura(&args);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{err}");
    let last = d.join(format!("frame_{:04}.png", frames - 1));
    assert!(last.exists() && d.join("budget.svg").exists());
    let csv = std::fs::read_to_string(d.join("budget.csv")).unwrap();
    let rows = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    std::fs::remove_dir_all(d).unwrap();
    (err, rows)
}

/// `render --orbit --budget-ms`: with a budget no level can miss, the controller climbs to
/// the top of the ladder once the first level has settled (3 frames); with one no level
/// can meet, it never leaves the cheapest. Each frame is a row of budget.csv, the plot is
/// written, and a bad budget is refused before any work.
#[test]
fn render_orbit_holds_a_budget_by_level() {
    let levels = |budget: &str| -> Vec<String> {
        let (err, rows) = budget_orbit(&format!("budget-{budget}"), budget, 6, Some("ladder"));
        assert!(err.contains("frame    5: level"), "per-frame lines: {err}");
        rows.iter().map(|c| c[2].clone() + " " + &c[3]).collect()
    };
    // The first level is the cheapest one kept: at this size the quarter and half levels
    // cost about the same, and a level that a better one undercuts is skipped.
    let generous = levels("1000000");
    assert_eq!(generous.len(), 6);
    assert!(
        generous[..3].iter().all(|l| *l == generous[0]) && generous[0] != "full ultra",
        "{generous:?}"
    );
    assert!(
        generous[3..].iter().all(|l| l == "full ultra"),
        "{generous:?}"
    );
    let impossible = levels("0.001");
    assert!(
        impossible.iter().all(|l| *l == impossible[0]) && impossible[0] != "full ultra",
        "{impossible:?}"
    );
    let d = scratch("budget-bad");
    assert_fails(
        "budget-negative",
        &[
            "render",
            "--orbit",
            "10",
            "--out-dir",
            s(&d),
            "--budget-ms=-5",
        ],
        "--budget-ms must be",
    );
    assert_fails(
        "budget-nan",
        &[
            "render",
            "--orbit",
            "10",
            "--out-dir",
            s(&d),
            "--budget-ms",
            "NaN",
        ],
        "--budget-ms must be",
    );
    assert_fails(
        "budget-without-orbit",
        &["render", "--budget-ms", "20"],
        "--orbit",
    );
    std::fs::remove_dir_all(d).unwrap();
}

/// `render --orbit --budget-ms` with both knobs (the default, `--budget-control joint`):
/// the scale up to the measured top, then full-resolution sample counts; budget.csv names
/// each frame's resolution, scale and preset.
#[test]
fn render_orbit_holds_a_budget_by_scale_and_samples() {
    // Each frame's (resolution, scale, preset) from budget.csv.
    let knobs = |budget: &str| -> Vec<(String, f32, String)> {
        let (err, rows) = budget_orbit(&format!("budget-joint-{budget}"), budget, 10, None);
        assert!(err.contains("top scale"), "the measured top scale: {err}");
        rows.iter()
            .map(|c| (c[1].clone(), c[2].parse().unwrap(), c[3].clone()))
            .collect()
    };
    // A budget nothing can miss: the scale climbs to its top (one frame), holds it for the
    // three frames that hand over, then the ladder's cheapest rung settles for three frames
    // and the controller goes to the top rung, full ultra. The joint controller is the
    // default.
    let generous = knobs("1000000");
    let scaled = generous.iter().take_while(|k| k.0 == "scaled").count();
    assert!((3..=4).contains(&scaled), "{generous:?}");
    assert!(generous[scaled..]
        .iter()
        .all(|k| k.0 == "full" && k.1 == 1.0));
    assert!(
        generous[scaled + 3..].iter().all(|k| k.2 == "ultra"),
        "{generous:?}"
    );
    assert!(generous[0].2 == "high" && generous[0].1 <= 0.5);
    // One nothing can meet: the smallest scale from the second frame on, never full.
    let impossible = knobs("0.001");
    assert!(
        impossible[1..]
            .iter()
            .all(|k| k.0 == "scaled" && k.1 == 0.25),
        "{impossible:?}"
    );
}

/// `render --orbit --budget-ms --budget-control scale` (the continuous scale alone): from
/// half resolution's scale, a budget every scale meets takes it to 1 after one frame, one
/// no scale can meet to the smallest, 0.25. `--resolution scaled --scale S` renders one
/// frame at scale S; `--scale` with another resolution, or out of range, is refused.
#[test]
fn render_orbit_holds_a_budget_by_scale() {
    let scales = |budget: &str| -> Vec<f32> {
        let (err, rows) = budget_orbit(&format!("budget-scale-{budget}"), budget, 4, Some("scale"));
        assert!(err.contains("frame    3: scale"), "per-frame lines: {err}");
        rows.iter().map(|c| c[1].parse().unwrap()).collect()
    };
    assert_eq!(scales("1000000"), [0.5, 1.0, 1.0, 1.0]);
    assert_eq!(scales("0.001"), [0.5, 0.25, 0.25, 0.25]);
    let d = scratch("scaled-one");
    let out = obscura(&[
        "render",
        "--width",
        "96",
        "--height",
        "64",
        "--resolution",
        "scaled",
        "--scale",
        "0.6",
        "--out",
        s(&d.join("ao.png")),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(d.join("ao.png").exists());
    std::fs::remove_dir_all(d).unwrap();
    assert_fails(
        "scale-without-scaled",
        &["render", "--scale", "0.5"],
        "--scale 0.5 needs --resolution scaled",
    );
    assert_fails(
        "scale-out-of-range",
        &["render", "--resolution", "scaled", "--scale", "0.1"],
        "scale",
    );
}

/// A budget below what the view costs at the cheapest setting is said once, by each
/// controller, and the run goes on (frames are written, exit 0).
#[test]
fn a_budget_that_cannot_be_held_says_so_once() {
    for control in ["joint", "scale", "ladder"] {
        let d = scratch(&format!("floor-{control}"));
        let out = obscura(&[
            "render",
            "--width",
            "160",
            "--height",
            "100",
            "--orbit",
            "20",
            "--frames",
            "6",
            "--out-dir",
            s(&d),
            "--budget-ms",
            "0.01",
            "--budget-control",
            control,
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{control}: {err}");
        assert_eq!(
            err.matches("cannot be held on this view").count(),
            1,
            "{control}: {err}"
        );
        assert!(
            d.join("frame_0005.png").exists(),
            "{control}: the orbit ran on"
        );
        std::fs::remove_dir_all(d).unwrap();
    }
}

fn assert_fails(name: &str, args: &[&str], message: &str) {
    let d = scratch(name);
    let ao = d.join("ao.png");
    let mut all: Vec<&str> = args.to_vec();
    all.extend(["--out", s(&ao)]);
    let out = obscura(&all);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{name}: should fail");
    assert!(!err.contains("panicked"), "{name}: panicked: {err}");
    assert!(
        err.to_lowercase().contains(&message.to_lowercase()),
        "{name}: expected `{message}` in: {err}"
    );
    assert!(!ao.exists(), "{name}: left an output file");
    let n = std::fs::read_dir(&d).unwrap().count();
    assert_eq!(n, 0, "{name}: left files behind");
    std::fs::remove_dir_all(d).unwrap();
}

#[test]
fn bad_input_fails_cleanly() {
    let d = scratch("inputs");
    let stl = d.join("model.stl");
    std::fs::write(&stl, b"solid").unwrap();
    let glb = d.join("cut.glb");
    std::fs::write(&glb, b"glTF\x02\x00\x00\x00\xff\xff").unwrap();
    let missing = d.join("missing.glb");
    assert_fails(
        "missing",
        &["render", "--scene", s(&missing)],
        "missing.glb",
    );
    assert_fails(
        "extension",
        &["render", "--scene", s(&stl)],
        "unsupported scene file extension",
    );
    assert_fails("truncated", &["render", "--scene", s(&glb)], "invalid glTF");
    assert_fails("width0", &["render", "--width", "0"], "--width");
    assert_fails("height0", &["render", "--height", "0"], "--height");
    assert_fails(
        "nan-camera",
        &["render", "--camera", "nan,1,5,0,0,0"],
        "finite",
    );
    assert_fails(
        "short-camera",
        &["render", "--camera", "1,2,3"],
        "6 or 7 numbers",
    );
    assert_fails(
        "same-eye-target",
        &["render", "--camera", "1,1,1,1,1,1"],
        "same point",
    );
    assert_fails("radius", &["render", "--radius=-2"], "--radius");
    // --help says 2..=256; 0 was once taken as "no history" with --frames > 1.
    assert_fails(
        "history0",
        &["render", "--frames", "4", "--history", "0"],
        "'0' for '--history <HISTORY>': 0 is not in 2..=256",
    );
    assert_fails("directions", &["render", "--directions", "0"], "directions");
    assert_fails(
        "huge",
        &["render", "--width", "60000", "--height", "8"],
        "exceeds",
    );
    std::fs::remove_dir_all(d).unwrap();
}

#[test]
fn bad_output_path_fails_before_work() {
    let d = scratch("outpath");
    let out = obscura(&["render", "--out", s(&d.join("no/such/dir/ao.png"))]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("does not exist"));
    let out = obscura(&["render", "--out", s(&d.join("ao.jpg"))]);
    assert_eq!(out.status.code(), Some(1), "a .jpg output is refused");
    assert!(String::from_utf8_lossy(&out.stderr).contains(".png"));
    assert!(
        std::fs::read_dir(&d).unwrap().next().is_none(),
        "a refused output leaves no file"
    );
    std::fs::remove_dir_all(d).unwrap();
}

#[test]
fn help_documents_every_option() {
    let out = obscura(&["render", "--help"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for opt in [
        "--scene",
        "--camera",
        "--width",
        "--height",
        "--projection",
        "--radius",
        "--directions",
        "--steps",
        "--out",
        "--depth-out",
        "--normals-out",
    ] {
        assert!(text.contains(opt), "help lacks {opt}");
    }
    assert!(String::from_utf8_lossy(&obscura(&["--help"]).stdout).contains("OBSCURA_ADAPTER"));
}

#[test]
fn bench_writes_table_json_and_plot() {
    let d = scratch("bench");
    let (json, plot) = (d.join("b.json"), d.join("b.svg"));
    let out = obscura(&[
        "bench",
        "--resolutions",
        "64x36,67x45",
        "--radii",
        "4,16",
        "--runs",
        "1",
        "--json",
        s(&json),
        "--plot",
        s(&plot),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("[4/4]"), "progress per cell: {err}");
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(table.contains("| 67×45 | 16 |"), "{table}");
    let j = std::fs::read_to_string(&json).unwrap();
    // 5 variants × 2 resolutions × 2 radii, the randomized pass being the unit of ratio.
    assert_eq!(j.matches("\"variant\"").count(), 20, "{j}");
    assert_eq!(j.matches("\"variant\": \"randomized\"").count(), 4);
    // Each variant's ratio is its own median over the randomized pass's of the same size and
    // radius (to the JSON's four decimals).
    let v: serde_json::Value = serde_json::from_str(&j).unwrap();
    let records: Vec<&serde_json::Value> = v
        .as_array()
        .or_else(|| v["records"].as_array())
        .expect("an array of records")
        .iter()
        .collect();
    let key = |r: &serde_json::Value| {
        (
            r["width"].clone(),
            r["height"].clone(),
            r["radius_px"].clone(),
        )
    };
    for r in &records {
        let base = records
            .iter()
            .find(|b| b["variant"] == "randomized" && key(b) == key(r))
            .expect("a baseline for each size and radius");
        let want = r["median_ms"].as_f64().unwrap() / base["median_ms"].as_f64().unwrap();
        let got = r["ratio_to_baseline"].as_f64().unwrap();
        assert!(
            (got - want).abs() <= 1e-4 + 1e-3 * want,
            "{r}: ratio {got}, medians give {want}"
        );
    }
    let svg = std::fs::read_to_string(&plot).unwrap();
    assert_eq!(svg.matches("<polyline").count(), 10);
    std::fs::remove_dir_all(d).unwrap();
}

#[test]
fn bench_times_a_guard_band_and_a_second_layer() {
    let d = scratch("bench-layers");
    let (json, plot) = (d.join("l.json"), d.join("l.svg"));
    let out = obscura(&[
        "bench",
        "--compare",
        "layers",
        "--estimator",
        "bitmask",
        "--guard-band",
        "8",
        "--resolutions",
        "64x36",
        "--radii",
        "8",
        "--runs",
        "1",
        "--json",
        s(&json),
        "--plot",
        s(&plot),
    ]);
    // obscura refuses a second layer it was not asked for, and asks for one the options
    // want: a variant handed the wrong G-buffer fails the run.
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let v = read_json(&json);
    let names: Vec<&str> = v["records"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["variant"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "one-layer",
            "guard-band",
            "second-layer",
            "second-layer+guard-band"
        ]
    );
    // All four are 2×2 fused: the plot tells them apart by colour, one each.
    let svg = std::fs::read_to_string(&plot).unwrap();
    let mut strokes: Vec<&str> = svg
        .lines()
        .filter(|l| l.starts_with("<polyline"))
        .filter_map(|l| l.split("stroke=\"").nth(1))
        .collect();
    strokes.sort_unstable();
    strokes.dedup();
    assert_eq!(strokes.len(), 4, "{svg}");
    std::fs::remove_dir_all(d).unwrap();
}

#[test]
fn bench_rejects_bad_lists() {
    for args in [
        &["bench", "--radii", "0"][..],
        &["bench", "--radii", "a,b"][..],
        &["bench", "--resolutions", "640"][..],
        &["bench", "--resolutions", "0x10"][..],
        &["bench", "--plot", "/no/such/dir/p.svg"][..],
        &["bench", "--compare", "layers", "--msaa"][..],
        &["bench", "--compare", "layers", "--guard-band", "0"][..],
    ] {
        let out = obscura(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.starts_with("error:") && !err.contains("panicked"),
            "{args:?}: {err}"
        );
    }
}

/// The record of `variant` in `eval --json`'s output `v`.
fn record(v: &serde_json::Value, variant: &str) -> serde_json::Value {
    v["records"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["variant"] == variant)
        .unwrap_or_else(|| panic!("no {variant} in {v}"))
        .clone()
}

/// A JSON file, parsed.
fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// `obscura eval --view cornell` on the shared scenes with `args`, writing its report, its
/// JSON (if given) and its reference cache where it is told.
fn eval_cornell(args: &[&str], report: &Path, json: Option<&Path>, cache: &Path) -> Output {
    let scenes = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/scenes");
    let mut all = vec!["eval", "--view", "cornell", "--scenes-dir", scenes];
    all.extend_from_slice(args);
    all.extend(["--report", s(report), "--cache", s(cache)]);
    if let Some(j) = json {
        all.extend(["--json", s(j)]);
    }
    obscura(&all)
}

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
/// preset, although High's counts differ there (3 × 5 crowded at full resolution in the
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

/// `eval --view VIEW` (shared scenes, one run, 2×2 layers, no pictures) with `args`, its
/// JSON and reference cache in `d`; the run must succeed.
fn eval_view(d: &Path, view: &str, args: &[&str]) -> serde_json::Value {
    eval_view_logged(d, view, args).0
}

/// [`eval_view`] with what eval printed on stderr.
fn eval_view_logged(d: &Path, view: &str, args: &[&str]) -> (serde_json::Value, String) {
    let (json, cache) = (d.join("q.json"), d.join("cache"));
    let scenes = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/scenes");
    let mut all = vec![
        "eval",
        "--view",
        view,
        "--scenes-dir",
        scenes,
        "--runs",
        "1",
    ];
    all.extend(["--modes", "deinterleaved2"]);
    all.extend_from_slice(args);
    all.extend(["--cache", s(&cache), "--json", s(&json)]);
    let out = obscura(&all);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{err}");
    (read_json(&json), err)
}

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

/// The float32 payload of a 2-D C-order `.npy` of shape (h, w), checking its header.
fn read_npy_f32(path: &Path, h: usize, w: usize) -> Vec<f32> {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
    let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let header = std::str::from_utf8(&bytes[10..10 + len]).unwrap();
    assert!(
        header.contains("'<f4'") && header.contains(&format!("({h}, {w})")),
        "{header}"
    );
    assert_eq!((10 + len) % 64, 0, "data aligned to 64 bytes");
    let data = &bytes[10 + len..];
    assert_eq!(data.len(), 4 * w * h);
    data.chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

/// A float32 depth map of a floor 2 m away with a 5 cm step towards the camera (its foot is a crease), a few pixels at
/// 1e30 (a fill value some tools write for "no data far away"): it renders with the
/// default radius (taken from robust bounds, not the outliers), the crease is darker than
/// the open floor, and the depth scale of the intrinsics does not rescale float data.
#[test]
fn float_depth_with_outliers_renders_without_rescaling() {
    let d = scratch("outliers");
    let (w, h) = (96usize, 64usize);
    let mut depth = vec![2.0f32; w * h];
    for y in 0..h {
        for x in 48..w {
            depth[y * w + x] = 1.95;
        }
    }
    for i in [5, 700, 3000] {
        depth[i] = 1e30;
    }
    let header = format!("{{'descr': '<f4', 'fortran_order': False, 'shape': ({h}, {w}), }}\n");
    let mut npy = b"\x93NUMPY\x01\x00".to_vec();
    npy.extend((header.len() as u16).to_le_bytes());
    npy.extend(header.as_bytes());
    npy.extend(depth.iter().flat_map(|v| v.to_le_bytes()));
    let (dpath, kpath, ao) = (d.join("d.npy"), d.join("k.json"), d.join("ao.npy"));
    std::fs::write(&dpath, npy).unwrap();
    std::fs::write(
        &kpath,
        r#"{"fx": 80, "fy": 80, "cx": 47.5, "cy": 31.5, "width": 96, "height": 64, "depth_scale": 0.001}"#,
    )
    .unwrap();
    let out = obscura(&[
        "render",
        "--depth",
        s(&dpath),
        "--intrinsics",
        s(&kpath),
        "--out",
        s(&ao),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("depth 1.950.."),
        "float depth is not rescaled: {err}"
    );
    let v = read_npy_f32(&ao, h, w);
    // Lower side of the step, just before it (the step faces it), against open floor.
    let crease = v[32 * w + 46];
    let open = v[32 * w + 20];
    assert!(crease < open - 0.05, "crease {crease}, open floor {open}");
    std::fs::remove_dir_all(&d).unwrap();
}

/// A depth map whose valid depth spans no extent (one valid pixel) gives no default radius:
/// the error names that cause, not an invalid `radius` = 0 the user never gave.
#[test]
fn an_underivable_radius_names_its_cause() {
    let d = scratch("lone-pixel");
    let mut depth = vec![0.0f32; 16];
    depth[5] = 2.0;
    let (dpath, kpath) = (d.join("d.npy"), d.join("k.json"));
    std::fs::write(&dpath, npy_f32(&[4, 4], &depth)).unwrap();
    std::fs::write(
        &kpath,
        r#"{"fx": 100, "fy": 100, "cx": 1.5, "cy": 1.5, "width": 4, "height": 4}"#,
    )
    .unwrap();
    let args = ["render", "--depth", s(&dpath), "--intrinsics", s(&kpath)];
    assert_fails("lone-pixel-run", &args, "span no extent; give the radius");
    std::fs::remove_dir_all(&d).unwrap();
}

/// A `.npy` of `values` with `shape` (little-endian float32, C order).
fn npy_f32(shape: &[usize], values: &[f32]) -> Vec<u8> {
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let header = format!(
        "{{'descr': '<f4', 'fortran_order': False, 'shape': ({},), }}\n",
        dims.join(", ")
    );
    let mut npy = b"\x93NUMPY\x01\x00".to_vec();
    npy.extend((header.len() as u16).to_le_bytes());
    npy.extend(header.as_bytes());
    npy.extend(values.iter().flat_map(|v| v.to_le_bytes()));
    npy
}

/// The depth-map outputs and given normals: one AO written as float `.npy`, float `.exr`
/// and 16-bit PNG holds the same values (EXR exactly, 16-bit within half a step); normals
/// handed in with `--normals-file` are used (a wall whose normals face the camera reads
/// open, and the same file read with the other axes warns that they face away); a normal
/// map of the wrong size fails cleanly.
#[test]
fn depth_map_writes_float_and_16_bit_ao_and_takes_normals() {
    let d = scratch("outputs");
    let (w, h) = (64usize, 48usize);
    // A wall 2 units away with a 5 cm step towards the camera on its right half.
    let depth: Vec<f32> = (0..w * h)
        .map(|i| if i % w >= 32 { 1.95 } else { 2.0 })
        .collect();
    let (dpath, kpath) = (d.join("d.npy"), d.join("k.json"));
    std::fs::write(&dpath, npy_f32(&[h, w], &depth)).unwrap();
    std::fs::write(
        &kpath,
        r#"{"fx": 60, "fy": 60, "cx": 31.5, "cy": 23.5, "width": 64, "height": 48}"#,
    )
    .unwrap();
    let render = |out: &Path, extra: &[&str]| {
        let mut args = vec![
            "render",
            "--depth",
            s(&dpath),
            "--intrinsics",
            s(&kpath),
            "--runs",
            "1",
            "--radius",
            "0.3",
            "--out",
            s(out),
        ];
        args.extend_from_slice(extra);
        let out = obscura(&args);
        let err = String::from_utf8_lossy(&out.stderr).to_string();
        assert!(out.status.success(), "{err}");
        err
    };
    let (npy, exr, png) = (d.join("ao.npy"), d.join("ao.exr"), d.join("ao.png"));
    render(&npy, &[]);
    render(&exr, &[]);
    render(&png, &["--bits", "16"]);
    let v = read_npy_f32(&npy, h, w);
    assert!(v.iter().any(|&a| a < 0.9), "the step is occluded");
    let e = image::open(&exr).unwrap().to_rgb32f();
    assert_eq!(e.dimensions(), (w as u32, h as u32));
    for (a, p) in v.iter().zip(e.pixels()) {
        assert!(
            (a - p[0]).abs() < 1e-6 && p[0] == p[1] && p[1] == p[2],
            "{a} vs {p:?}"
        );
    }
    let img = image::open(&png).unwrap();
    assert!(
        matches!(img, image::DynamicImage::ImageLuma16(_)),
        "{:?}",
        img.color()
    );
    for (a, p) in v.iter().zip(img.to_luma16().pixels()) {
        assert!(
            (a.clamp(0.0, 1.0) * 65535.0 - p[0] as f32).abs() <= 0.5 + 1e-3,
            "{a} vs {}",
            p[0]
        );
    }

    // Normals facing the camera in OpenCV axes (z into the scene): (0, 0, −1).
    let npath = d.join("n.npy");
    let normals: Vec<f32> = (0..w * h).flat_map(|_| [0.0, 0.0, -1.0]).collect();
    std::fs::write(&npath, npy_f32(&[h, w, 3], &normals)).unwrap();
    let given = d.join("given.npy");
    let err = render(&given, &["--normals-file", s(&npath)]);
    assert!(
        err.contains("normals:") && !err.contains("face away"),
        "{err}"
    );
    let g = read_npy_f32(&given, h, w);
    let open = g[24 * w + 10];
    assert!(open > 0.97, "open wall with given normals: {open}");
    let err = render(
        &given,
        &["--normals-file", s(&npath), "--normals-frame", "opengl"],
    );
    assert!(err.contains("face away"), "{err}");
    let small = d.join("small.npy");
    std::fs::write(
        &small,
        npy_f32(&[h / 2, w, 3], &normals[..normals.len() / 2]),
    )
    .unwrap();
    let (dp, kp, sp) = (
        s(&dpath).to_string(),
        s(&kpath).to_string(),
        s(&small).to_string(),
    );
    assert_fails(
        "normals-size",
        &[
            "render",
            "--depth",
            &dp,
            "--intrinsics",
            &kp,
            "--normals-file",
            &sp,
        ],
        "the normals are 64x24 but the depth map is 64x48",
    );
    assert_fails(
        "bits",
        &[
            "render",
            "--depth",
            &dp,
            "--intrinsics",
            &kp,
            "--bits",
            "12",
        ],
        "expected 8 or 16",
    );
    // The library's one rule for normals and intrinsics, as the Python package applies it:
    // normals of which none is a vector, and a focal length no pinhole has.
    let nan = d.join("nan.npy");
    std::fs::write(&nan, npy_f32(&[h, w, 3], &vec![f32::NAN; w * h * 3])).unwrap();
    let nan = s(&nan).to_string();
    assert_fails(
        "normals-nan",
        &[
            "render",
            "--depth",
            &dp,
            "--intrinsics",
            &kp,
            "--normals-file",
            &nan,
        ],
        "not one is a finite, non-zero vector",
    );
    let absurd = d.join("absurd.json");
    std::fs::write(
        &absurd,
        r#"{"fx": 1e30, "fy": 60, "cx": 31.5, "cy": 23.5, "width": 64, "height": 48}"#,
    )
    .unwrap();
    let absurd = s(&absurd).to_string();
    assert_fails(
        "fx-absurd",
        &["render", "--depth", &dp, "--intrinsics", &absurd],
        "field of view",
    );
    std::fs::remove_dir_all(&d).unwrap();
}

/// The shared real depth maps render with their intrinsics (the Middlebury motorcycle:
/// the motorcycle is darker in its creases than the open floor), and bad depth input
/// fails cleanly.
#[test]
fn real_depth_maps_render_and_bad_ones_fail() {
    let shared = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/depth");
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/intrinsics");
    let d = scratch("depthmap");
    let ao = d.join("ao.png");
    let moto = format!("{shared}/middlebury2014_motorcycle/depth_mm.png");
    let moto_k = format!("{data}/middlebury2014_motorcycle.json");
    let out = obscura(&[
        "render",
        "--depth",
        &moto,
        "--intrinsics",
        &moto_k,
        "--out",
        s(&ao),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let img = image::open(&ao).unwrap().to_luma8();
    assert_eq!(img.dimensions(), (741, 500));
    let dark = img.pixels().filter(|p| p[0] < 160).count();
    assert!(
        dark > 1000 && dark < 741 * 500 / 2,
        "{dark} occluded pixels"
    );
    // The same AO as float32 .npy (1 = unoccluded), the PNG's values before 8-bit rounding;
    // --runs is honoured on the depth-map path as on the scene path.
    let ao_npy = d.join("ao.npy");
    let out = obscura(&[
        "render",
        "--depth",
        &moto,
        "--intrinsics",
        &moto_k,
        "--runs",
        "2",
        "--out",
        s(&ao_npy),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("median") && err.contains("over 2 runs"),
        "{err}"
    );
    let floats = read_npy_f32(&ao_npy, 500, 741);
    for (f, p) in floats.iter().zip(img.pixels()) {
        assert!((0.0..=1.0).contains(f), "{f}");
        assert!(
            (f * 255.0 - p[0] as f32).abs() <= 0.5 + 1e-3,
            "{f} vs {}",
            p[0]
        );
    }
    let redwood = format!("{shared}/redwood/redwood_depth_mm.png");
    let intrinsics = format!("{data}/redwood.json");
    let render_redwood = |extra: &[&str], out: &Path| {
        let mut args = vec![
            "render",
            "--depth",
            &redwood,
            "--intrinsics",
            &intrinsics,
            "--resolution",
            "half",
            "--out",
            s(out),
        ];
        args.extend_from_slice(extra);
        obscura(&args)
    };
    let out = render_redwood(&["--depth-noise", "none"], &ao);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let plain = image::open(&ao).unwrap().to_luma8();
    assert_eq!(plain.dimensions(), (640, 480));
    // Redwood's sensor noise read as occlusion darkens the walls; with the noise model
    // estimated from the map (the default) it reads brighter (mostly open walls and floor).
    let ao_k = d.join("ao_estimated.png");
    let out = render_redwood(&[], &ao_k);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success() && err.contains("depth noise σ") && err.contains("estimated"),
        "{err}"
    );
    let mean = |img: &image::GrayImage| {
        img.pixels().map(|p| p[0] as f64).sum::<f64>() / (255.0 * img.pixels().len() as f64)
    };
    let (m0, m1) = (mean(&plain), mean(&image::open(&ao_k).unwrap().to_luma8()));
    assert!(
        m1 > m0 + 0.03,
        "mean AO {m0} without the noise model, {m1} with it"
    );
    std::fs::remove_dir_all(&d).unwrap();

    let bad = scratch("depthmap-bad");
    let json = bad.join("k.json");
    std::fs::write(
        &json,
        r#"{"fx": 500, "fy": 500, "cx": 10, "cy": 10, "width": 20, "height": 20}"#,
    )
    .unwrap();
    let npy = bad.join("d.npy");
    std::fs::write(&npy, b"\x93NUMPY\x01\x00\x10\x00{'descr': '<f4'").unwrap();
    let txt = bad.join("d.txt");
    std::fs::write(&txt, b"1 2 3").unwrap();
    let (json_s, npy_s, txt_s) = (
        s(&json).to_string(),
        s(&npy).to_string(),
        s(&txt).to_string(),
    );
    assert_fails(
        "depth-size",
        &["render", "--depth", &moto, "--intrinsics", &json_s],
        "intrinsics say",
    );
    assert_fails(
        "depth-npy",
        &["render", "--depth", &npy_s, "--intrinsics", &json_s],
        "npy",
    );
    assert_fails(
        "depth-ext",
        &["render", "--depth", &txt_s, "--intrinsics", &json_s],
        "unsupported",
    );
    assert_fails("depth-no-k", &["render", "--depth", &moto], "--intrinsics");
    let moto_args = |noise: &'static str| {
        vec![
            "render".to_string(),
            "--depth".into(),
            moto.clone(),
            "--intrinsics".into(),
            moto_k.clone(),
            "--depth-noise".into(),
            noise.into(),
        ]
    };
    for (name, noise, says) in [
        ("noise-count", "1,2", "3 numbers"),
        ("noise-negative", "-1,0,0", "depth_noise.constant"),
        ("noise-word", "loud", "expected auto, none, kinect"),
    ] {
        let args = moto_args(noise);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        assert_fails(name, &args, says);
    }
    assert_fails(
        "depth-bad-k",
        &["render", "--depth", &moto, "--intrinsics", &npy_s],
        "intrinsics",
    );
    std::fs::remove_dir_all(bad).unwrap();
}

/// The largest size the adapter's limits allow (16384 x 16384 on lavapipe) needs more
/// memory than the driver gives: a typed out-of-memory message and no file (where a
/// machine has the memory, a complete image instead), never a crash or a partial file.
#[test]
fn the_largest_size_fails_cleanly_or_succeeds() {
    let d = scratch("largest");
    let out_png = d.join("ao.png");
    let out = obscura(&[
        "render",
        "--width",
        "16384",
        "--height",
        "16384",
        "--runs",
        "1",
        "--out",
        s(&out_png),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    if out.status.success() {
        let img = image::open(&out_png).unwrap().to_luma8();
        assert_eq!(img.dimensions(), (16384, 16384));
    } else {
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert!(
            err.contains("out of memory") || err.contains("exceeds"),
            "{err}"
        );
        assert!(!out_png.exists(), "a failed run left {}", out_png.display());
        assert!(
            std::fs::read_dir(&d).unwrap().next().is_none(),
            "no partial files"
        );
    }
    std::fs::remove_dir_all(d).unwrap();
}

/// `--bent-normals-out`: from a depth map (a wall 2 units away with a 5 cm step towards the
/// camera on its right half) a float `.npy` of shape (h, w, 3) cropped to the map, unit
/// vectors; on the open wall they face the camera (+z), at the foot of the step they lean
/// away from it (−x); a PNG of the built-in scene; and the traps: another estimator, an
/// unknown extension, an orbit.
#[test]
fn bent_normals_are_written_as_float_and_png() {
    let d = scratch("bent");
    let (w, h) = (64usize, 48usize);
    let depth: Vec<f32> = (0..w * h)
        .map(|i| if i % w >= 32 { 1.95 } else { 2.0 })
        .collect();
    let (dpath, kpath, bent) = (d.join("d.npy"), d.join("k.json"), d.join("bent.npy"));
    std::fs::write(&dpath, npy_f32(&[h, w], &depth)).unwrap();
    std::fs::write(
        &kpath,
        r#"{"fx": 60, "fy": 60, "cx": 31.5, "cy": 23.5, "width": 64, "height": 48}"#,
    )
    .unwrap();
    let ao = d.join("ao.png");
    // `render` with `args`, the AO to `ao` and the bent normals to `to`; must succeed.
    let render = |args: &[&str], to: &Path| {
        let mut all = vec!["render", "--out", s(&ao), "--bent-normals-out", s(to)];
        all.extend(args);
        let out = obscura(&all);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{all:?}: {err}");
    };
    let depth_map = ["--depth", s(&dpath), "--intrinsics", s(&kpath)];
    render(&[&depth_map[..], &["--radius", "0.2"]].concat(), &bent);
    let bytes = std::fs::read(&bent).unwrap();
    let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let header = std::str::from_utf8(&bytes[10..10 + len]).unwrap();
    assert!(header.contains(&format!("({h}, {w}, 3)")), "{header}");
    let v: Vec<f32> = bytes[10 + len..]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    assert_eq!(v.len(), w * h * 3);
    let at = |x: usize, y: usize| {
        let i = 3 * (y * w + x);
        [v[i], v[i + 1], v[i + 2]]
    };
    for b in v.chunks_exact(3) {
        let n = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt();
        assert!((n - 1.0).abs() < 1e-3, "|bent| = {n}");
    }
    let (open, foot) = (at(10, 24), at(30, 24));
    assert!(open[2] > 0.99, "open wall: {open:?}");
    assert!(foot[0] < -0.05, "foot of the step: {foot:?}");
    let png = d.join("bent.png");
    render(&["--width", "96", "--height", "64", "--runs", "1"], &png);
    let img = image::open(&png).unwrap();
    assert_eq!((img.width(), img.height()), (96, 64));
    assert!(matches!(img, image::DynamicImage::ImageRgb8(_)));
    std::fs::remove_dir_all(&d).unwrap();
    // Checked before any work; nothing is written (assert_fails checks its own folder).
    let tmp = std::env::temp_dir();
    let (png, txt) = (
        tmp.join("obscura-bent-trap.png"),
        tmp.join("obscura-bent-trap.txt"),
    );
    for (args, msg) in [
        (
            vec!["render", "--estimator", "vo", "--bent-normals-out", s(&png)],
            "needs --estimator gtao, hbao or bitmask",
        ),
        (
            vec!["render", "--bent-normals-out", s(&txt)],
            "must end in .png",
        ),
        (
            vec![
                "render",
                "--orbit",
                "10",
                "--frames",
                "2",
                "--out-dir",
                s(&tmp),
                "--bent-normals-out",
                s(&png),
            ],
            "--orbit",
        ),
    ] {
        assert_fails("bent-traps", &args, msg);
        assert!(!png.exists() && !txt.exists());
    }
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

/// The error column of the table row whose variant is `variant` (a float), if any.
fn table_error(table: &str, variant: &str) -> Option<f64> {
    table
        .lines()
        .find(|l| l.split('|').nth(2).map(str::trim) == Some(variant))
        .and_then(|l| l.split('|').nth(5))
        .and_then(|c| c.trim().parse().ok())
}

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
