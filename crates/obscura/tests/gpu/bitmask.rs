//! The visibility-bitmask estimator (src/passes/estimators/bitmask.wgsl): its GPU pass
//! against its CPU mirror for finite and infinite thickness and both march spacings, its
//! agreement with GTAO when surfaces are infinitely thick, and what a thin prior changes
//! behind a thin occluder. One device per binary.

use crate::{
    all_variants, assert_matches_mirror, lock, persp, run_ao, test_projections, test_scene, H, W,
};
use obscura::{reference, AoMode, AoOptions, AoParams, DepthConvention, Estimator, Projection};

/// `run_ao` on linear view depth over the whole image.
fn run_linear(
    raw: &[f32],
    (w, h): (u32, u32),
    projection: Projection,
    options: AoOptions,
    params: &AoParams,
) -> crate::Run {
    run_ao(
        raw,
        w,
        h,
        projection,
        DepthConvention::LinearView,
        None,
        options,
        params,
    )
}

fn bitmask(mode: AoMode) -> AoOptions {
    AoOptions {
        estimator: Estimator::Bitmask,
        mode,
        ..crate::randomized()
    }
}

/// The mirror test of every mode runs with the default model; this one runs the other
/// corners of the model (infinite thickness, a thin prior, a march denser near the centre)
/// in the randomized and 2×2 layouts, perspective and orthographic.
#[test]
fn bitmask_matches_its_mirror_for_every_model() {
    let _g = lock();
    for projection in test_projections() {
        let raw = test_scene(&projection, W, H);
        for (thickness, march_exponent) in [(f32::INFINITY, 1.0), (0.2, 2.5), (1.0, 1.5)] {
            let params = AoParams {
                radius: 1.5,
                thickness,
                ..Default::default()
            };
            let prepared = run_linear(
                &raw,
                (W, H),
                projection,
                bitmask(AoMode::Randomized),
                &params,
            )
            .prepared;
            for options in all_variants()
                .into_iter()
                .filter(|o| o.estimator == Estimator::Bitmask && o.mode != AoMode::Deinterleaved4)
                .map(|o| AoOptions {
                    march_exponent,
                    ..o
                })
            {
                let r = run_linear(&raw, (W, H), projection, options, &params);
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
/// so the bitmask is GTAO but for rounding each horizon to the nearest of 32 equal shares
/// of the slice's integral: at most 1/64 of a slice per side, 1/32 of the AO. Tolerance:
/// every pixel within 0.04 of GTAO, the mean within 0.005.
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
        run_linear(&raw, (W, H), projection, options, &params).ao
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

/// A thin strip one unit in front of a wall, seen orthographically. Taken as infinitely
/// deep it shadows the wall beside it like a fin reaching back into the wall; taken as
/// 0.2 units deep it blocks only the sectors between its front and back, so the wall
/// beside it is brighter, and the strip's own top, which nothing covers, is unchanged.
#[test]
fn a_thin_prior_lightens_the_wall_behind_a_thin_strip() {
    let _g = lock();
    let (w, h) = (64u32, 40u32);
    let projection = Projection::Orthographic {
        half_width: 4.0 * w as f32 / h as f32,
        half_height: 4.0,
        near: 0.1,
        far: 50.0,
    };
    // Columns 30..34: the strip at depth 9; elsewhere the wall at depth 10.
    let strip = |x: u32| (30..34).contains(&x);
    let raw: Vec<f32> = (0..w * h)
        .map(|i| if strip(i % w) { 9.0 } else { 10.0 })
        .collect();
    let ao = |thickness: f32| {
        let params = AoParams {
            radius: 2.0,
            thickness: thickness / 2.0,
            ..Default::default()
        };
        run_linear(
            &raw,
            (w, h),
            projection,
            bitmask(AoMode::Randomized),
            &params,
        )
        .ao
    };
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
