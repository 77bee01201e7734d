//! The spatial denoiser against the CPU reference, and its stop at depth edges.

use super::*;

/// Denoising matches its CPU mirror, applied to the same frame's AO without denoising:
/// the spatial denoiser at full resolution (randomized: 5×5; fused 2×2 deinterleaving: 3×3;
/// its taps packed by the AO pass, or after it by the temporal pass) and half resolution
/// (the denoised working AO), and
/// the box and tent downsamples followed by upsampling (the output); and the denoiser is
/// edge-aware: on a step edge it leaves the open near side open.
#[test]
fn denoise_matches_cpu_reference_and_stops_at_edges() {
    let _g = lock();
    let p = persp(W, H);
    let raw = test_scene(&p, W, H);
    let params = AoParams {
        radius: 1.5,
        ..Default::default()
    };
    let run = |options| run_linear(&raw, W, H, p, options, &params);
    // Tolerance: 99.5% of pixels within 1e-3 (exp differs in the last bits between the
    // GPU and the CPU; the working AO itself matches exactly).
    let check = |gpu: &[f32], cpu: &[f32], what: &str| {
        assert_eq!(gpu.len(), cpu.len(), "{what}");
        let close = gpu
            .iter()
            .zip(cpu)
            .filter(|(g, c)| (*g - *c).abs() <= 1e-3)
            .count();
        assert!(
            close * 200 >= gpu.len() * 199,
            "{what}: {close}/{}",
            gpu.len()
        );
    };
    let spatial_cases = [
        (Resolution::Full, randomized()),
        (
            Resolution::Full,
            AoOptions {
                denoise: Denoise::None,
                ..Default::default()
            },
        ),
        (
            Resolution::Half,
            AoOptions {
                fused: false,
                ..randomized()
            },
        ),
        // After the temporal pass (its first frame), which packs the AO for the denoiser as
        // the AO pass does where nothing runs between them.
        (
            Resolution::Full,
            AoOptions {
                denoise: Denoise::None,
                history: 4,
                ..Default::default()
            },
        ),
    ];
    for (resolution, o) in spatial_cases {
        let base = AoOptions { resolution, ..o };
        let denoised = run(AoOptions {
            denoise: Denoise::Spatial,
            ..base
        });
        let none = run(base);
        // The AO before denoising: the working AO below full resolution, the output at full.
        let (before, after) = if resolution == Resolution::Full {
            (&none.ao, &denoised.ao)
        } else {
            (&none.work_ao, &denoised.work_ao)
        };
        let work = denoised.frame.at_factor(resolution.factor());
        let prepared = if resolution == Resolution::Full {
            reference::prepare(&work, &raw, W)
        } else {
            none.levels[0].clone()
        };
        let cpu = reference::denoise(&work, &prepared, before, base.pattern_period());
        let what = format!(
            "{resolution:?} {:?} history {} spatial",
            base.mode, base.history
        );
        check(after, &cpu, &what);
        assert!(
            before
                .iter()
                .zip(after.iter())
                .any(|(a, b)| (a - b).abs() > 1e-3),
            "{what}: the denoiser changed nothing"
        );
    }
    for resolution in [Resolution::Full, Resolution::Half] {
        let base = AoOptions {
            resolution,
            fused: false,
            ..randomized()
        };
        let none = run(base);
        let before = if resolution == Resolution::Full {
            &none.ao
        } else {
            &none.work_ao
        };
        for tent in [false, true] {
            let denoise = if tent { Denoise::Tent } else { Denoise::Box };
            let r = run(AoOptions { denoise, ..base });
            let work_size = [W, H].map(|s| s.div_ceil(resolution.factor()));
            let (low_size, low) = reference::ao_downsample(tent, work_size, before);
            let up_level = resolution.factor().ilog2() as usize + 1;
            let cpu = reference::upsample(
                base.upsample,
                &r.frame,
                &none.prepared,
                low_size,
                &low,
                &r.levels[up_level - 1],
                &[],
            );
            check(&r.ao, &cpu, &format!("{resolution:?} {denoise:?}"));
        }
    }
    // Edge stopping: a step edge's far side is occluded next to the edge; denoised, the
    // near side stays open (a plain box filter would carry the far side's darkness over).
    let (w, h, edge) = (67, 21, 33);
    let depth = step_edge(w, h, edge, 4.0, 8.0);
    let params = AoParams {
        radius: 6.0,
        ..Default::default()
    };
    let r = run_ao(
        &depth,
        w,
        h,
        ortho(w, h),
        DepthConvention::LinearView,
        None,
        AoOptions {
            denoise: Denoise::Spatial,
            ..randomized()
        },
        &params,
    );
    let row = (h / 2 * w) as usize;
    let near_min = r.ao[row..row + edge as usize]
        .iter()
        .fold(1.0f32, |m, &a| m.min(a));
    assert!(
        near_min > 0.999,
        "the denoiser bled across the edge: {near_min}"
    );
    assert!(
        r.ao[row + edge as usize] < 0.9,
        "the far side next to the edge stays dark"
    );
}
