//! Bent normals against the CPU reference in every layout, and on planes and in a crease.

use super::*;

#[test]
fn bent_normals_match_cpu_reference_in_every_layout() {
    let _g = lock();
    let p = persp(W, H);
    let raw = test_scene(&p, W, H);
    let params = AoParams {
        radius: 1.5,
        ..Default::default()
    };
    let run = |options| run_linear(&raw, W, H, p, options, &params);
    // The full-resolution prepared buffer (fused deinterleaved modes keep none).
    let full = run(AoOptions {
        fused: false,
        ..randomized()
    })
    .prepared;
    for (estimator, resolution) in [
        (Estimator::Gtao, Resolution::Full),
        (Estimator::Gtao, Resolution::Half),
        (Estimator::Hbao, Resolution::Full),
        (Estimator::Hbao, Resolution::Half),
        (Estimator::Bitmask, Resolution::Full),
    ] {
        for mode in AoMode::ALL {
            for (fused, denoise) in [
                (true, Denoise::None),
                (false, Denoise::None),
                (true, Denoise::Spatial),
            ] {
                let options = AoOptions {
                    estimator,
                    resolution,
                    mode,
                    fused,
                    denoise,
                    directions: 6,
                    steps: 5,
                    bent_normals: true,
                    ..Default::default()
                };
                let r = run(options);
                let plain = run(AoOptions {
                    bent_normals: false,
                    ..options
                });
                assert_rounding_only(
                    &r.ao,
                    &plain.ao,
                    &format!("{options:?}: bent normals changed the AO"),
                );
                let (work, prepared) = match resolution {
                    Resolution::Full => (r.frame, full.clone()),
                    _ => (
                        r.frame.at_factor(resolution.factor()),
                        r.levels.last().unwrap().clone(),
                    ),
                };
                // The AO pass's against the mirror, then each later pass from the GPU's own
                // input: the denoiser at the working resolution, the upsampler to full.
                let gpu_raw = if r.bent_raw.is_empty() {
                    &r.bent
                } else {
                    &r.bent_raw
                };
                let cpu_raw = reference::bent_normals(&work, &options, &prepared);
                assert_close(gpu_raw, &cpu_raw, &format!("{options:?}: AO pass"));
                let mut cpu = gpu_raw.clone();
                if denoise == Denoise::Spatial {
                    cpu = reference::denoise_bent(&work, &prepared, &cpu, options.pattern_period());
                }
                if resolution != Resolution::Full {
                    let size = [W, H].map(|s| s.div_ceil(resolution.factor()));
                    cpu = reference::upsample_bent(
                        options.upsample,
                        &r.frame,
                        &full,
                        size,
                        &cpu,
                        &prepared,
                        &[],
                        true,
                    );
                }
                assert_close(&r.bent, &cpu, &format!("{options:?}: result"));
                // Bent normals at full resolution; unit on surfaces, zero on sky; bent away
                // from the normal in the creases.
                let prepared = &full;
                let mut bent_far = 0;
                for (b, v) in r.bent.iter().zip(prepared) {
                    if v.x > 0.0 {
                        assert!(
                            (b.length() - 1.0).abs() < 1e-3,
                            "{options:?}: |b| = {}",
                            b.length()
                        );
                        let n = Vec3::new(v.y, v.z, v.w);
                        if b.dot(n).clamp(-1.0, 1.0).acos() > 10f32.to_radians() {
                            bent_far += 1;
                        }
                    } else {
                        assert_eq!(*b, Vec3::ZERO, "{options:?}: sky");
                    }
                }
                assert!(
                    bent_far > 10,
                    "{options:?}: only {bent_far} pixels bent by 10°"
                );
            }
        }
    }
    // Every upsampler takes them with its own weights; without full-resolution normals
    // (fused, other than the bilateral one) it interpolates the directions themselves.
    let pyramid = reference::pyramid([W, H], &full);
    for upsampler in Upsampler::ALL {
        let options = AoOptions {
            resolution: Resolution::Half,
            mode: AoMode::Randomized,
            upsample: upsampler,
            denoise: Denoise::None,
            bent_normals: true,
            ..Default::default()
        };
        let r = run(options);
        let size = [W, H].map(|s| s.div_ceil(2));
        let cpu = reference::upsample_bent(
            upsampler,
            &r.frame,
            &full,
            size,
            &r.bent_raw,
            r.levels.last().unwrap(),
            &pyramid,
            upsampler == Upsampler::Bilateral,
        );
        assert_close(&r.bent, &cpu, &format!("{upsampler:?}"));
    }
}

/// Bent normals with analytic answers, in every layout. On a plane (facing the camera, or
/// tilted 60°) nothing is occluded and the bent normal is the normal. In a 90° crease — a
/// plane A meeting a plane B, both turned 45° from the view axis (a valley seen from its
/// open side) — a point of A at distance t from B sees its whole hemisphere except the
/// directions that reach B within R (ω·n_B < −t/R); the cosine-weighted mean of what it sees
/// tilts from n_A toward n_B, toward the bisector of the open quadrant, by atan(z / y) with,
/// for a = t/R < 1,
///   y = 2π/3 − (π/2)(2/3 − a + a³/3),   z = (2/3)(1 − a²)^{3/2}
/// (integrals over the unit hemisphere; 32.5° at the crease, 0 from a = 1 on).
/// GTAO 16 × 16, no denoiser, R ≈ 11 px. Tolerances (measured worst in brackets): planes
/// facing: every pixel within 1° (0.7°); tilted: mean within 2.5° (2.1°), every pixel within
/// 8° (7.0°: as for the AO, samples snapped to the N-pixel lattice leave the slice plane,
/// where a tilted plane rises above its horizon). Crease, pixels of A with 0.1 < a < 0.9
/// away from the image's sides: within 3° of the formula (1.3° randomized, 2.1° 2×2), 6° on
/// the 4×4 lattice (5.3°: 4-pixel snapping against an 11-pixel radius); beyond a = 1.2
/// within 1.5° of n_A (1.0°); no component along the crease above 0.1 (0.07).
/// HBAO 16 × 16 on the same planes: its horizon in a direction is the highest sample along
/// the march, which runs in the plane of the view vector, while its integral (and its AO,
/// Bavoil et al. 2008) takes that horizon in the plane of the normal: in the crease, within
/// 11° of the formula (8.0–9.6°, where the formula spans 0–32.5°) and 0.15 along the crease
/// (0.11–0.14); planes and beyond R as GTAO.
#[test]
fn bent_normals_on_planes_and_in_a_crease() {
    use std::f32::consts::PI;
    let _g = lock();
    let (w, h) = (96, 64);
    let p = persp(w, h);
    let params = AoParams {
        radius: 1.0,
        ..Default::default()
    };
    let run = |raw: &[f32], estimator, mode| {
        let options = AoOptions {
            estimator,
            mode,
            directions: 16,
            steps: 16,
            denoise: Denoise::None,
            bent_normals: true,
            ..Default::default()
        };
        run_linear(raw, w, h, p, options, &params)
    };
    let angle = |a: Vec3, b: Vec3| a.dot(b).clamp(-1.0, 1.0).acos().to_degrees();
    let tilted = Vec3::new(0.0, 60f32.to_radians().sin(), 60f32.to_radians().cos());
    let (na, nb) = (
        Vec3::new(0.0, 1.0, 1.0).normalize(),
        Vec3::new(0.0, -1.0, 1.0).normalize(),
    );
    let corner = Vec3::new(0.0, 0.0, -5.0);
    for (estimator, mode) in [Estimator::Gtao, Estimator::Hbao, Estimator::Bitmask]
        .into_iter()
        .flat_map(|e| AoMode::ALL.map(|m| (e, m)))
    {
        for normal in [Vec3::Z, tilted] {
            let raw = ray_cast(&p, w, h, &[(Vec3::new(0.0, 0.0, -5.0), normal)], &[]);
            let r = run(&raw, estimator, mode);
            let angles: Vec<f32> = r
                .bent
                .iter()
                .zip(&raw)
                .filter(|(_, d)| **d > 0.0)
                .map(|(b, _)| angle(*b, normal))
                .collect();
            let mean = angles.iter().sum::<f32>() / angles.len() as f32;
            let max = angles.iter().cloned().fold(0.0, f32::max);
            let (mean_ok, max_ok) = if normal == Vec3::Z {
                (1.0, 1.0)
            } else {
                (2.5, 8.0)
            };
            assert!(
                angles.len() > 4000 && mean <= mean_ok && max <= max_ok,
                "{estimator:?} {mode:?} plane {normal}: mean {mean}°, max {max}° from the normal"
            );
        }
        let raw = ray_cast(&p, w, h, &[(corner, na), (corner, nb)], &[]);
        let r = run(&raw, estimator, mode);
        let f = r.frame;
        let (mut worst, mut far, mut side, mut count) = (0f32, 0f32, 0f32, 0);
        for y in 0..h {
            for x in 16..w - 16 {
                let i = (y * w + x) as usize;
                let pos = f.view_position([x as f32 + 0.5, y as f32 + 0.5], raw[i]);
                // Pixels of A (the lower half) only; B's mirror B's by symmetry.
                if raw[i] <= 0.0 || (pos - corner).dot(na).abs() > 1e-3 {
                    continue;
                }
                let a = (pos - corner).dot(nb) / params.radius;
                let b = r.bent[i];
                let got = b.dot(nb).atan2(b.dot(na)).to_degrees();
                side = side.max(b.x.abs());
                if a > 1.2 {
                    far = far.max(got.abs());
                } else if (0.1..0.9).contains(&a) {
                    let y_ = 2.0 * PI / 3.0 - PI / 2.0 * (2.0 / 3.0 - a + a * a * a / 3.0);
                    let z_ = 2.0 / 3.0 * (1.0 - a * a).powf(1.5);
                    let want = z_.atan2(y_).to_degrees();
                    worst = worst.max((got - want).abs());
                    count += 1;
                }
            }
        }
        let (worst_ok, side_ok) = match (estimator, mode) {
            (Estimator::Hbao, _) => (11.0, 0.15),
            (_, AoMode::Deinterleaved4) => (6.0, 0.1),
            _ => (3.0, 0.1),
        };
        assert!(
            count > 300 && worst <= worst_ok && far <= 1.5 && side <= side_ok,
            "{estimator:?} {mode:?} crease: {count} px, worst {worst}° from the formula, {far}° beyond R, \
             {side} along the crease"
        );
    }
}
