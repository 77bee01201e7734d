//! The compute passes and how their WGSL is assembled. Every pass is the prelude, then
//! `common.wgsl`, then its own fragments: [`Pass`] names a pass and its label (here),
//! `fragments.rs` lists its WGSL fragments, `overrides.rs` its pipeline-overridable
//! constants, and `prelude.rs` the WGSL generated from Rust constants and
//! [`gpu_struct!`](crate::gpu_struct) declarations, the single source of truth for values
//! both sides use.

mod fragments;
mod overrides;
mod prelude;

pub use crate::passes::constants::*;
use crate::{DepthDownsample, Estimator, Upsampler};
pub(crate) use overrides::pattern_sector;
pub(crate) use prelude::create_module;
pub use prelude::{dispatch_size, prelude};

/// Where the first pyramid level reads linear depth from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PyramidSource {
    /// Full-resolution linear depth: `.x` of the prepared buffer, or the linear depth of
    /// [`PrepareStore::Down`].
    Full,
    /// The deinterleaved prepared layers (fused deinterleaved modes have no full buffer).
    Layers,
    /// The previous pyramid level (one level per pass).
    Mip,
}

/// Where the prepare pass writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrepareStore {
    /// The full-resolution prepared buffer.
    Full,
    /// Straight into the N×N deinterleaved layers (the split fused away).
    Layers,
    /// Half resolution by a depth rule, plus what the passes after the AO read at full
    /// resolution: the first downsampling fused away (passes/prepare/prepare_down.wgsl), for AO
    /// below full resolution. `normals`: the full-resolution output is `vec4(depth,
    /// normal)` (for the bilateral upsampler), else linear depth only.
    Down {
        rule: DepthDownsample,
        normals: bool,
    },
}

/// How the depth input is bound.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DepthBinding {
    /// A depth-format texture (`texture_depth_2d`).
    Depth,
    /// A float colour texture (`texture_2d<f32>`, e.g. linear view depth).
    Float,
}

/// The compute passes. Each is composed from WGSL fragments under `src/passes/` (one pass =
/// entry file + the fragments it names); [`Pass::label`] is its pipeline name and debug label.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pass {
    /// Linearize depth and build normals, stored as `store` says; `reconstruct`: normals
    /// from depth (else from the caller's texture); `fit`: depth and normals from plane
    /// fits for noisy depth (with `reconstruct`; [`crate::DepthNoise`]); `second_layer`:
    /// the caller's second depth layer linearised too (store `Full` or `Layers` only;
    /// [`crate::AoOptions::second_layer`]).
    Prepare {
        depth: DepthBinding,
        store: PrepareStore,
        reconstruct: bool,
        fit: bool,
        second_layer: bool,
    },
    /// The randomized single full-resolution AO pass; `bent`: bent normals written too
    /// (GTAO, HBAO and the bitmask); `second_layer`: the bitmask reads the second depth
    /// layer; `packed`: the AO stored beside its pixel's geometry ([`AO_PACKED_FORMAT`])
    /// for the spatial denoiser that follows.
    AoFull {
        estimator: Estimator,
        bent: bool,
        second_layer: bool,
        packed: bool,
    },
    /// AO over deinterleaved layers; `merge`: write full resolution directly (fused merge),
    /// else keep the result in layers for [`Pass::Interleave`]; `bent`, `second_layer` and
    /// `packed` (with `merge` only) as for [`Pass::AoFull`] (bent normals always written at
    /// full resolution).
    AoLayered {
        merge: bool,
        estimator: Estimator,
        bent: bool,
        second_layer: bool,
        packed: bool,
    },
    /// Full-resolution prepared buffer → layers (unfused split).
    Deinterleave,
    /// AO layers → full resolution (unfused merge).
    Interleave,
    /// One level of the min/max depth pyramid (also SAO's depth mips).
    Pyramid { source: PyramidSource },
    /// The next [`PYRAMID_LEVELS_PER_PASS`] levels of the pyramid from the one above.
    PyramidLevels,
    /// One level of the depth moments pyramid (VO's area integral), from linear depth or
    /// from the level above ([`PyramidSource::Mip`]).
    Moments { source: PyramidSource },
    /// Prepared buffer 2×2 → 1 by a depth rule.
    Downsample { rule: DepthDownsample, level: u32 },
    /// Full-resolution prepared buffer → the working grid of [`crate::Resolution::Scaled`]
    /// (any scale, by the depth rule of `AoOptions::downsample`; passes/pyramid/rescale.wgsl).
    Rescale,
    /// The working grid's AO → full resolution at any scale, joint bilateral weights
    /// (passes/upsample/upsample_scaled.wgsl).
    UpsampleScaled,
    /// Low-resolution AO → full resolution; `bent`: bent normals too, `full_normals`: the
    /// full-resolution input holds normals (see passes/upsample/upsample_bent.wgsl).
    Upsample {
        upsampler: Upsampler,
        bent: bool,
        full_normals: bool,
    },
    /// The edge-aware spatial denoiser, its taps read from the AO packed with its geometry
    /// ([`AO_PACKED_FORMAT`], one fetch each); `bent`: bent normals filtered too.
    Denoise { bent: bool },
    /// Temporal accumulation (history reprojection, rejection, clamp, blend); `bent`: bent
    /// normals accumulated too; `packed`: its AO stored packed with its geometry for the
    /// spatial denoiser that follows ([`AO_PACKED_FORMAT`]).
    Temporal {
        layers: bool,
        bent: bool,
        packed: bool,
    },
    /// AO 2×2 → 1 by seed 003's box or tent filter.
    AoDownsample { tent: bool },
    /// Multisampled depth → one raw depth per pixel (before [`Pass::Prepare`], which then
    /// reads it as a float input).
    ResolveDepth,
    /// Many-light diffuse shading of the prepared buffer: every light, or with an override
    /// `PERIOD` n > 1 each pixel class of an n × n tile a 1/n² subset ([`crate::lights`]);
    /// `layers`: the prepared buffer as the AO's N×N layers (fused deinterleaved modes).
    /// `packed`: writes [`LIT_PACKED_FORMAT`] for the merge, else [`LIT_FORMAT`].
    LightsShade { layers: bool, packed: bool },
    /// The geometry-aware merge of interleaved many-light shading over one period (also
    /// merges the SSDO bounce), along the override `AXIS`, from [`LIT_PACKED_FORMAT`];
    /// `packed_out`: writes [`LIT_PACKED_FORMAT`] (for the second axis), else [`LIT_FORMAT`].
    LightsMerge { packed_out: bool },
    /// One diffuse bounce of screen-space directional occlusion ([`crate::ssdo`]).
    /// `packed`: writes [`LIT_PACKED_FORMAT`] for the merge, else [`LIT_FORMAT`].
    SsdoBounce { layers: bool, packed: bool },
    /// SSDO's combine: albedo · (AO · environment at the bent normal + bounce).
    SsdoCombine { layers: bool },
}

impl Pass {
    /// Every pass variant, for validation tests.
    pub fn all() -> Vec<Pass> {
        let mut v = Vec::new();
        let stores = [PrepareStore::Full, PrepareStore::Layers]
            .into_iter()
            .chain(DepthDownsample::ALL.into_iter().flat_map(|rule| {
                [false, true].map(|normals| PrepareStore::Down { rule, normals })
            }));
        for depth in [DepthBinding::Depth, DepthBinding::Float] {
            for store in stores.clone() {
                for (reconstruct, fit) in [(false, false), (true, false), (true, true)] {
                    let seconds = match store {
                        PrepareStore::Full | PrepareStore::Layers => &[false, true][..],
                        PrepareStore::Down { .. } => &[false][..],
                    };
                    for &second_layer in seconds {
                        v.push(Pass::Prepare {
                            depth,
                            store,
                            reconstruct,
                            fit,
                            second_layer,
                        });
                    }
                }
            }
        }
        for estimator in Estimator::ALL {
            let bents = if estimator.has_bent_normals() {
                &[false, true][..]
            } else {
                &[false][..]
            };
            let seconds = if estimator == Estimator::Bitmask {
                &[false, true][..]
            } else {
                &[false][..]
            };
            for &bent in bents {
                for &second_layer in seconds {
                    for packed in [false, true] {
                        v.push(Pass::AoFull {
                            estimator,
                            bent,
                            second_layer,
                            packed,
                        });
                    }
                    for (merge, packed) in [(true, false), (true, true), (false, false)] {
                        v.push(Pass::AoLayered {
                            merge,
                            estimator,
                            bent,
                            second_layer,
                            packed,
                        });
                    }
                }
            }
        }
        v.extend([Pass::Deinterleave, Pass::Interleave, Pass::ResolveDepth]);
        for source in [
            PyramidSource::Full,
            PyramidSource::Layers,
            PyramidSource::Mip,
        ] {
            v.push(Pass::Pyramid { source });
            v.push(Pass::Moments { source });
        }
        v.extend([Pass::PyramidLevels, Pass::Rescale, Pass::UpsampleScaled]);
        v.extend(DepthDownsample::ALL.map(|rule| Pass::Downsample { rule, level: 1 }));
        for upsampler in Upsampler::ALL {
            for (bent, full_normals) in [(false, true), (true, true), (true, false)] {
                v.push(Pass::Upsample {
                    upsampler,
                    bent,
                    full_normals,
                });
            }
        }
        for b in [false, true] {
            v.extend([Pass::Denoise { bent: b }, Pass::AoDownsample { tent: b }]);
            for layers in [false, true] {
                for packed in [false, true] {
                    v.push(Pass::Temporal {
                        layers,
                        bent: b,
                        packed,
                    });
                }
            }
        }
        for layers in [false, true] {
            v.extend([
                Pass::LightsShade {
                    layers,
                    packed: false,
                },
                Pass::LightsShade {
                    layers,
                    packed: true,
                },
                Pass::LightsMerge { packed_out: layers },
                Pass::SsdoBounce {
                    layers,
                    packed: false,
                },
                Pass::SsdoBounce {
                    layers,
                    packed: true,
                },
                Pass::SsdoCombine { layers },
            ]);
        }
        v
    }

    /// Whether the pass stores through output.wgsl, so that as a frame's output step with
    /// a guard band it stores the viewport alone (override `CROPS`).
    pub fn crops_output(self) -> bool {
        matches!(
            self,
            Pass::AoFull { .. }
                | Pass::AoLayered { merge: true, .. }
                | Pass::Interleave
                | Pass::Denoise { .. }
                | Pass::Temporal { .. }
                | Pass::Upsample { .. }
                | Pass::UpsampleScaled
        )
    }

    /// The pass's label.
    pub fn label(self) -> &'static str {
        match self {
            Pass::Prepare {
                depth,
                store,
                second_layer,
                ..
            } => {
                let depth = (depth == DepthBinding::Float) as usize + 2 * second_layer as usize;
                match store {
                    PrepareStore::Full => [
                        "prepare_depth",
                        "prepare_float",
                        "prepare_depth_second",
                        "prepare_float_second",
                    ][depth],
                    PrepareStore::Layers => [
                        "prepare_depth_split",
                        "prepare_float_split",
                        "prepare_depth_second_split",
                        "prepare_float_second_split",
                    ][depth],
                    PrepareStore::Down { .. } => {
                        ["prepare_depth_down", "prepare_float_down"][depth]
                    }
                }
            }
            Pass::AoFull {
                estimator,
                bent,
                second_layer,
                packed,
            } => ao_label(estimator, 3 * packed as usize, bent, second_layer),
            Pass::AoLayered {
                merge,
                estimator,
                bent,
                second_layer,
                packed,
            } => {
                let kind = if packed { 4 } else { 2 - merge as usize };
                ao_label(estimator, kind, bent, second_layer)
            }
            Pass::Deinterleave => "deinterleave",
            Pass::Interleave => "interleave",
            Pass::Pyramid { source } => match source {
                PyramidSource::Full => "pyramid_from_full",
                PyramidSource::Layers => "pyramid_from_layers",
                PyramidSource::Mip => "pyramid",
            },
            Pass::PyramidLevels => "pyramid_levels",
            Pass::Moments { source } => match source {
                PyramidSource::Full => "moments_from_full",
                PyramidSource::Layers => "moments_from_layers",
                PyramidSource::Mip => "moments",
            },
            Pass::Downsample { rule, .. } => match rule {
                DepthDownsample::Max => "downsample_max",
                DepthDownsample::Min => "downsample_min",
                DepthDownsample::Checkerboard => "downsample_checkerboard",
                DepthDownsample::Representative => "downsample_representative",
            },
            Pass::Rescale => "rescale",
            Pass::UpsampleScaled => "upsample_scaled",
            Pass::Upsample {
                upsampler, bent, ..
            } => {
                let names = match upsampler {
                    Upsampler::Bilinear => ["upsample_bilinear", "upsample_bilinear_bent"],
                    Upsampler::NearestDepth => {
                        ["upsample_nearest_depth", "upsample_nearest_depth_bent"]
                    }
                    Upsampler::Classified => ["upsample_classified", "upsample_classified_bent"],
                    Upsampler::Bilateral => ["upsample_bilateral", "upsample_bilateral_bent"],
                };
                names[bent as usize]
            }
            Pass::Denoise { bent } => ["denoise", "denoise_bent"][bent as usize],
            Pass::Temporal {
                layers,
                bent,
                packed,
            } => [
                "temporal",
                "temporal_from_layers",
                "temporal_packed",
                "temporal_from_layers_packed",
                "temporal_bent",
                "temporal_bent_from_layers",
                "temporal_bent_packed",
                "temporal_bent_from_layers_packed",
            ][layers as usize + 2 * packed as usize + 4 * bent as usize],
            Pass::AoDownsample { tent: false } => "ao_downsample_box",
            Pass::AoDownsample { tent: true } => "ao_downsample_tent",
            Pass::ResolveDepth => "resolve_depth",
            Pass::LightsShade { layers, packed } => [
                "lights_shade",
                "lights_shade_from_layers",
                "lights_shade_packed",
                "lights_shade_packed_from_layers",
            ][layers as usize + 2 * packed as usize],
            Pass::LightsMerge { packed_out } => {
                ["lights_merge", "lights_merge_to_packed"][packed_out as usize]
            }
            Pass::SsdoBounce { layers, packed } => [
                "ssdo_bounce",
                "ssdo_bounce_from_layers",
                "ssdo_bounce_packed",
                "ssdo_bounce_packed_from_layers",
            ][layers as usize + 2 * packed as usize],
            Pass::SsdoCombine { layers } => {
                ["ssdo_combine", "ssdo_combine_from_layers"][layers as usize]
            }
        }
    }
}

/// The five labels of one AO pass's base name, in [`ao_label`]'s `kind` order.
macro_rules! ao_names {
    ($base:literal) => {
        [
            $base,
            concat!($base, "_layers_merge"),
            concat!($base, "_layers"),
            concat!($base, "_packed"),
            concat!($base, "_layers_packed"),
        ]
    };
}

/// Labels of the AO passes: `kind` 0 = full resolution, 1 = layers with fused merge,
/// 2 = layers kept for the interleave pass, 3 = full resolution packed for the denoiser,
/// 4 = layers merged and packed; `bent`: with bent normals (GTAO, HBAO, bitmask);
/// `second`: reading a second depth layer (the bitmask).
fn ao_label(e: Estimator, kind: usize, bent: bool, second: bool) -> &'static str {
    let names: [&'static str; 5] = match (e, bent, second) {
        (_, true, true) => ao_names!("bitmask_second_bent"),
        (_, false, true) => ao_names!("bitmask_second"),
        (Estimator::Hbao, true, _) => ao_names!("hbao_bent"),
        (Estimator::Bitmask, true, _) => ao_names!("bitmask_bent"),
        (_, true, _) => ao_names!("gtao_bent"),
        (Estimator::Hbao, ..) => ao_names!("hbao"),
        (Estimator::Gtao, ..) => ao_names!("gtao"),
        (Estimator::Vo, ..) => ao_names!("vo"),
        (Estimator::Vao, ..) => ao_names!("vao"),
        (Estimator::Sao, ..) => ao_names!("sao"),
        (Estimator::VoArea, ..) => ao_names!("vo_area"),
        (Estimator::Bitmask, ..) => ao_names!("bitmask"),
    };
    names[kind]
}
