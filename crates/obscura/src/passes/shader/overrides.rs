//! Each pass's pipeline-overridable constants (WGSL `override`), valued from the options.

use super::{Pass, PrepareStore, PyramidSource};
use crate::{DepthDownsample, Estimator};

impl Pass {
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
            Pass::Denoise { .. } => vec![("PERIOD", options.pattern_period() as f64)],
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
                &[
                    split,
                    skip_band,
                    ("PATTERN_SECTOR", pattern_sector(options)),
                ],
                &bent_constant(e, bent)[..],
            ]
            .concat(),
        }
    }
}

/// The rotation sector a deinterleaved layer's pixels turn their pattern within
/// (`jitter::pixel_pattern`): 0 without jitter, so every pixel takes the fixed pattern.
pub(crate) fn pattern_sector(options: &crate::AoOptions) -> f64 {
    if options.jitter {
        crate::passes::jitter::rotation_sector(options.estimator, options.directions) as f64
    } else {
        0.0
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
