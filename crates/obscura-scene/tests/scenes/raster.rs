//! The raster and what obscura reads from it: orthographic cameras, guard bands, the peeled
//! second layer, the layouts and estimators against each other and their screen-space
//! references.

use super::*;

/// An orthographic camera rasterizes where obscura's projection says: a plane tilted in
/// both axes, seen obliquely, has every covered pixel's depth, unprojected through
/// `Camera::obscura_projection` (pixel centre to NDC, times the half extents, at the
/// linearized depth) and the inverse view, on the plane within 1e-3 of the view's height
/// (Depth32Float reversed-Z keeps about 2⁻²⁴ of the depth range; a half extent wrong by
/// 1% moves points off the plane by about 0.01 of it). And the default scene renders with
/// occlusion.
#[test]
fn orthographic_camera_renders_and_matches_obscura_projection() {
    let _g = lock();
    let (w, h, height) = (96u32, 64u32, 6.0f32);
    let on_plane = |x: f32, z: f32| [x, 0.3 * x + 0.2 * z, z];
    let mut mesh = Mesh::default();
    let corners = [(-20.0, -20.0), (20.0, -20.0), (20.0, 20.0), (-20.0, 20.0)];
    mesh.append(
        glam::Mat4::IDENTITY,
        &corners.map(|(x, z)| on_plane(x, z)),
        &[0, 2, 1, 0, 3, 2],
    );
    let cam = Camera {
        eye: glam::Vec3::new(3.0, 8.0, 6.0),
        target: glam::Vec3::ZERO,
        up: glam::Vec3::Y,
        projection: CameraProjection::Orthographic { height },
        near: 0.1,
        far: 100.0,
    };
    let (depth, _) = render(&mesh, &cam, w, h, 1.0);
    let projection = cam.obscura_projection(w as f32 / h as f32);
    let lin = projection.linearize(DEPTH_CONVENTION).unwrap();
    let [sx, sy] = projection.ndc_to_view_scale();
    let world_from_view = cam.view_matrix().inverse();
    let mut covered = 0;
    for y in 0..h {
        for x in 0..w {
            let Some(d) = lin.apply(depth[(y * w + x) as usize]) else {
                continue;
            };
            let ndc = (
                2.0 * (x as f32 + 0.5) / w as f32 - 1.0,
                1.0 - 2.0 * (y as f32 + 0.5) / h as f32,
            );
            let p = world_from_view.transform_point3(glam::Vec3::new(ndc.0 * sx, ndc.1 * sy, -d));
            let off = p.y - (0.3 * p.x + 0.2 * p.z);
            assert!(
                off.abs() < 1e-3 * height,
                "pixel ({x}, {y}): {p} lies {off} off the plane"
            );
            covered += 1;
        }
    }
    assert_eq!(covered, w * h, "the plane fills the view");
    let mut scene_cam = default_scene::camera();
    scene_cam.projection = CameraProjection::Orthographic { height: 12.0 };
    let (_, ao) = render(&default_scene::mesh(), &scene_cam, 192, 128, 1.0);
    assert!(ao.iter().any(|&a| a < 0.8));
}

/// A G-buffer rendered with a guard band holds the plain render's depth in its middle:
/// the widened camera keeps the pixel size and centres (a wrong field of view shifts every
/// pixel; a band grown by 1.9 g instead of 2 g fails on 80% of them). Pixels whose centre
/// lies on a triangle edge may flip with rounding: at most 0.5% of them may differ by more
/// than 1e-5 of their linear depth (reversed-Z Depth32Float keeps about 2⁻²⁴ of it; the
/// standard convention, near = far / 10⁴, differed by 1e-5 between the two projection
/// matrices). Its AO input is the view inside the band.
#[test]
fn guard_band_render_holds_the_plain_view_in_its_middle() {
    let _g = lock();
    let c = ctx();
    let mesh = default_scene::mesh();
    let raster = GBufferRenderer::new(&c.device);
    let gm = raster.upload(c, &mesh).unwrap();
    let (w, h, g) = (160u32, 90u32, 24u32);
    let mut ortho = default_scene::camera();
    ortho.projection = CameraProjection::Orthographic { height: 12.0 };
    for cam in [default_scene::camera(), ortho] {
        let plain = c
            .read_f32(&raster.render(c, &gm, &cam, w, h).unwrap().depth)
            .unwrap();
        let banded = raster.render_guarded(c, &gm, &cam, (w, h), g).unwrap();
        assert_eq!((banded.width, banded.height), (w + 2 * g, h + 2 * g));
        let input = banded.ao_input(&cam, false);
        assert_eq!(input.guard_band, g);
        assert_eq!(
            input.projection,
            cam.obscura_projection(w as f32 / h as f32)
        );
        let depth = c.read_f32(&banded.depth).unwrap();
        let lin = input.projection.linearize(DEPTH_CONVENTION).unwrap();
        let bw = (w + 2 * g) as usize;
        let off = (0..h as usize)
            .flat_map(|y| (0..w as usize).map(move |x| (x, y)))
            .filter(|&(x, y)| {
                let a = lin.apply(plain[y * w as usize + x]);
                let b = lin.apply(depth[(y + g as usize) * bw + x + g as usize]);
                match (a, b) {
                    (Some(a), Some(b)) => (a - b).abs() > 1e-5 * a,
                    (a, b) => a.is_some() != b.is_some(),
                }
            })
            .count();
        assert!(
            off * 200 <= (w * h) as usize,
            "{:?}: {off} of {} pixels differ",
            cam.projection,
            w * h
        );
    }
}

/// The depth peel on stacked quads seen orthographically from z = 10: front faces at
/// linear depths 5 (everywhere), 6 (left half) and 7 (everywhere), and a back face at 5.5
/// (wound the other way). The second layer is the nearest front face at least the
/// separation behind the first: 6 on the left and 7 on the right with separation 0.5 (never
/// the back face), 7 with 1.5, none with 2.5 (tolerance 1e-4 of the depth; the two columns
/// beside the middle are skipped). A guard band peels the same layer around the view, and
/// a separation that is not positive is refused.
#[test]
fn peel_finds_the_nearest_front_face_behind_the_separation() {
    let _g = lock();
    let c = ctx();
    let mut mesh = Mesh::default();
    let quad = |z: f32| {
        [
            [-9.0, -9.0, z],
            [9.0, -9.0, z],
            [9.0, 9.0, z],
            [-9.0, 9.0, z],
        ]
    };
    let front = [0, 1, 2, 0, 2, 3];
    let back = [0, 2, 1, 0, 3, 2];
    mesh.append(glam::Mat4::IDENTITY, &quad(5.0), &front);
    mesh.append(glam::Mat4::IDENTITY, &quad(4.5), &back);
    mesh.append(glam::Mat4::IDENTITY, &quad(3.0), &front);
    let left_only = [
        [-9.0, -9.0, 4.0],
        [0.0, -9.0, 4.0],
        [0.0, 9.0, 4.0],
        [-9.0, 9.0, 4.0],
    ];
    mesh.append(glam::Mat4::IDENTITY, &left_only, &front);
    let cam = Camera {
        eye: glam::Vec3::new(0.0, 0.0, 10.0),
        target: glam::Vec3::ZERO,
        up: glam::Vec3::Y,
        projection: CameraProjection::Orthographic { height: 6.0 },
        near: 0.1,
        far: 50.0,
    };
    let raster = GBufferRenderer::new(&c.device);
    let gm = raster.upload(c, &mesh).unwrap();
    let (w, h) = (64u32, 32u32);
    for guard in [0u32, 8] {
        let gb = raster.render_guarded(c, &gm, &cam, (w, h), guard).unwrap();
        let lin = cam
            .obscura_projection(w as f32 / h as f32)
            .linearize(DEPTH_CONVENTION)
            .unwrap();
        for (separation, left, right) in [
            (0.5, Some(6.0), Some(7.0)),
            (1.5, Some(7.0), Some(7.0)),
            (2.5, None, None),
        ] {
            let second = raster.peel(c, &gm, &cam, &gb, separation).unwrap();
            assert_eq!(
                (second.texture.width(), second.texture.height()),
                (gb.width, gb.height)
            );
            let depth = c.read_f32(&second.texture).unwrap();
            let bw = gb.width as usize;
            for y in 0..gb.height as usize {
                for x in 0..bw {
                    let xv = x as i64 - guard as i64;
                    if (w as i64 / 2 - 1..=w as i64 / 2).contains(&xv) {
                        continue;
                    }
                    let want = if xv < w as i64 / 2 { left } else { right };
                    let got = lin.apply(depth[y * bw + x]);
                    let ok = match (got, want) {
                        (Some(g), Some(e)) => (g - e).abs() <= 1e-4 * e,
                        (g, e) => g.is_none() && e.is_none(),
                    };
                    assert!(ok, "guard {guard}, separation {separation}, pixel ({x}, {y}): {got:?}, want {want:?}");
                }
            }
        }
        for bad in [0.0, -1.0, f32::NAN] {
            assert!(matches!(
                raster.peel(c, &gm, &cam, &gb, bad),
                Err(SceneError::Camera(_))
            ));
        }
    }
}

#[test]
fn deinterleaved_ao_matches_randomized_on_the_default_scene() {
    // The speed-up must not come from doing different work: the same estimator with the
    // same patterns, only with offsets snapped to the N-pixel lattice.
    let _g = lock();
    let mesh = default_scene::mesh();
    let cam = default_scene::camera();
    let (w, h) = (640, 360);
    for estimator in Estimator::ALL {
        let run = |mode| {
            let o = AoOptions {
                mode,
                ..AoOptions::preset(estimator, Preset::High)
            };
            render_with(&mesh, &cam, w, h, 1.0, o).1
        };
        let base = run(AoMode::Randomized);
        // Stated tolerances (AO units): HBAO RMSE ≤ 0.03, |bias| ≤ 0.005 (measured
        // 0.009 / 0.014 RMSE); GTAO at High RMSE ≤ 0.045, |bias| ≤ 0.01 (measured
        // 0.024 / 0.033 with 4 × 4 even steps, before High became 3 × 5 crowded).
        let (max_rmse, max_bias) = match estimator {
            Estimator::Hbao => (0.03, 0.005),
            _ => (0.045, 0.01),
        };
        for mode in [AoMode::Deinterleaved2, AoMode::Deinterleaved4] {
            let ao = run(mode);
            let n = ao.len() as f32;
            let bias = ao.iter().zip(&base).map(|(a, b)| a - b).sum::<f32>() / n;
            let rmse = (ao
                .iter()
                .zip(&base)
                .map(|(a, b)| (a - b).powi(2))
                .sum::<f32>()
                / n)
                .sqrt();
            eprintln!("{estimator:?} {mode:?}: RMSE {rmse:.4}, bias {bias:.4} against randomized");
            assert!(
                rmse <= max_rmse && bias.abs() <= max_bias,
                "{estimator:?} {mode:?}: RMSE {rmse}, bias {bias}"
            );
        }
    }
}

#[test]
fn every_estimator_converges_to_its_screen_space_reference() {
    // The screen-space reference is the estimator's own integral (64 × 64 samples, no
    // jitter); more samples per pixel must bring each estimator closer to it.
    let _g = lock();
    let mesh = default_scene::mesh();
    let cam = default_scene::camera();
    let (w, h) = (192, 108);
    for estimator in Estimator::ALL {
        let reference = render_with(
            &mesh,
            &cam,
            w,
            h,
            1.0,
            AoOptions::screen_reference(estimator),
        )
        .1;
        assert!(
            reference.iter().any(|&a| a < 0.7),
            "{estimator:?}: the reference has occlusion"
        );
        // Raw samples, as the reference: no denoiser between them.
        let errors: Vec<f32> = Preset::ALL
            .into_iter()
            .map(|preset| AoOptions {
                mode: AoMode::Randomized,
                denoise: Denoise::None,
                ..AoOptions::preset(estimator, preset)
            })
            .chain([AoOptions {
                directions: 32,
                steps: 32,
                mode: AoMode::Randomized,
                denoise: Denoise::None,
                ..AoOptions::preset(estimator, Preset::Ultra)
            }])
            .map(|o| rmse(&render_with(&mesh, &cam, w, h, 1.0, o).1, &reference))
            .collect();
        eprintln!("{estimator:?}: RMSE vs screen-space reference, low..ultra, 32×32: {errors:?}");
        // Stated tolerance: each step up may not raise the error by more than 5% (noise
        // between neighbouring presets), and 32 × 32 jittered samples end within a quarter
        // of the low preset's error and 0.01 AO units of the reference (measured: every
        // step lowers it; 32 × 32 is at 3–7% of low, 0.0014–0.0049).
        for pair in errors.windows(2) {
            assert!(pair[1] <= pair[0] * 1.05, "{estimator:?}: {errors:?}");
        }
        let last = *errors.last().unwrap();
        assert!(
            last <= 0.25 * errors[0] && last <= 0.01,
            "{estimator:?}: {errors:?}"
        );
    }
}
