//! Each pass's WGSL fragments, in the order they follow the prelude and common.wgsl.

use super::{prelude, DepthBinding, Pass, PrepareStore, PyramidSource};
use crate::{Estimator, Upsampler};

impl Pass {
    /// The WGSL fragments of the pass, in order (after the prelude and common.wgsl).
    fn fragments(self) -> Vec<&'static str> {
        let estimator_source = |e: Estimator| match e {
            Estimator::Hbao => include_str!("../estimators/hbao.wgsl"),
            Estimator::Gtao => concat!(
                include_str!("../estimators/gtao_arcs.wgsl"),
                "\n",
                include_str!("../estimators/gtao.wgsl")
            ),
            Estimator::Vo | Estimator::Vao | Estimator::VoArea => {
                include_str!("../estimators/sphere.wgsl")
            }
            Estimator::Sao => include_str!("../estimators/sao.wgsl"),
            Estimator::Bitmask => concat!(
                include_str!("../estimators/gtao_arcs.wgsl"),
                "\n",
                include_str!("../estimators/bitmask.wgsl")
            ),
        };
        // How sphere.wgsl reads a chord: one depth (VO, VAO) or a texel's depth moments
        // (VO's area integral).
        let sphere_chord = |e: Estimator| match e {
            Estimator::Vo | Estimator::Vao => Some(include_str!("../estimators/sphere_line.wgsl")),
            Estimator::VoArea => Some(include_str!("../estimators/sphere_area.wgsl")),
            _ => None,
        };
        const STORE_PREPARED_FULL: &str = include_str!("../prepare/prepare_store_full.wgsl");
        const STORE_PREPARED_LAYERS: &str = include_str!("../prepare/prepare_store_layers.wgsl");
        // The output's store (CROPS), in every pass that can write the output; the AO
        // passes and the unfused merge reach it through STORE_AO_FULL.
        const OUTPUT: &str = include_str!("../output.wgsl");
        const STORE_AO_FULL: &str = concat!(
            include_str!("../output.wgsl"),
            "\n",
            include_str!("../estimators/ao_store_full.wgsl")
        );
        const STORE_AO_LAYERS: &str = include_str!("../estimators/ao_store_layers.wgsl");
        const STORE_AO_PACKED: &str = concat!(
            include_str!("../estimators/ao_packed.wgsl"),
            "\n",
            include_str!("../estimators/ao_store_packed.wgsl")
        );
        let store_ao_full = |packed: bool| {
            if packed {
                STORE_AO_PACKED
            } else {
                STORE_AO_FULL
            }
        };
        const PREPARE: &str = include_str!("../prepare/prepare.wgsl");
        const DOWNSAMPLE_RULE: &str = include_str!("../pyramid/downsample_rule.wgsl");
        const UPSAMPLE_FOOTPRINT: &str = include_str!("../upsample/upsample_footprint.wgsl");
        const UPSAMPLE_BILATERAL: &str = include_str!("../upsample/upsample_bilateral.wgsl");
        // The depth source fragment of the pyramid and moments passes.
        let pyramid_source = |source: PyramidSource| match source {
            PyramidSource::Full => include_str!("../pyramid/pyramid_from_full.wgsl"),
            PyramidSource::Layers => include_str!("../pyramid/pyramid_from_layers.wgsl"),
            PyramidSource::Mip => include_str!("../pyramid/pyramid_from_mip.wgsl"),
        };
        // The bitmask's second depth layer, or its empty interface.
        let second_source = |e: Estimator, second: bool| {
            (e == Estimator::Bitmask).then_some(if second {
                include_str!("../estimators/second_layer.wgsl")
            } else {
                include_str!("../estimators/second_layer_none.wgsl")
            })
        };
        let prepared_source = |layers: bool| {
            if layers {
                include_str!("../prepared_layers.wgsl")
            } else {
                include_str!("../prepared_full.wgsl")
            }
        };
        match self {
            Pass::Prepare {
                depth,
                store,
                reconstruct,
                fit,
                second_layer,
            } => {
                let mut v = vec![
                    match depth {
                        DepthBinding::Depth => include_str!("../prepare/depth_input_depth.wgsl"),
                        DepthBinding::Float => include_str!("../prepare/depth_input_float.wgsl"),
                    },
                    include_str!("../prepare/prepare_input.wgsl"),
                    if reconstruct {
                        include_str!("../prepare/normals_reconstruct.wgsl")
                    } else {
                        include_str!("../prepare/normals_given.wgsl")
                    },
                    if fit {
                        include_str!("../prepare/normals_fit.wgsl")
                    } else {
                        include_str!("../ssdo/surface_plain.wgsl")
                    },
                ];
                v.extend(match store {
                    PrepareStore::Full => [STORE_PREPARED_FULL, PREPARE],
                    PrepareStore::Layers => [STORE_PREPARED_LAYERS, PREPARE],
                    PrepareStore::Down { normals, .. } => [
                        DOWNSAMPLE_RULE,
                        if normals {
                            include_str!("../prepare/prepare_down_prepared.wgsl")
                        } else {
                            include_str!("../prepare/prepare_down_depth.wgsl")
                        },
                    ],
                });
                match (store, second_layer, depth) {
                    (PrepareStore::Down { .. }, ..) => {
                        v.push(include_str!("../prepare/prepare_down.wgsl"))
                    }
                    (_, false, _) => v.insert(
                        v.len() - 1,
                        include_str!("../prepare/prepare_second_none.wgsl"),
                    ),
                    (_, true, depth) => {
                        let input = match depth {
                            DepthBinding::Depth => {
                                include_str!("../prepare/second_input_depth.wgsl")
                            }
                            DepthBinding::Float => {
                                include_str!("../prepare/second_input_float.wgsl")
                            }
                        };
                        let at = v.len() - 1;
                        v.splice(
                            at..at,
                            [input, include_str!("../prepare/prepare_second.wgsl")],
                        );
                    }
                }
                v
            }
            Pass::AoFull {
                estimator,
                bent,
                second_layer,
                packed,
            } => sphere_chord(estimator)
                .into_iter()
                .chain(second_source(estimator, second_layer))
                .chain([
                    estimator_source(estimator),
                    store_ao_full(packed),
                    ao_bent(bent),
                    include_str!("../estimators/ao_full.wgsl"),
                ])
                .collect(),
            Pass::AoLayered {
                merge,
                estimator,
                bent,
                second_layer,
                packed,
            } => sphere_chord(estimator)
                .into_iter()
                .chain(second_source(estimator, second_layer))
                .chain([
                    estimator_source(estimator),
                    if merge {
                        store_ao_full(packed)
                    } else {
                        STORE_AO_LAYERS
                    },
                    ao_bent(bent),
                    include_str!("../estimators/ao_layered.wgsl"),
                ])
                .collect(),
            Pass::Deinterleave => vec![
                STORE_PREPARED_LAYERS,
                include_str!("../layers/deinterleave.wgsl"),
            ],
            Pass::Interleave => vec![STORE_AO_FULL, include_str!("../layers/interleave.wgsl")],
            Pass::Pyramid { source } => {
                vec![
                    pyramid_source(source),
                    include_str!("../pyramid/pyramid.wgsl"),
                ]
            }
            Pass::PyramidLevels => vec![include_str!("../pyramid/pyramid_levels.wgsl")],
            Pass::Moments { source } => {
                vec![
                    pyramid_source(source),
                    include_str!("../pyramid/moments.wgsl"),
                ]
            }
            Pass::Downsample { .. } => {
                vec![DOWNSAMPLE_RULE, include_str!("../pyramid/downsample.wgsl")]
            }
            Pass::Upsample {
                upsampler, bent, ..
            } => vec![
                if bent {
                    include_str!("../upsample/upsample_bent.wgsl")
                } else {
                    include_str!("../upsample/upsample_bent_none.wgsl")
                },
                UPSAMPLE_FOOTPRINT,
                OUTPUT,
                include_str!("../upsample/upsample.wgsl"),
                match upsampler {
                    Upsampler::Bilinear => include_str!("../upsample/upsample_bilinear.wgsl"),
                    Upsampler::NearestDepth => include_str!("../upsample/upsample_nearest.wgsl"),
                    Upsampler::Classified => include_str!("../upsample/upsample_classified.wgsl"),
                    Upsampler::Bilateral => UPSAMPLE_BILATERAL,
                },
            ],
            Pass::Rescale => vec![DOWNSAMPLE_RULE, include_str!("../pyramid/rescale.wgsl")],
            Pass::UpsampleScaled => vec![
                include_str!("../upsample/upsample_bent_none.wgsl"),
                UPSAMPLE_FOOTPRINT,
                OUTPUT,
                include_str!("../upsample/upsample_scaled.wgsl"),
                UPSAMPLE_BILATERAL,
            ],
            Pass::Denoise { bent } => vec![
                include_str!("../estimators/ao_packed.wgsl"),
                include_str!("../denoise/merge.wgsl"),
                if bent {
                    include_str!("../denoise/denoise_bent.wgsl")
                } else {
                    include_str!("../denoise/denoise_bent_none.wgsl")
                },
                OUTPUT,
                include_str!("../denoise/denoise.wgsl"),
            ],
            Pass::Temporal {
                layers,
                bent,
                packed,
            } => {
                let (store, out) = if packed {
                    (
                        include_str!("../estimators/ao_packed.wgsl"),
                        include_str!("../temporal/temporal_out_packed.wgsl"),
                    )
                } else {
                    (OUTPUT, include_str!("../temporal/temporal_out_plain.wgsl"))
                };
                vec![
                    prepared_source(layers),
                    if bent {
                        include_str!("../temporal/temporal_bent.wgsl")
                    } else {
                        include_str!("../temporal/temporal_bent_none.wgsl")
                    },
                    store,
                    out,
                    include_str!("../temporal/temporal.wgsl"),
                ]
            }
            Pass::AoDownsample { .. } => vec![include_str!("../denoise/ao_downsample.wgsl")],
            Pass::ResolveDepth => vec![include_str!("../prepare/resolve_depth.wgsl")],
            Pass::LightsShade { layers, packed } => [
                &[prepared_source(layers)][..],
                &lit_out(false, packed)[..],
                &[include_str!("../lights/lights_shade.wgsl")][..],
            ]
            .concat(),
            Pass::LightsMerge { packed_out } => [
                &lit_out(true, packed_out)[..],
                &[
                    include_str!("../denoise/merge.wgsl"),
                    include_str!("../lights/lights_merge.wgsl"),
                ][..],
            ]
            .concat(),
            Pass::SsdoBounce { layers, packed } => [
                &[
                    prepared_source(layers),
                    include_str!("../estimators/gtao_arcs.wgsl"),
                    include_str!("../ssdo/ssdo_env.wgsl"),
                ][..],
                &lit_out(false, packed)[..],
                &[include_str!("../ssdo/ssdo_bounce.wgsl")][..],
            ]
            .concat(),
            Pass::SsdoCombine { layers } => vec![
                prepared_source(layers),
                include_str!("../ssdo/ssdo_env.wgsl"),
                include_str!("../ssdo/ssdo_combine.wgsl"),
            ],
        }
    }

    /// The complete WGSL source of the pass.
    pub fn source(self) -> String {
        let mut s = prelude();
        s.push('\n');
        s.push_str(include_str!("../common.wgsl"));
        for f in self.fragments() {
            s.push('\n');
            s.push_str(f);
        }
        s
    }
}

/// The many-light passes' output fragment, packed or plain irradiance, after the packing
/// functions where the pass reads (`packed_in`) or writes packed texels.
fn lit_out(packed_in: bool, packed: bool) -> Vec<&'static str> {
    let mut v = Vec::new();
    if packed_in || packed {
        v.push(include_str!("../lights/lit_packed.wgsl"));
    }
    v.push(if packed {
        include_str!("../lights/lit_out_packed.wgsl")
    } else {
        include_str!("../lights/lit_out_plain.wgsl")
    });
    v
}

/// The AO pass's bent-normal fragment: stored, or the empty interface.
fn ao_bent(bent: bool) -> &'static str {
    if bent {
        include_str!("../estimators/ao_bent.wgsl")
    } else {
        include_str!("../estimators/ao_bent_none.wgsl")
    }
}
