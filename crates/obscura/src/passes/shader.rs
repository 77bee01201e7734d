//! WGSL source assembly. Every pass is `prelude + common.wgsl + <pass>.wgsl`, where the
//! prelude is generated here from Rust constants and [`gpu_struct!`](crate::gpu_struct)
//! declarations: the single source of truth for values both sides use.

pub use crate::passes::constants::*;
use crate::passes::jitter::{PATTERN_COUNT, PATTERN_DIM};
use crate::passes::lights::{GpuLight, LightsUniforms};
use crate::passes::ssdo::SsdoUniforms;
use crate::passes::uniforms::FrameUniforms;
use crate::{DepthDownsample, Estimator, Upsampler};

/// Compiles one of obscura's WGSL passes without wgpu's loop-bounding guard.
///
/// wgpu adds a counter to every shader loop by default (`force_loop_bounding`) so that an
/// infinite loop cannot become undefined behaviour in the driver's compiler. The counter
/// costs an increment and a branch per iteration, and it stops the driver from unrolling
/// constant-trip loops: on lavapipe the GTAO pass ran 13% slower with it
/// (BENCHMARKS.md, "Shader loops without wgpu's bound"). Every loop in obscura's passes
/// is a counted `for` whose counter moves monotonically toward a bound it cannot step
/// over, and the test `every_shader_loop_is_counted` (tests/gpu/shaders.rs) checks that
/// form in every file, so the guard has nothing to guard. Every other runtime check
/// (bounds checks, integer-division guards) stays on.
pub(crate) fn create_module(
    device: &wgpu::Device,
    label: Option<&str>,
    source: String,
) -> wgpu::ShaderModule {
    let mut checks = wgpu::ShaderRuntimeChecks::checked();
    checks.force_loop_bounding = false;
    // SAFETY: `force_loop_bounding = false` requires that no shader loops forever. The
    // sources are obscura's own passes, whose loops are all counted (see above, and the
    // test that enforces it); only this crate calls this function.
    #[allow(unsafe_code)]
    unsafe {
        device.create_shader_module_trusted(
            wgpu::ShaderModuleDescriptor {
                label,
                source: wgpu::ShaderSource::Wgsl(source.into()),
            },
            checks,
        )
    }
}

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
    /// layer.
    AoFull {
        estimator: Estimator,
        bent: bool,
        second_layer: bool,
    },
    /// AO over deinterleaved layers; `merge`: write full resolution directly (fused merge),
    /// else keep the result in layers for [`Pass::Interleave`]; `bent` and `second_layer`
    /// as for [`Pass::AoFull`] (bent normals always written at full resolution).
    AoLayered {
        merge: bool,
        estimator: Estimator,
        bent: bool,
        second_layer: bool,
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
    /// The edge-aware spatial denoiser; `layers`: the prepared source is the deinterleaved
    /// layers (fused deinterleaved modes); `bent`: bent normals filtered too.
    Denoise { layers: bool, bent: bool },
    /// Temporal accumulation (history reprojection, rejection, clamp, blend); `bent`: bent
    /// normals accumulated too.
    Temporal { layers: bool, bent: bool },
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
                    v.push(Pass::AoFull {
                        estimator,
                        bent,
                        second_layer,
                    });
                    for merge in [true, false] {
                        v.push(Pass::AoLayered {
                            merge,
                            estimator,
                            bent,
                            second_layer,
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
            v.extend([
                Pass::Denoise {
                    layers: b,
                    bent: false,
                },
                Pass::Denoise {
                    layers: b,
                    bent: true,
                },
                Pass::Temporal {
                    layers: b,
                    bent: false,
                },
                Pass::Temporal {
                    layers: b,
                    bent: true,
                },
                Pass::AoDownsample { tent: b },
            ]);
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
            } => ao_label(estimator, 0, bent, second_layer),
            Pass::AoLayered {
                merge,
                estimator,
                bent,
                second_layer,
            } => ao_label(estimator, 2 - merge as usize, bent, second_layer),
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
            Pass::Denoise { layers, bent } => [
                "denoise",
                "denoise_from_layers",
                "denoise_bent",
                "denoise_bent_from_layers",
            ][layers as usize + 2 * bent as usize],
            Pass::Temporal { layers, bent } => [
                "temporal",
                "temporal_from_layers",
                "temporal_bent",
                "temporal_bent_from_layers",
            ][layers as usize + 2 * bent as usize],
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

    /// The WGSL fragments of the pass, in order (after the prelude and common.wgsl).
    fn fragments(self) -> Vec<&'static str> {
        let estimator_source = |e: Estimator| match e {
            Estimator::Hbao => include_str!("estimators/hbao.wgsl"),
            Estimator::Gtao => concat!(
                include_str!("estimators/gtao_arcs.wgsl"),
                "\n",
                include_str!("estimators/gtao.wgsl")
            ),
            Estimator::Vo | Estimator::Vao | Estimator::VoArea => {
                include_str!("estimators/sphere.wgsl")
            }
            Estimator::Sao => include_str!("estimators/sao.wgsl"),
            Estimator::Bitmask => concat!(
                include_str!("estimators/gtao_arcs.wgsl"),
                "\n",
                include_str!("estimators/bitmask.wgsl")
            ),
        };
        // How sphere.wgsl reads a chord: one depth (VO, VAO) or a texel's depth moments
        // (VO's area integral).
        let sphere_chord = |e: Estimator| match e {
            Estimator::Vo | Estimator::Vao => Some(include_str!("estimators/sphere_line.wgsl")),
            Estimator::VoArea => Some(include_str!("estimators/sphere_area.wgsl")),
            _ => None,
        };
        const STORE_PREPARED_FULL: &str = include_str!("prepare/prepare_store_full.wgsl");
        const STORE_PREPARED_LAYERS: &str = include_str!("prepare/prepare_store_layers.wgsl");
        // The output's store (CROPS), in every pass that can write the output; the AO
        // passes and the unfused merge reach it through STORE_AO_FULL.
        const OUTPUT: &str = include_str!("output.wgsl");
        const STORE_AO_FULL: &str = concat!(
            include_str!("output.wgsl"),
            "\n",
            include_str!("estimators/ao_store_full.wgsl")
        );
        const STORE_AO_LAYERS: &str = include_str!("estimators/ao_store_layers.wgsl");
        const PREPARE: &str = include_str!("prepare/prepare.wgsl");
        const DOWNSAMPLE_RULE: &str = include_str!("pyramid/downsample_rule.wgsl");
        const UPSAMPLE_FOOTPRINT: &str = include_str!("upsample/upsample_footprint.wgsl");
        const UPSAMPLE_BILATERAL: &str = include_str!("upsample/upsample_bilateral.wgsl");
        // The depth source fragment of the pyramid and moments passes.
        let pyramid_source = |source: PyramidSource| match source {
            PyramidSource::Full => include_str!("pyramid/pyramid_from_full.wgsl"),
            PyramidSource::Layers => include_str!("pyramid/pyramid_from_layers.wgsl"),
            PyramidSource::Mip => include_str!("pyramid/pyramid_from_mip.wgsl"),
        };
        // The bitmask's second depth layer, or its empty interface.
        let second_source = |e: Estimator, second: bool| {
            (e == Estimator::Bitmask).then_some(if second {
                include_str!("estimators/second_layer.wgsl")
            } else {
                include_str!("estimators/second_layer_none.wgsl")
            })
        };
        let prepared_source = |layers: bool| {
            if layers {
                include_str!("prepared_layers.wgsl")
            } else {
                include_str!("prepared_full.wgsl")
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
                        DepthBinding::Depth => include_str!("prepare/depth_input_depth.wgsl"),
                        DepthBinding::Float => include_str!("prepare/depth_input_float.wgsl"),
                    },
                    include_str!("prepare/prepare_input.wgsl"),
                    if reconstruct {
                        include_str!("prepare/normals_reconstruct.wgsl")
                    } else {
                        include_str!("prepare/normals_given.wgsl")
                    },
                    if fit {
                        include_str!("prepare/normals_fit.wgsl")
                    } else {
                        include_str!("ssdo/surface_plain.wgsl")
                    },
                ];
                v.extend(match store {
                    PrepareStore::Full => [STORE_PREPARED_FULL, PREPARE],
                    PrepareStore::Layers => [STORE_PREPARED_LAYERS, PREPARE],
                    PrepareStore::Down { normals, .. } => [
                        DOWNSAMPLE_RULE,
                        if normals {
                            include_str!("prepare/prepare_down_prepared.wgsl")
                        } else {
                            include_str!("prepare/prepare_down_depth.wgsl")
                        },
                    ],
                });
                match (store, second_layer, depth) {
                    (PrepareStore::Down { .. }, ..) => {
                        v.push(include_str!("prepare/prepare_down.wgsl"))
                    }
                    (_, false, _) => v.insert(
                        v.len() - 1,
                        include_str!("prepare/prepare_second_none.wgsl"),
                    ),
                    (_, true, depth) => {
                        let input = match depth {
                            DepthBinding::Depth => include_str!("prepare/second_input_depth.wgsl"),
                            DepthBinding::Float => include_str!("prepare/second_input_float.wgsl"),
                        };
                        let at = v.len() - 1;
                        v.splice(at..at, [input, include_str!("prepare/prepare_second.wgsl")]);
                    }
                }
                v
            }
            Pass::AoFull {
                estimator,
                bent,
                second_layer,
            } => sphere_chord(estimator)
                .into_iter()
                .chain(second_source(estimator, second_layer))
                .chain([
                    estimator_source(estimator),
                    STORE_AO_FULL,
                    ao_bent(bent),
                    include_str!("estimators/ao_full.wgsl"),
                ])
                .collect(),
            Pass::AoLayered {
                merge,
                estimator,
                bent,
                second_layer,
            } => sphere_chord(estimator)
                .into_iter()
                .chain(second_source(estimator, second_layer))
                .chain([
                    estimator_source(estimator),
                    if merge {
                        STORE_AO_FULL
                    } else {
                        STORE_AO_LAYERS
                    },
                    ao_bent(bent),
                    include_str!("estimators/ao_layered.wgsl"),
                ])
                .collect(),
            Pass::Deinterleave => vec![
                STORE_PREPARED_LAYERS,
                include_str!("layers/deinterleave.wgsl"),
            ],
            Pass::Interleave => vec![STORE_AO_FULL, include_str!("layers/interleave.wgsl")],
            Pass::Pyramid { source } => {
                vec![pyramid_source(source), include_str!("pyramid/pyramid.wgsl")]
            }
            Pass::PyramidLevels => vec![include_str!("pyramid/pyramid_levels.wgsl")],
            Pass::Moments { source } => {
                vec![pyramid_source(source), include_str!("pyramid/moments.wgsl")]
            }
            Pass::Downsample { .. } => {
                vec![DOWNSAMPLE_RULE, include_str!("pyramid/downsample.wgsl")]
            }
            Pass::Upsample {
                upsampler, bent, ..
            } => vec![
                if bent {
                    include_str!("upsample/upsample_bent.wgsl")
                } else {
                    include_str!("upsample/upsample_bent_none.wgsl")
                },
                UPSAMPLE_FOOTPRINT,
                OUTPUT,
                include_str!("upsample/upsample.wgsl"),
                match upsampler {
                    Upsampler::Bilinear => include_str!("upsample/upsample_bilinear.wgsl"),
                    Upsampler::NearestDepth => include_str!("upsample/upsample_nearest.wgsl"),
                    Upsampler::Classified => include_str!("upsample/upsample_classified.wgsl"),
                    Upsampler::Bilateral => UPSAMPLE_BILATERAL,
                },
            ],
            Pass::Rescale => vec![DOWNSAMPLE_RULE, include_str!("pyramid/rescale.wgsl")],
            Pass::UpsampleScaled => vec![
                include_str!("upsample/upsample_bent_none.wgsl"),
                UPSAMPLE_FOOTPRINT,
                OUTPUT,
                include_str!("upsample/upsample_scaled.wgsl"),
                UPSAMPLE_BILATERAL,
            ],
            Pass::Denoise { layers, bent } => {
                vec![
                    prepared_source(layers),
                    include_str!("denoise/merge.wgsl"),
                    if bent {
                        include_str!("denoise/denoise_bent.wgsl")
                    } else {
                        include_str!("denoise/denoise_bent_none.wgsl")
                    },
                    OUTPUT,
                    include_str!("denoise/denoise.wgsl"),
                ]
            }
            Pass::Temporal { layers, bent } => {
                vec![
                    prepared_source(layers),
                    if bent {
                        include_str!("temporal/temporal_bent.wgsl")
                    } else {
                        include_str!("temporal/temporal_bent_none.wgsl")
                    },
                    OUTPUT,
                    include_str!("temporal/temporal.wgsl"),
                ]
            }
            Pass::AoDownsample { .. } => vec![include_str!("denoise/ao_downsample.wgsl")],
            Pass::ResolveDepth => vec![include_str!("prepare/resolve_depth.wgsl")],
            Pass::LightsShade { layers, packed } => [
                &[prepared_source(layers)][..],
                &lit_out(false, packed)[..],
                &[include_str!("lights/lights_shade.wgsl")][..],
            ]
            .concat(),
            Pass::LightsMerge { packed_out } => [
                &lit_out(true, packed_out)[..],
                &[
                    include_str!("denoise/merge.wgsl"),
                    include_str!("lights/lights_merge.wgsl"),
                ][..],
            ]
            .concat(),
            Pass::SsdoBounce { layers, packed } => [
                &[
                    prepared_source(layers),
                    include_str!("estimators/gtao_arcs.wgsl"),
                    include_str!("ssdo/ssdo_env.wgsl"),
                ][..],
                &lit_out(false, packed)[..],
                &[include_str!("ssdo/ssdo_bounce.wgsl")][..],
            ]
            .concat(),
            Pass::SsdoCombine { layers } => vec![
                prepared_source(layers),
                include_str!("ssdo/ssdo_env.wgsl"),
                include_str!("ssdo/ssdo_combine.wgsl"),
            ],
        }
    }

    /// The complete WGSL source of the pass.
    pub fn source(self) -> String {
        let mut s = prelude();
        s.push('\n');
        s.push_str(include_str!("common.wgsl"));
        for f in self.fragments() {
            s.push('\n');
            s.push_str(f);
        }
        s
    }

    /// The pipeline-overridable constants this pass declares, valued from `options`.
    pub fn constants(self, options: &crate::AoOptions) -> Vec<(&'static str, f64)> {
        let split = ("SPLIT", options.mode.split() as f64);
        // The AO pass skips a guard band beyond GUARD_AO_MARGIN, but for a history.
        let skip_band = ("SKIP_BAND", (options.history == 0) as u32 as f64);
        let estimator = [
            ("DIRECTIONS", options.directions as f64),
            ("STEPS", options.steps as f64),
        ];
        // Each estimator's own: sphere.wgsl serves VO and its area integral (sphere on the
        // surface) and VAO (sphere offset R/2); GTAO and the bitmask march.
        let own = |e: Estimator| match e {
            Estimator::Vo => vec![("SPHERE_OFFSET", 0.0)],
            Estimator::Vao => vec![("SPHERE_OFFSET", 0.5)],
            Estimator::VoArea => vec![("SPHERE_OFFSET", 0.0)],
            Estimator::Gtao | Estimator::Bitmask => {
                vec![("MARCH_EXPONENT", options.march_exponent as f64)]
            }
            _ => vec![],
        };
        let rule = |rule: DepthDownsample, level: u32| {
            vec![
                (
                    "RULE",
                    match rule {
                        DepthDownsample::Max => 0.0,
                        DepthDownsample::Min => 1.0,
                        DepthDownsample::Checkerboard => 2.0,
                        DepthDownsample::Representative => 3.0,
                    },
                ),
                ("LEVEL", level as f64),
                ("RECENTRE", options.recentre as u32 as f64),
            ]
        };
        match self {
            Pass::Prepare {
                store: PrepareStore::Full,
                ..
            } => vec![],
            Pass::Prepare {
                store: PrepareStore::Down { rule: r, .. },
                ..
            } => rule(r, 1),
            Pass::Prepare {
                store: PrepareStore::Layers,
                ..
            }
            | Pass::Deinterleave
            | Pass::Interleave
            | Pass::Pyramid {
                source: PyramidSource::Layers,
            } => vec![split],
            Pass::Moments { source } => {
                let depth = ("FROM_DEPTH", (source != PyramidSource::Mip) as u32 as f64);
                if source == PyramidSource::Layers {
                    vec![split, depth]
                } else {
                    vec![depth]
                }
            }
            Pass::Pyramid { .. }
            | Pass::PyramidLevels
            | Pass::ResolveDepth
            | Pass::UpsampleScaled => vec![],
            Pass::Rescale => rule(options.downsample, 1),
            Pass::Upsample {
                bent, full_normals, ..
            } => {
                let mut v = vec![("UP_FACTOR", options.upsample_factor() as f64)];
                if bent {
                    v.push(("FULL_NORMALS", full_normals as u32 as f64));
                }
                v
            }
            Pass::Downsample { rule: r, level } => rule(r, level),
            Pass::Denoise { layers, .. } => {
                let period = ("PERIOD", options.pattern_period() as f64);
                if layers {
                    vec![period, split]
                } else {
                    vec![period]
                }
            }
            Pass::Temporal { layers, .. } => {
                if layers {
                    vec![split]
                } else {
                    vec![]
                }
            }
            Pass::AoDownsample { tent } => vec![("TENT", tent as u32 as f64)],
            // Not AO passes: [`crate::shading::lights::Lights`] sets their `PERIOD`.
            // Not AO passes: [`crate::shading::ssdo::Ssdo`] sets theirs.
            Pass::LightsShade { .. }
            | Pass::LightsMerge { .. }
            | Pass::SsdoBounce { .. }
            | Pass::SsdoCombine { .. } => vec![],
            Pass::AoFull {
                estimator: e, bent, ..
            } => [
                &estimator[..],
                &own(e)[..],
                &[skip_band],
                &bent_constant(e, bent)[..],
            ]
            .concat(),
            Pass::AoLayered {
                estimator: e, bent, ..
            } => [
                &estimator[..],
                &own(e)[..],
                &[split, skip_band],
                &bent_constant(e, bent)[..],
            ]
            .concat(),
        }
    }
}

/// The `BENT_NORMALS` of the estimators that have bent normals (the others declare no
/// such constant).
fn bent_constant(e: Estimator, bent: bool) -> Vec<(&'static str, f64)> {
    if e.has_bent_normals() {
        vec![("BENT_NORMALS", bent as u32 as f64)]
    } else {
        vec![]
    }
}

/// The many-light passes' output fragment, packed or plain irradiance, after the packing
/// functions where the pass reads (`packed_in`) or writes packed texels.
fn lit_out(packed_in: bool, packed: bool) -> Vec<&'static str> {
    let mut v = Vec::new();
    if packed_in || packed {
        v.push(include_str!("lights/lit_packed.wgsl"));
    }
    v.push(if packed {
        include_str!("lights/lit_out_packed.wgsl")
    } else {
        include_str!("lights/lit_out_plain.wgsl")
    });
    v
}

/// The AO pass's bent-normal fragment: stored, or the empty interface.
fn ao_bent(bent: bool) -> &'static str {
    if bent {
        include_str!("estimators/ao_bent.wgsl")
    } else {
        include_str!("estimators/ao_bent_none.wgsl")
    }
}

/// Labels of the AO passes: `kind` 0 = full resolution, 1 = layers with fused merge,
/// 2 = layers kept for the interleave pass; `bent`: with bent normals (GTAO, HBAO, bitmask);
/// `second`: reading a second depth layer (the bitmask).
fn ao_label(e: Estimator, kind: usize, bent: bool, second: bool) -> &'static str {
    if second {
        let names = if bent {
            [
                "bitmask_second_bent",
                "bitmask_second_bent_layers_merge",
                "bitmask_second_bent_layers",
            ]
        } else {
            [
                "bitmask_second",
                "bitmask_second_layers_merge",
                "bitmask_second_layers",
            ]
        };
        return names[kind];
    }
    if bent {
        let names = match e {
            Estimator::Hbao => ["hbao_bent", "hbao_bent_layers_merge", "hbao_bent_layers"],
            Estimator::Bitmask => [
                "bitmask_bent",
                "bitmask_bent_layers_merge",
                "bitmask_bent_layers",
            ],
            _ => ["gtao_bent", "gtao_bent_layers_merge", "gtao_bent_layers"],
        };
        return names[kind];
    }
    let names: [&'static str; 3] = match e {
        Estimator::Hbao => ["hbao", "hbao_layers_merge", "hbao_layers"],
        Estimator::Gtao => ["gtao", "gtao_layers_merge", "gtao_layers"],
        Estimator::Vo => ["vo", "vo_layers_merge", "vo_layers"],
        Estimator::Vao => ["vao", "vao_layers_merge", "vao_layers"],
        Estimator::Sao => ["sao", "sao_layers_merge", "sao_layers"],
        Estimator::VoArea => ["vo_area", "vo_area_layers_merge", "vo_area_layers"],
        Estimator::Bitmask => ["bitmask", "bitmask_layers_merge", "bitmask_layers"],
    };
    names[kind]
}

/// Constants and structs generated from Rust.
pub fn prelude() -> String {
    format!(
        "// Generated from Rust (crates/obscura/src/passes/constants.rs): do not copy these values.\n\
         const WG_SIZE: u32 = {WORKGROUP_SIZE}u;\n\
         const PATTERN_DIM: u32 = {PATTERN_DIM}u;\n\
         const PATTERN_COUNT: u32 = {PATTERN_COUNT}u;\n\
         const GUARD_AO_MARGIN: u32 = {GUARD_AO_MARGIN}u;\n\
         const PLANE_TOLERANCE: f32 = {PLANE_TOLERANCE:?};\n\
         const DEPTH_RANGE_TOLERANCE: f32 = {DEPTH_RANGE_TOLERANCE:?};\n\
         const SPHERE_THICKNESS: f32 = {SPHERE_THICKNESS:?};\n\
         const DENOISE_RADIUS_TOLERANCE: f32 = {DENOISE_RADIUS_TOLERANCE:?};\n\
         const NOISE_TOLERANCE_SIGMAS: f32 = {NOISE_TOLERANCE_SIGMAS:?};\n\
         const DENOISE_RIDGE: f32 = {DENOISE_RIDGE:?};\n\
         const HISTORY_NORMAL_COS: f32 = {HISTORY_NORMAL_COS:?};\n\
         const TENT_WEIGHTS: array<f32, 3> = array<f32, 3>({});\n\
         const TENT_SPACING: i32 = {TENT_SPACING};\n\
         const ACOS_POLY: array<f32, 4> = array<f32, 4>({});\n\
         const FIT_RADIUS: i32 = {FIT_RADIUS};\n\
         const FIT_NORMAL_TAN: f32 = {FIT_NORMAL_TAN:?};\n\
         const FIT_MAX_STRIDE: i32 = {FIT_MAX_STRIDE};\n\
         const FIT_SIGMAS: f32 = {FIT_SIGMAS:?};\n\
         const FIT_SLOPE: f32 = {FIT_SLOPE:?};\n\
         const NOISE_OFFSET_SIGMAS: f32 = {NOISE_OFFSET_SIGMAS:?};\n\
         const LIGHTS_CLASS_MIN_WEIGHT: f32 = {LIGHTS_CLASS_MIN_WEIGHT:?};\n\
         const LIGHTS_MAX: u32 = {LIGHTS_MAX}u;\n\
         const LIT_RATIO_MAX: vec3<f32> = vec3<f32>({});\n\
         const LIT_NORMAL_MAX: f32 = {LIT_NORMAL_MAX:?};\n\
         const SSDO_SELF_TOLERANCE: f32 = {SSDO_SELF_TOLERANCE:?};\n\
         const SH9_SCALE: array<f32, 5> = array<f32, 5>({});\n\
         {}{}{}{}",
        wgsl_floats(&TENT_WEIGHTS),
        wgsl_floats(&ACOS_POLY),
        wgsl_floats(&LIT_RATIO_MAX),
        wgsl_floats(&SH9_SCALE),
        FrameUniforms::wgsl(),
        GpuLight::wgsl(),
        LightsUniforms::wgsl(),
        SsdoUniforms::wgsl()
    )
}

/// `a, b, c` with every value spelled as a WGSL float literal.
fn wgsl_floats(values: &[f32]) -> String {
    values
        .iter()
        .map(|v| format!("{v:?}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Workgroups needed to cover `size` pixels.
pub fn dispatch_size(size: [u32; 2]) -> (u32, u32) {
    (
        size[0].div_ceil(WORKGROUP_SIZE),
        size[1].div_ceil(WORKGROUP_SIZE),
    )
}
