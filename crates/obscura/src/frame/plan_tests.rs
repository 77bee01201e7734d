//! The frame plan without a GPU: which passes run for each layout, resolution, history and
//! extension (bent normals, pyramids), which textures they need at what size, and that
//! every binding names a texture the plan creates or the output.

use super::plan::{Dispatch, Grid, Lifetime, Plan, Res};
use crate::passes::bindings::layout_entries;
use crate::passes::constants::{AO_FORMAT, AO_PACKED_FORMAT, PREPARED_FORMAT};
use crate::passes::shader::{Pass, PrepareStore};
use crate::{AoMode, AoOptions, Denoise, Estimator, Resolution, Upsampler};

/// The plan on a CPU adapter (one pyramid level per pass).
fn plan(o: AoOptions) -> Plan {
    Plan::new(&o, 1)
}

/// The passes after prepare, by label.
fn labels(p: &Plan) -> Vec<&'static str> {
    p.steps.iter().map(|s| s.pass.label()).collect()
}

fn options(mode: AoMode, resolution: Resolution, denoise: Denoise) -> AoOptions {
    AoOptions {
        mode,
        resolution,
        denoise,
        ..AoOptions::default()
    }
}

/// Every binding names a texture with a spec (or the output), each step binds exactly the
/// textures its pass's layout declares, exactly one step writes the output, and every spec
/// has a non-empty size.
fn check_consistent(p: &Plan, size: [u32; 2]) {
    let textures = p.textures();
    for st in &p.steps {
        let mut declared: Vec<u32> = layout_entries(st.pass)
            .iter()
            .filter(|e| !matches!(e.ty, wgpu::BindingType::Buffer { .. }))
            .map(|e| e.binding)
            .collect();
        let mut bound: Vec<u32> = st.views.iter().map(|v| v.0).collect();
        declared.sort_unstable();
        bound.sort_unstable();
        // The pyramid's further mips bind their own levels (no views in the plan).
        if !st.views.is_empty() {
            assert_eq!(declared, bound, "{}: bindings", st.pass.label());
        }
        for &(_, r) in &st.views {
            let base = match r {
                Res::PyramidMip(_) => Res::Pyramid,
                Res::MomentsMip(_) => Res::Moments,
                r => r.at_parity(0),
            };
            assert!(
                base == Res::Output || textures.contains(&base),
                "{:?} binds {r:?}, which the plan does not create",
                st.pass
            );
        }
    }
    let writers = p
        .steps
        .iter()
        .filter(|st| st.views.iter().any(|v| v.1 == Res::Output));
    assert_eq!(
        writers.count(),
        1,
        "one step writes the output: {:?}",
        labels(p)
    );
    // With a guard band the output step stores the viewport alone: there is no crop pass.
    assert!(
        p.output_crops(),
        "the output step cannot crop: {:?}",
        labels(p)
    );
    for r in textures {
        let s = p.spec(r, size).expect("every created texture has a spec");
        assert!(
            s.size.0 >= 1 && s.size.1 >= 1 && s.layers >= 1 && s.mips >= 1,
            "{s:?}"
        );
    }
}

#[test]
fn the_default_is_one_fused_pass_over_2x2_layers_then_the_denoiser() {
    let o = AoOptions::default();
    assert_eq!(
        (o.mode, o.denoise),
        (AoMode::Deinterleaved2, Denoise::Spatial)
    );
    let p = plan(o);
    assert_eq!(p.prepare_store, PrepareStore::Layers);
    // The AO pass stores its AO packed beside the geometry, and the denoiser's taps read
    // that alone.
    assert!(matches!(
        p.passes()[..],
        [
            Pass::AoLayered {
                merge: true,
                packed: true,
                ..
            },
            Pass::Denoise { bent: false }
        ]
    ));
    assert_eq!(p.textures(), vec![Res::PreparedLayers, Res::AoPacked]);
    let layers = p.spec(Res::PreparedLayers, [641, 400]).unwrap();
    assert_eq!((layers.size, layers.layers), ((321, 200), 4));
    assert_eq!(layers.format, PREPARED_FORMAT);
    let packed = p.spec(Res::AoPacked, [641, 400]).unwrap();
    assert_eq!((packed.size, packed.format), ((641, 400), AO_PACKED_FORMAT));
    assert_eq!(p.prepare_dispatch([641, 400]), Dispatch::Fixed([41, 25, 4]));
    check_consistent(&p, [641, 400]);
}

#[test]
fn each_layout_runs_its_own_passes() {
    let full = Resolution::Full;
    let randomized = plan(options(AoMode::Randomized, full, Denoise::None));
    assert_eq!(randomized.prepare_store, PrepareStore::Full);
    assert!(matches!(randomized.passes()[..], [Pass::AoFull { .. }]));
    assert_eq!(randomized.textures(), vec![Res::Prepared]);

    let four = plan(options(AoMode::Deinterleaved4, full, Denoise::Spatial));
    let layers = four.spec(Res::PreparedLayers, [640, 400]).unwrap();
    assert_eq!((layers.size, layers.layers), ((160, 100), 16));

    // Unfused and direct: the split, the AO over the layers and the interleave apart.
    let unfused = plan(AoOptions {
        fused: false,
        ..options(AoMode::Deinterleaved2, full, Denoise::None)
    });
    assert_eq!(unfused.prepare_store, PrepareStore::Full);
    assert!(matches!(
        unfused.passes()[..],
        [
            Pass::Deinterleave,
            Pass::AoLayered { merge: false, .. },
            Pass::Interleave
        ]
    ));
    assert!(unfused.textures().contains(&Res::AoLayers));
    for p in [&randomized, &four, &unfused] {
        check_consistent(p, [640, 400]);
    }
}

#[test]
fn below_full_resolution_the_prepare_pass_downsamples_and_an_upsampler_follows() {
    for (resolution, level) in [(Resolution::Half, 1), (Resolution::Quarter, 2)] {
        let p = plan(options(AoMode::Randomized, resolution, Denoise::Spatial));
        assert!(
            matches!(p.prepare_store, PrepareStore::Down { .. }),
            "{resolution:?}"
        );
        let last = p.steps.last().unwrap();
        assert!(matches!(last.pass, Pass::Upsample { .. }));
        assert_eq!(last.grid, Grid::Level(level));
        // Quarter resolution downsamples once more after the fused first level.
        let downsamples = p
            .steps
            .iter()
            .filter(|s| matches!(s.pass, Pass::Downsample { .. }))
            .count();
        assert_eq!(downsamples, level as usize - 1);
        let work = p.spec(Res::Level(level), [641, 401]).unwrap();
        let f = 1 << level;
        assert_eq!(work.size, (641u32.div_ceil(f), 401u32.div_ceil(f)));
        assert_eq!(p.spec(Res::AoWork, [641, 401]).unwrap().size, work.size);
        check_consistent(&p, [641, 401]);
    }
    // The bilateral upsampler reads full-resolution normals: the prepared buffer, not
    // linear depth alone.
    let bilateral = plan(AoOptions {
        upsample: Upsampler::Bilateral,
        ..options(AoMode::Randomized, Resolution::Half, Denoise::None)
    });
    assert!(bilateral.textures().contains(&Res::Prepared));
    assert!(!bilateral.textures().contains(&Res::LinearDepth));
}

#[test]
fn the_scaled_grid_rescales_then_upsamples_at_the_frame_scale() {
    let p = plan(options(
        AoMode::Randomized,
        Resolution::Scaled,
        Denoise::Spatial,
    ));
    let l = labels(&p);
    assert_eq!(l.first(), Some(&Pass::Rescale.label()));
    assert_eq!(l.last(), Some(&Pass::UpsampleScaled.label()));
    // The working grid changes every frame: its passes take their size from the frame.
    assert!(p
        .steps
        .iter()
        .any(|s| p.dispatch(s.grid, [640, 400]) == Dispatch::Work));
    // Created at full size; the frame uses its top-left `ceil(full × scale)` texels.
    assert_eq!(p.spec(Res::Scaled, [640, 400]).unwrap().size, (640, 400));
    check_consistent(&p, [640, 400]);
}

#[test]
fn history_adds_a_temporal_pass_and_two_textures_that_live_across_frames() {
    let still = plan(options(
        AoMode::Deinterleaved2,
        Resolution::Full,
        Denoise::Spatial,
    ));
    let o = AoOptions {
        history: 8,
        ..options(AoMode::Deinterleaved2, Resolution::Full, Denoise::Spatial)
    };
    let p = plan(o);
    assert_eq!(p.steps.len(), still.steps.len() + 1);
    assert!(matches!(p.steps[1].pass, Pass::Temporal { .. }));
    // The temporal pass reads the AO alone and packs what it accumulates for the denoiser.
    assert!(matches!(
        p.steps[0].pass,
        Pass::AoLayered { packed: false, .. }
    ));
    assert!(matches!(
        p.steps[1].pass,
        Pass::Temporal {
            layers: true,
            packed: true,
            ..
        }
    ));
    assert_eq!(p.steps[1].views[4], (5, Res::AoPacked));
    assert_eq!(p.steps[2].views[0], (2, Res::AoPacked));
    let across: Vec<Res> = p
        .textures()
        .into_iter()
        .filter(|&r| p.spec(r, [64, 64]).unwrap().lifetime == Lifetime::AcrossFrames)
        .collect();
    assert_eq!(across, vec![Res::History(0), Res::History(1)]);
    // The temporal pass reads one history and writes the other, alternating by frame.
    let views = &p.steps[1].views;
    assert!(views.contains(&(3, Res::HistoryPrev)) && views.contains(&(4, Res::HistoryNext)));
    assert_eq!(Res::HistoryPrev.at_parity(1), Res::HistoryNext.at_parity(0));
    check_consistent(&p, [64, 64]);
}

#[test]
fn extensions_add_their_passes_and_textures() {
    // Bent normals: through the temporal pass and the denoiser, ending in `Bent`.
    let bent = plan(AoOptions {
        bent_normals: true,
        history: 4,
        ..options(AoMode::Deinterleaved2, Resolution::Full, Denoise::Spatial)
    });
    for r in [
        Res::Bent,
        Res::BentRaw,
        Res::BentHistory(0),
        Res::BentHistory(1),
    ] {
        assert!(bent.textures().contains(&r), "{r:?}");
    }
    check_consistent(&bent, [100, 60]);
    // SAO reads the depth pyramid: its base pass, then one pass per further mip on a
    // CPU adapter, four mips a pass on a GPU.
    let sao = AoOptions {
        estimator: Estimator::Sao,
        ..options(AoMode::Randomized, Resolution::Full, Denoise::None)
    };
    let cpu = plan(sao);
    assert!(matches!(cpu.steps[0].pass, Pass::Pyramid { .. }));
    assert_eq!(cpu.steps[1].grid, Grid::PyramidMips);
    let pyramid = cpu.spec(Res::Pyramid, [640, 400]).unwrap();
    assert_eq!((pyramid.size, pyramid.mips), ((320, 200), 9));
    let gpu = Plan::new(&sao, crate::passes::constants::PYRAMID_LEVELS_PER_PASS);
    assert_eq!(gpu.steps[1].pass, Pass::PyramidLevels);
    check_consistent(&cpu, [640, 400]);
    // VO's area integral reads the moments pyramid instead.
    let area = plan(AoOptions {
        estimator: Estimator::VoArea,
        ..options(AoMode::Randomized, Resolution::Full, Denoise::None)
    });
    assert!(area.textures().contains(&Res::Moments));
    assert!(!area.textures().contains(&Res::Pyramid));
    // The box filter halves the AO before the upsampler.
    let boxed = plan(options(AoMode::Randomized, Resolution::Half, Denoise::Box));
    let half = boxed.spec(Res::AoHalf, [640, 400]).unwrap();
    assert_eq!((half.size, half.format), ((160, 100), AO_FORMAT));
    check_consistent(&boxed, [640, 400]);
}

#[test]
fn every_valid_option_set_gives_a_consistent_plan() {
    let mut n = 0;
    for mode in [
        AoMode::Randomized,
        AoMode::Deinterleaved2,
        AoMode::Deinterleaved4,
    ] {
        for resolution in [
            Resolution::Full,
            Resolution::Half,
            Resolution::Quarter,
            Resolution::Scaled,
        ] {
            for denoise in Denoise::ALL {
                for estimator in Estimator::ALL {
                    for (history, bent_normals, fused) in
                        [(0, false, true), (4, true, true), (0, false, false)]
                    {
                        let o = AoOptions {
                            estimator,
                            history,
                            bent_normals,
                            fused,
                            ..options(mode, resolution, denoise)
                        };
                        if o.validate().is_err() {
                            continue;
                        }
                        check_consistent(&plan(o), [97, 61]);
                        n += 1;
                    }
                }
            }
        }
    }
    assert!(n > 100, "only {n} valid option sets");
}
