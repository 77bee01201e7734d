//! `obscura render --depth`: depth maps in float and 16-bit formats, outliers, radii that
//! cannot be derived, real depth maps and bad ones.

use super::*;

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
