//! `obscura render`: the images it writes, presets, MSAA depth, a guard band, a second
//! layer, bent normals; bad input and output paths; the help text.

use super::*;

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
/// 3 × 6 steps at march exponent 1.3 where the lattice is at most 2 pixels (the default
/// 2×2 at full resolution), 4 × 4 even steps at half resolution in the 2×2 layout; counts
/// given by hand march evenly unless --march-exponent is given.
#[test]
fn render_takes_the_presets_samples_for_its_layout_and_resolution() {
    let d = scratch("preset-samples");
    let ao = d.join("ao.png");
    for (extra, want) in [
        (
            &[][..],
            "3 directions x 6 steps (36 samples/pixel), march exponent 1.3, deinterleaved2",
        ),
        (
            &["--resolution", "half"][..],
            "4 directions x 4 steps (32 samples/pixel), deinterleaved2",
        ),
        (
            &["--mode", "randomized", "--resolution", "half"][..],
            "3 directions x 6 steps (36 samples/pixel), march exponent 1.3, randomized",
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
