//! The visibility-bitmask estimator (src/passes/estimators/bitmask.wgsl): its GPU pass
//! against its CPU mirror for finite and infinite thickness and both march spacings, its
//! agreement with GTAO when surfaces are infinitely thick, what a thin prior changes
//! behind a thin occluder, and a solid reaching into the radius from in front; the second
//! depth layer against its mirror, and its input checks. One device per binary.

use crate::{
    all_variants, assert_matches_mirror, lock, persp, run_linear, test_projections, test_scene, H,
    W,
};
use obscura::{reference, AoMode, AoOptions, AoParams, DepthConvention, Estimator, Projection};

fn bitmask(mode: AoMode) -> AoOptions {
    AoOptions {
        estimator: Estimator::Bitmask,
        mode,
        ..crate::randomized()
    }
}

/// The mirror test of every mode runs with the default model; this one runs the other
/// corners of the model (infinite thickness, a thin prior, marches denser near the centre,
/// by pow and by square roots) in the randomized and 2×2 layouts, perspective and
/// orthographic.
#[test]
fn bitmask_matches_its_mirror_for_every_model() {
    let _g = lock();
    for projection in test_projections() {
        let raw = test_scene(&projection, W, H);
        let models = [(f32::INFINITY, 1.0), (0.2, 2.5), (1.0, 1.5), (0.5, 1.25)];
        for (thickness, march_exponent) in models {
            let params = AoParams {
                radius: 1.5,
                thickness,
                ..Default::default()
            };
            let prepared =
                run_linear(&raw, W, H, projection, bitmask(AoMode::Randomized), &params).prepared;
            for options in all_variants()
                .into_iter()
                .filter(|o| o.estimator == Estimator::Bitmask && o.mode != AoMode::Deinterleaved4)
                .map(|o| AoOptions {
                    march_exponent,
                    ..o
                })
            {
                let r = run_linear(&raw, W, H, projection, options, &params);
                let cpu = reference::ao(&r.frame, &options, &prepared);
                let what = format!(
                    "{projection:?} thickness {thickness} exponent {march_exponent} {options:?}"
                );
                assert_matches_mirror(&r.ao, &cpu, &what);
                assert!(r.ao.iter().any(|&a| a < 0.9), "{what}: nothing occluded");
            }
        }
    }
}

/// With infinitely thick surfaces a slice's occluded sectors are those beyond its horizons,
/// so the bitmask is GTAO but for rounding each horizon to the nearest sector edge: half a
/// sector, at most 0.04 of a slice's integral per side (a sector is 3.6° to 7.2°), with no
/// sign. Tolerance: every pixel within 0.04 of GTAO, the mean within 0.005.
#[test]
fn infinitely_thick_bitmask_is_gtao() {
    let _g = lock();
    let projection = persp(W, H);
    let raw = test_scene(&projection, W, H);
    let params = AoParams {
        radius: 1.5,
        thickness: f32::INFINITY,
        ..Default::default()
    };
    let run = |estimator| {
        let options = AoOptions {
            estimator,
            ..crate::randomized()
        };
        run_linear(&raw, W, H, projection, options, &params).ao
    };
    let (b, g) = (run(Estimator::Bitmask), run(Estimator::Gtao));
    let max = b
        .iter()
        .zip(&g)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f32::max);
    let mean = b.iter().zip(&g).map(|(x, y)| x - y).sum::<f32>() / b.len() as f32;
    assert!(max <= 0.04 && mean.abs() <= 0.005, "max {max}, mean {mean}");
    assert!(g.iter().any(|&a| a < 0.8), "the scene occludes");
}

/// The strip scenes' size: 64 × 40, seen orthographically, 0.2 view units a pixel.
const STRIP_SIZE: (u32, u32) = (64, 40);

/// Randomized bitmask AO of a strip over columns 30..34 at linear depth `strip`, in front
/// of a plane at depth 10, seen orthographically (`STRIP_SIZE`), with `radius` and a
/// prior of `thickness` radii.
fn strip_ao(strip: f32, radius: f32, thickness: f32) -> Vec<f32> {
    let (w, h) = STRIP_SIZE;
    let projection = Projection::Orthographic {
        half_width: 4.0 * w as f32 / h as f32,
        half_height: 4.0,
        near: 0.1,
        far: 50.0,
    };
    let raw: Vec<f32> = (0..w * h)
        .map(|i| if is_strip(i % w) { strip } else { 10.0 })
        .collect();
    let params = AoParams {
        radius,
        thickness,
        ..Default::default()
    };
    run_linear(&raw, w, h, projection, bitmask(AoMode::Randomized), &params).ao
}

/// Whether column `x` is the strip's.
fn is_strip(x: u32) -> bool {
    (30..34).contains(&x)
}

/// A thin strip one unit in front of a wall, seen orthographically. Taken as infinitely
/// deep it shadows the wall beside it like a fin reaching back into the wall; taken as
/// 0.2 units deep it blocks only the sectors between its front and back, so the wall
/// beside it is brighter, and the strip's own top, which nothing covers, is unchanged.
#[test]
fn a_thin_prior_lightens_the_wall_behind_a_thin_strip() {
    let _g = lock();
    let (w, h) = STRIP_SIZE;
    let strip = is_strip;
    // The strip at depth 9, radius 2: the prior in view units over 2.
    let ao = |thickness: f32| strip_ao(9.0, 2.0, thickness / 2.0);
    let (thin, thick) = (ao(0.2), ao(f32::INFINITY));
    // Wall pixels within 6 columns of the strip, away from the image's top and bottom.
    let near_wall: Vec<usize> = (0..(w * h) as usize)
        .filter(|&i| {
            let (x, y) = (i as u32 % w, i as u32 / w);
            !strip(x) && (24..40).contains(&x) && (8..32).contains(&y)
        })
        .collect();
    let mean = |v: &[f32], at: &[usize]| at.iter().map(|&i| v[i]).sum::<f32>() / at.len() as f32;
    let (m_thin, m_thick) = (mean(&thin, &near_wall), mean(&thick, &near_wall));
    assert!(
        m_thick < 0.9,
        "the infinitely deep strip shadows the wall: {m_thick}"
    );
    assert!(
        m_thin > m_thick + 0.05,
        "a thin prior lightens the wall: {m_thin} against {m_thick}"
    );
    let top: Vec<usize> = (0..(w * h) as usize)
        .filter(|&i| strip(i as u32 % w) && (8..32).contains(&(i as u32 / w)))
        .collect();
    let (t_thin, t_thick) = (mean(&thin, &top), mean(&thick, &top));
    assert!(
        t_thin > 0.99 && t_thick > 0.99,
        "the strip's top is open: {t_thin}, {t_thick}"
    );
}

/// A plank 1.4 units above a floor, seen from above orthographically, radius 1. Its front
/// lies beyond R of every floor pixel, so a thin prior leaves the floor beside it open.
/// With the prior of one radius the plank reaches down to 0.4 above the floor, within R of
/// the floor beside it (under 0.6 away for the two columns next to it), so only the part
/// of its solid inside that sphere darkens them; the floor far from the plank stays open
/// either way. Infinitely thick, GTAO's rule counts its front in part (its falloff beyond
/// R, to GTAO_FALLOFF_END = 2 radii), and not at all from 2.2 units above.
#[test]
fn a_solid_reaching_into_the_radius_from_in_front_occludes() {
    let _g = lock();
    let w = STRIP_SIZE.0;
    // The plank's top at depth 8.6.
    let ao = |thickness: f32| strip_ao(8.6, 1.0, thickness);
    let rows = |cols: &[u32]| -> Vec<usize> {
        (8..32u32)
            .flat_map(|y| cols.iter().map(move |&x| (y * w + x) as usize))
            .collect()
    };
    let mean = |v: &[f32], at: &[usize]| at.iter().map(|&i| v[i]).sum::<f32>() / at.len() as f32;
    let (beside, far) = (rows(&[28, 29, 34, 35]), rows(&[10, 11, 52, 53]));
    let high = strip_ao(7.8, 1.0, f32::INFINITY);
    for (a, what) in [
        (&high, "infinitely thick 2.2 above"),
        (&ao(0.2), "0.2 deep"),
    ] {
        assert!(
            mean(a, &beside) > 0.99,
            "a plank {what} is out of reach: {}",
            mean(a, &beside)
        );
    }
    let thick = mean(&ao(f32::INFINITY), &beside);
    assert!(
        (0.75..0.95).contains(&thick),
        "a plank infinitely thick 1.4 above counts in part: {thick}"
    );
    let a = ao(1.0);
    assert!(
        mean(&a, &beside) < 0.9,
        "a plank one radius deep reaches into R: {}",
        mean(&a, &beside)
    );
    assert!(mean(&a, &far) > 0.99, "the open floor: {}", mean(&a, &far));
}

/// The bitmask with a second depth layer ([`AoOptions::second_layer`]): the AO of `raw`
/// (linear view depth) with `second` behind it, the prepare pass's copy of the second
/// layer, and the frame.
fn run_second_layer(
    raw: &[f32],
    second: &[f32],
    projection: Projection,
    options: AoOptions,
    params: &AoParams,
) -> (Vec<f32>, Vec<f32>, obscura::uniforms::FrameUniforms) {
    let c = crate::ctx();
    let depth = crate::upload_r32(raw, W, H);
    let back = crate::upload_r32(second, W, H);
    let (depth_view, back_view) = (
        depth.create_view(&Default::default()),
        back.create_view(&Default::default()),
    );
    let mut ao = obscura::Ao::new(&c.device, options).unwrap();
    let input = obscura::AoInput {
        depth: &depth_view,
        convention: DepthConvention::LinearView,
        projection,
        normals: None,
        viewport: None,
        guard_band: 0,
        second_layer: Some(&back_view),
        output: None,
    };
    let frame = ao.validate(&input, params).unwrap();
    c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, params))
        .unwrap();
    let copied = c.read_f32(ao.second_layer().unwrap()).unwrap();
    (c.read_f32(ao.output().unwrap()).unwrap(), copied, frame)
}

/// The test scene's second layer: behind the left 60% of the image a surface `gap` behind
/// the first (as a peel at the prior finds the far side of a thin object), none elsewhere
/// (0), and a few pixels whose "second layer" lies in front of the first, which the
/// estimator must ignore.
fn second_layer_of(raw: &[f32], gap: f32) -> Vec<f32> {
    raw.iter()
        .enumerate()
        .map(|(i, &d)| {
            let x = i as u32 % W;
            if d <= 0.0 || x >= W * 3 / 5 {
                0.0
            } else if i % 97 == 0 {
                0.5 * d
            } else {
                d + gap
            }
        })
        .collect()
}

/// In every full-resolution layout, perspective and orthographic, the GPU's bitmask with a
/// second layer matches its CPU mirror (`reference::ao_second_layer`, on the GPU's own
/// prepared buffer; tolerance as `assert_matches_mirror`), and the prepare pass copies the
/// second layer exactly (linear input). A second layer only adds solids, so without
/// denoising the AO never rises (to 1e-6) and falls somewhere by more than 0.05.
#[test]
fn second_layer_matches_its_mirror_and_only_darkens() {
    let _g = lock();
    let params = AoParams {
        radius: 1.5,
        thickness: 0.2,
        ..Default::default()
    };
    for projection in test_projections() {
        let raw = test_scene(&projection, W, H);
        let second = second_layer_of(&raw, 0.5);
        let prepared =
            run_linear(&raw, W, H, projection, bitmask(AoMode::Randomized), &params).prepared;
        for options in all_variants()
            .into_iter()
            .filter(|o| o.estimator == Estimator::Bitmask)
        {
            let with = AoOptions {
                second_layer: true,
                ..options
            };
            let what = format!("{projection:?} {with:?}");
            let (ao, copied, frame) = run_second_layer(&raw, &second, projection, with, &params);
            let expected: Vec<f32> = second.iter().map(|&d| d.max(0.0)).collect();
            assert_eq!(copied, expected, "{what}: the prepared second layer");
            let cpu = reference::ao_second_layer(&frame, &with, &prepared, &copied);
            assert_matches_mirror(&ao, &cpu, &what);
            let one = run_linear(&raw, W, H, projection, options, &params).ao;
            let rises = ao
                .iter()
                .zip(&one)
                .filter(|(a, b)| **a > **b + 1e-6)
                .count();
            let most = ao.iter().zip(&one).map(|(a, b)| b - a).fold(0.0, f32::max);
            assert!(
                rises == 0 && most > 0.05,
                "{what}: {rises} pixels rise, largest fall {most}"
            );
        }
    }
}

/// The second layer is checked like the other inputs: required by options that ask for
/// one, refused by options that do not, and of the depth's format and size.
#[test]
fn second_layer_inputs_are_checked() {
    let _g = lock();
    let c = crate::ctx();
    let projection = persp(W, H);
    let raw = test_scene(&projection, W, H);
    let depth = crate::upload_r32(&raw, W, H);
    let small = crate::upload_r32(&raw[..(W * H / 2) as usize], W, H / 2);
    let views = [&depth, &small].map(|t| t.create_view(&Default::default()));
    let input = |second| obscura::AoInput {
        depth: &views[0],
        convention: DepthConvention::LinearView,
        projection,
        normals: None,
        viewport: None,
        guard_band: 0,
        second_layer: second,
        output: None,
    };
    let params = AoParams::default();
    let with = AoOptions {
        second_layer: true,
        ..bitmask(AoMode::Deinterleaved2)
    };
    let mut two = obscura::Ao::new(&c.device, with).unwrap();
    let one = obscura::Ao::new(&c.device, bitmask(AoMode::Deinterleaved2)).unwrap();
    for (ao, second, why) in [
        (&two, None, "missing"),
        (&two, Some(&views[1]), "the wrong size"),
        (&one, Some(&views[0]), "not asked for"),
    ] {
        let err = ao.validate(&input(second), &params).unwrap_err();
        assert!(
            matches!(
                err,
                obscura::Error::InvalidTexture {
                    what: "second layer",
                    ..
                }
            ),
            "{why}: {err}"
        );
    }
    c.run(|enc| two.record(&c.device, &c.queue, enc, &input(Some(&views[0])), &params))
        .unwrap();
    for o in [
        AoOptions {
            second_layer: true,
            ..AoOptions::default()
        },
        AoOptions {
            second_layer: true,
            resolution: obscura::Resolution::Half,
            ..bitmask(AoMode::Randomized)
        },
    ] {
        assert!(matches!(
            obscura::Ao::new(&c.device, o),
            Err(obscura::Error::InvalidSetting {
                field: "second_layer",
                ..
            })
        ));
    }
}
