//! Temporal accumulation on lavapipe: the temporal pass against its CPU mirror after a
//! camera move, convergence of a still camera toward the estimator's integral, history
//! kept where the surface stayed visible and dropped where it was disoccluded, and resets.

use crate::{common, ctx};
use glam::{Mat4, Vec3, Vec4};
use obscura::{
    reference, Ao, AoMode, AoOptions, AoParams, CameraMotion, Denoise, Estimator, Projection,
};

const W: u32 = 96;
const H: u32 = 64;

fn persp() -> Projection {
    Projection::Perspective {
        fov_y: 60f32.to_radians(),
        aspect: W as f32 / H as f32,
        near: 0.1,
        far: 100.0,
    }
}

/// World → view of a camera at `eye` looking at `target` (y up).
fn view_matrix(eye: Vec3, target: Vec3) -> Mat4 {
    glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y)
}

/// Linear view depth of a floor (y = 0), a back wall (z = −6) and a sphere (centre
/// (0, 0.8, −3), radius 0.8) seen by `view`, 0 where the ray escapes.
fn scene_depth(view: Mat4) -> Vec<f32> {
    let inv = view.inverse();
    let s = persp().ndc_to_view_scale();
    let eye = inv.transform_point3(Vec3::ZERO);
    let (centre, radius) = (Vec3::new(0.0, 0.8, -3.0), 0.8f32);
    let mut out = Vec::with_capacity((W * H) as usize);
    for y in 0..H {
        for x in 0..W {
            let ndc = [
                (x as f32 + 0.5) / W as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / H as f32 * 2.0,
            ];
            let dir_view = Vec3::new(ndc[0] * s[0], ndc[1] * s[1], -1.0);
            let dir = inv.transform_vector3(dir_view);
            let mut t = f32::INFINITY;
            if dir.y < 0.0 {
                t = t.min(-eye.y / dir.y);
            }
            if dir.z < 0.0 {
                t = t.min((-6.0 - eye.z) / dir.z);
            }
            let oc = eye - centre;
            let (b, c) = (oc.dot(dir), oc.dot(oc) - radius * radius);
            let a = dir.dot(dir);
            let disc = b * b - a * c;
            if disc >= 0.0 {
                let ts = (-b - disc.sqrt()) / a;
                if ts > 0.0 {
                    t = t.min(ts);
                }
            }
            // dir_view has z = -1, so the ray parameter is the linear depth.
            out.push(if t.is_finite() { t } else { 0.0 });
        }
    }
    out
}

struct Frame {
    ao: Vec<f32>,
    raw: Vec<f32>,
    history: Vec<Vec4>,
    /// Bent normals (when on): the result, the AO pass's, and the history written.
    bent: Vec<Vec3>,
    bent_raw: Vec<Vec3>,
    bent_history: Vec<Vec3>,
    uniforms: obscura::uniforms::FrameUniforms,
}

/// Records one frame of `depth` and reads back the output, the raw AO before the temporal
/// pass and the history it wrote.
fn frame(ao: &mut Ao, depth: &[f32], params: &AoParams) -> Frame {
    let c = ctx();
    let tex = common::upload_r32(c, depth, W, H);
    let view = tex.create_view(&Default::default());
    let input = common::linear_input(&view, persp());
    let uniforms = ao.validate(&input, params).unwrap();
    c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, params))
        .unwrap();
    let hist = c.read_f32(ao.history().unwrap()).unwrap();
    let vectors = |t: Option<&wgpu::Texture>| -> Vec<Vec3> {
        t.map_or(Vec::new(), |t| {
            let v = c.read_f32(t).unwrap();
            v.chunks_exact(4)
                .map(|c| Vec3::new(c[0], c[1], c[2]))
                .collect()
        })
    };
    Frame {
        bent: vectors(ao.bent_normals()),
        bent_raw: vectors(ao.bent_normals_raw()),
        bent_history: vectors(ao.bent_history()),
        ao: c.read_f32(ao.output().unwrap()).unwrap(),
        raw: c.read_f32(ao.working_ao().unwrap()).unwrap(),
        history: hist.chunks_exact(4).map(Vec4::from_slice).collect(),
        uniforms,
    }
}

/// An `Ao` with `options` but no denoiser after the temporal pass, so the output is what
/// the temporal pass wrote.
fn temporal_ao(options: AoOptions) -> Ao {
    Ao::new(
        &ctx().device,
        AoOptions {
            denoise: Denoise::None,
            ..options
        },
    )
    .unwrap()
}

fn params(motion: CameraMotion) -> AoParams {
    AoParams {
        radius: 1.0,
        motion,
        ..Default::default()
    }
}

fn moved(from: Mat4, to: Mat4) -> CameraMotion {
    CameraMotion::Moved {
        previous_from_current: (from * to.inverse()).to_cols_array_2d(),
    }
}

/// After a camera move, the GPU's temporal pass (history and output) matches the CPU
/// mirror run on the GPU's own inputs (its raw AO and last frame's history), in the
/// randomized layout and in fused 2×2 deinterleaving (prepared values read from layers).
/// Tolerance: 99.5% of pixels within 1e-4 (bilinear weights differ in the last bits). Bent
/// normals are on: theirs match the mirror too (99.5% within 1e-3 per component), the
/// history written is the output, and where the history was kept they moved from this
/// frame's raw bent normals toward last frame's.
#[test]
fn temporal_pass_matches_cpu_mirror_after_a_move() {
    let _g = super::lock();
    let v0 = view_matrix(Vec3::new(0.0, 1.5, 2.0), Vec3::new(0.0, 0.6, -3.0));
    let v1 = view_matrix(Vec3::new(0.25, 1.55, 1.9), Vec3::new(0.1, 0.6, -3.0));
    let (d0, d1) = (scene_depth(v0), scene_depth(v1));
    for mode in [AoMode::Randomized, AoMode::Deinterleaved2] {
        let mut ao = temporal_ao(AoOptions {
            mode,
            history: 8,
            bent_normals: true,
            ..Default::default()
        });
        let f0 = frame(&mut ao, &d0, &params(CameraMotion::Still));
        let f1 = frame(&mut ao, &d1, &params(moved(v0, v1)));
        // The frame's uniforms as the library fills them for frame 1.
        let mut u = f1.uniforms;
        u.history = 1;
        u.prev_from_view = (v0 * v1.inverse()).to_cols_array_2d();
        u.prev_ndc_to_view = f0.uniforms.ndc_to_view;
        let prepared = reference::prepare(&u, &d1, W);
        let (hist, out) = reference::temporal(&u, &prepared, &f1.raw, &f0.history);
        let close = |a: f32, b: f32| (a - b).abs() <= 1e-4;
        let n = out.len();
        let ok_out = out
            .iter()
            .zip(&f1.ao)
            .filter(|(a, b)| close(**a, **b))
            .count();
        let ok_hist = hist
            .iter()
            .zip(&f1.history)
            .filter(|(a, b)| {
                let same_normal = a.y == 0.0
                    || reference::unpack_normal(a.w).dot(reference::unpack_normal(b.w)) > 0.999;
                close(a.x, b.x) && close(a.y, b.y) && close(a.z, b.z) && same_normal
            })
            .count();
        assert!(ok_out * 200 >= n * 199, "{mode:?}: output {ok_out}/{n}");
        assert!(ok_hist * 200 >= n * 199, "{mode:?}: history {ok_hist}/{n}");
        // The move kept history on most of the image and dropped some (the sphere moved
        // across the wall and floor).
        let kept = f1.history.iter().filter(|h| h.y == 2.0).count();
        let fresh = f1.history.iter().filter(|h| h.y == 1.0).count();
        assert!(kept * 2 > n, "{mode:?}: history kept on {kept}/{n}");
        assert!(fresh > 0, "{mode:?}: no pixel was disoccluded");
        let bent =
            reference::temporal_bent(&u, &prepared, &f0.history, &f1.bent_raw, &f0.bent_history);
        assert_eq!(f1.bent, f1.bent_history, "{mode:?}: bent history = output");
        let ok_bent = bent
            .iter()
            .zip(&f1.bent)
            .filter(|(a, b)| (**a - **b).abs().max_element() <= 1e-3)
            .count();
        assert!(ok_bent * 200 >= n * 199, "{mode:?}: bent {ok_bent}/{n}");
        let moved = f1
            .bent
            .iter()
            .zip(&f1.bent_raw)
            .zip(&f1.history)
            .filter(|((b, r), h)| h.y == 2.0 && (**b - **r).length() > 1e-3)
            .count();
        assert!(
            moved * 4 > kept,
            "{mode:?}: bent history used on {moved}/{kept}"
        );
    }
}

/// A still camera accumulates toward the estimator's integral: the error against the
/// screen-space reference (64 × 64 samples, no jitter) falls from 1 to 4 to 16 frames, and
/// after 16 it is at most 75% of one frame's, because the sampling patterns rotate over
/// frames. The randomized layout with 16 steps per side, so that sampling noise dominates;
/// what accumulation cannot remove stays (measured here: 0.67 of one frame's error): the
/// bias of a maximum over a finite number of steps, the per-frame normalisation by the
/// slices' weights, and, in 2×2 deinterleaving, samples snapped to the 2-pixel lattice
/// (there the same measure falls to 0.87).
#[test]
fn still_camera_converges_toward_the_integral() {
    let _g = super::lock();
    let c = ctx();
    let v = view_matrix(Vec3::new(0.0, 1.5, 2.0), Vec3::new(0.0, 0.6, -3.0));
    let depth = scene_depth(v);
    let p = AoParams {
        radius: 2.0,
        ..params(CameraMotion::Still)
    };
    let mut reference_ao =
        Ao::new(&c.device, AoOptions::screen_reference(Estimator::Gtao)).unwrap();
    let tex = common::upload_r32(c, &depth, W, H);
    let view = tex.create_view(&Default::default());
    let input = common::linear_input(&view, persp());
    c.run(|enc| reference_ao.record(&c.device, &c.queue, enc, &input, &p))
        .unwrap();
    let truth = c.read_f32(reference_ao.output().unwrap()).unwrap();
    let rmse = |a: &[f32]| {
        let s: f64 = a
            .iter()
            .zip(&truth)
            .map(|(x, y)| ((x - y) as f64).powi(2))
            .sum();
        (s / a.len() as f64).sqrt()
    };
    let mut ao = temporal_ao(AoOptions {
        history: 32,
        steps: 16,
        mode: AoMode::Randomized,
        ..Default::default()
    });
    let first = frame(&mut ao, &depth, &p);
    let mut last = first.ao.clone();
    let mut e4 = 0.0;
    for k in 1..16 {
        last = frame(&mut ao, &depth, &p).ao;
        if k == 3 {
            e4 = rmse(&last);
        }
    }
    let (e1, e16) = (rmse(&first.ao), rmse(&last));
    assert!(
        e16 < e4 && e4 < e1 && e16 <= 0.75 * e1,
        "1 frame: {e1:.4}, 4: {e4:.4}, 16: {e16:.4}"
    );
    assert!(first.history.iter().any(|h| h.y == 1.0));
    assert!(ao
        .history()
        .map(|t| c.read_f32(t).unwrap())
        .unwrap()
        .chunks_exact(4)
        .all(|h| h[1] == 16.0 || h[1] == 0.0));
}

/// A sideways move uncovers wall and floor behind the sphere: those pixels start a new
/// history (1 frame, AO = this frame's, no ghost of the sphere), while pixels whose
/// surface was visible before keep theirs. The classes come from the analytic scene:
/// a pixel is disoccluded when the previous camera saw something nearer than its surface
/// point at that point's previous pixel.
#[test]
fn camera_move_keeps_history_where_visible_and_drops_it_where_disoccluded() {
    let _g = super::lock();
    let v0 = view_matrix(Vec3::new(-0.6, 1.0, 1.0), Vec3::new(-0.6, 0.8, -3.0));
    let v1 = view_matrix(Vec3::new(0.6, 1.0, 1.0), Vec3::new(0.6, 0.8, -3.0));
    let (d0, d1) = (scene_depth(v0), scene_depth(v1));
    let mut ao = temporal_ao(AoOptions {
        history: 8,
        ..Default::default()
    });
    for _ in 0..4 {
        frame(&mut ao, &d0, &params(CameraMotion::Still));
    }
    let f = frame(&mut ao, &d1, &params(moved(v0, v1)));
    let s = persp().ndc_to_view_scale();
    let to_prev = v0 * v1.inverse();
    let (mut visible, mut visible_kept, mut uncovered, mut uncovered_fresh) = (0, 0, 0, 0);
    for y in 2..H - 2 {
        for x in 2..W - 2 {
            let i = (y * W + x) as usize;
            let d = d1[i];
            if d <= 0.0 {
                continue;
            }
            let ndc = [
                (x as f32 + 0.5) / W as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / H as f32 * 2.0,
            ];
            let pos = Vec3::new(ndc[0] * s[0] * d, ndc[1] * s[1] * d, -d);
            let prev = to_prev.transform_point3(pos);
            let pd = -prev.z;
            let px = [
                ((prev.x / (s[0] * pd)) + 1.0) * 0.5 * W as f32,
                (1.0 - prev.y / (s[1] * pd)) * 0.5 * H as f32,
            ];
            if px[0] < 3.0 || px[1] < 3.0 || px[0] > (W - 3) as f32 || px[1] > (H - 3) as f32 {
                continue;
            }
            // Depths the previous camera saw around that point (3×3 texels).
            let (cx, cy) = (px[0] as i32, px[1] as i32);
            let seen: Vec<f32> = (0..9)
                .map(|k| d0[((cy + k / 3 - 1) as u32 * W + (cx + k % 3 - 1) as u32) as usize])
                .collect();
            let near = |v: &f32| (*v - pd).abs() < 0.01 * pd;
            if seen.iter().all(near) {
                visible += 1;
                visible_kept += (f.history[i].y == 5.0) as u32;
            } else if seen.iter().all(|v| *v > 0.0 && *v < 0.8 * pd) {
                uncovered += 1;
                let fresh = f.history[i].y == 1.0 && (f.ao[i] - f.raw[i]).abs() < 1e-6;
                uncovered_fresh += fresh as u32;
            }
        }
    }
    assert!(
        visible > 500 && uncovered > 20,
        "{visible} visible, {uncovered} uncovered"
    );
    assert!(
        visible_kept * 100 >= visible * 99,
        "history kept on {visible_kept}/{visible} visible pixels"
    );
    assert_eq!(
        uncovered_fresh, uncovered,
        "disoccluded pixels with a ghost"
    );
}

/// The history starts over after `reset_history`, a camera cut and a resize, and only then.
#[test]
fn history_resets_on_reset_cut_and_resize() {
    let _g = super::lock();
    let v = view_matrix(Vec3::new(0.0, 1.5, 2.0), Vec3::new(0.0, 0.6, -3.0));
    let depth = scene_depth(v);
    let mut ao = temporal_ao(AoOptions {
        history: 8,
        ..Default::default()
    });
    let frames_at_centre = |f: &Frame| f.history[(H / 2 * W + W / 2) as usize].y;
    let still = params(CameraMotion::Still);
    for k in 1..=3 {
        assert_eq!(frames_at_centre(&frame(&mut ao, &depth, &still)), k as f32);
    }
    ao.reset_history();
    assert_eq!(frames_at_centre(&frame(&mut ao, &depth, &still)), 1.0);
    assert_eq!(frames_at_centre(&frame(&mut ao, &depth, &still)), 2.0);
    let cut = params(CameraMotion::Cut);
    assert_eq!(frames_at_centre(&frame(&mut ao, &depth, &cut)), 1.0);
    // A resize (a smaller viewport of the same texture) starts over, and so does the way back.
    let c = ctx();
    let tex = common::upload_r32(c, &depth, W, H);
    let view = tex.create_view(&Default::default());
    let input = obscura::AoInput {
        viewport: Some(obscura::Viewport {
            x: 0,
            y: 0,
            width: W - 10,
            height: H - 10,
        }),
        ..common::linear_input(&view, persp())
    };
    c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &still))
        .unwrap();
    let small = c.read_f32(ao.history().unwrap()).unwrap();
    assert!(small.chunks_exact(4).all(|h| h[1] <= 1.0));
    assert_eq!(frames_at_centre(&frame(&mut ao, &depth, &still)), 1.0);
    assert_eq!(frames_at_centre(&frame(&mut ao, &depth, &still)), 2.0);
}

/// The history's packed normal (one float: 12-bit octahedral coordinates) decodes within
/// 0.1° of the normal, over the whole sphere, and is an integer below 2^24 (exact in f32).
#[test]
fn packed_history_normals_round_trip() {
    let _g = super::lock();
    let mut worst = 1.0f32;
    for i in 0..2000 {
        // A Fibonacci sphere: both hemispheres, the poles and the octahedron's folds.
        let z = 1.0 - 2.0 * (i as f32 + 0.5) / 2000.0;
        let phi = i as f32 * 2.399_963;
        let r = (1.0 - z * z).sqrt();
        for n in [
            Vec3::new(r * phi.cos(), r * phi.sin(), z),
            Vec3::X,
            -Vec3::Z,
            Vec3::Y,
        ] {
            let w = reference::pack_normal(n);
            assert!(
                w == w.floor() && (0.0..16_777_216.0).contains(&w),
                "{n}: {w}"
            );
            worst = worst.min(reference::unpack_normal(w).dot(n));
        }
    }
    assert!(worst > 0.1f32.to_radians().cos(), "worst cosine {worst}");
}

/// The temporal mirror keeps a history texel whose normal matches this pixel's and drops
/// one whose normal is turned 90° (the other face of an edge), with a still camera.
#[test]
fn history_with_another_normal_is_not_reused() {
    let _g = super::lock();
    let d = scene_depth(view_matrix(
        Vec3::new(0.0, 1.5, 2.0),
        Vec3::new(0.0, 0.6, -3.0),
    ));
    let mut ao = temporal_ao(AoOptions {
        history: 8,
        ..Default::default()
    });
    let f = frame(&mut ao, &d, &params(CameraMotion::Still));
    let mut u = f.uniforms;
    u.history = 1;
    u.prev_from_view = Mat4::IDENTITY.to_cols_array_2d();
    u.prev_ndc_to_view = u.ndc_to_view;
    let prepared = reference::prepare(&u, &d, W);
    let history = |turn: bool| -> Vec<Vec4> {
        prepared
            .iter()
            .map(|p| {
                let n = Vec3::new(p.y, p.z, p.w);
                let n = if turn { n.any_orthonormal_vector() } else { n };
                Vec4::new(0.5, 3.0, p.x, reference::pack_normal(n))
            })
            .collect()
    };
    let surfaces = prepared.iter().filter(|p| p.x > 0.0).count();
    let (kept, _) = reference::temporal(&u, &prepared, &f.raw, &history(false));
    let (dropped, out) = reference::temporal(&u, &prepared, &f.raw, &history(true));
    let n_kept = kept.iter().filter(|h| h.y == 4.0).count();
    let n_dropped = dropped.iter().filter(|h| h.y == 1.0).count();
    assert!(
        n_kept * 100 >= surfaces * 99,
        "kept on {n_kept} of {surfaces} pixels"
    );
    assert_eq!(n_dropped, surfaces, "turned normals rejected");
    assert!(
        out.iter().zip(&f.raw).all(|(a, b)| a == b),
        "no history: the raw AO"
    );
}
