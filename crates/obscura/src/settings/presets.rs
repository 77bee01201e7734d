//! Quality presets: each estimator's directions, steps and march exponent per preset,
//! for the options' layout and resolution.

use super::{AoOptions, Estimator, Resolution};

/// Quality presets. Each estimator's directions (slices for GTAO) and steps are chosen so
/// that a preset costs about the same number of samples per pixel with every estimator:
///
/// | preset | samples/pixel | GTAO, bitmask: slices × steps (each way) | HBAO, VO, VAO, SAO, VO-area directions × steps |
/// |---|---|---|---|
/// | `Low` | 8 | 2 × 2 | 4 × 2 |
/// | `Medium` | 16 | 2 × 4 | 4 × 4 |
/// | `High` (default) | 36 or 32 | 3 × 6 at march exponent 1.3 where the samples' lattice is at most 2 pixels, else 4 × 4 evenly | 8 × 4 |
/// | `Ultra` | 96 | 8 × 6 | 16 × 6 |
///
/// `High` for GTAO and the bitmask depends on the layout and resolution
/// ([`AoOptions::with_preset`], [`AoOptions::lattice_px`]): where the samples' lattice is
/// fine (2×2 layers at full or scaled resolution, the randomized layout at full, half and
/// scaled resolution) three slices of six steps crowded toward the centre
/// ([`HIGH_MARCH_EXPONENT`]) find the contact shadows a few pixels wide that four even
/// steps step over; five such steps were better than 4 × 4 there on the mean of the
/// shared views, and at full resolution on every view (docs/thickness.md, "Steps and
/// slices"). The sixth step lowers the error on every view and the sampling pattern's
/// error by an eighth, at 1.02–1.04× the five-step frame on lavapipe once GTAO's samples
/// were made cheaper (docs/patterns.md). Where the
/// lattice is coarser (4×4 layers, 2×2 layers at half or quarter resolution, the
/// randomized layout at quarter resolution) the crowded steps land on a few lattice
/// points, the far field thins and the AO brightens, so `High` keeps 4 × 4 evenly.
/// `Resolution::Scaled` counts at scale 1, so that at scale 1 it is the full-resolution
/// frame of the same options: with five steps it gave up a little at its smallest scales
/// (GTAO 2×2 with the denoiser on the shared views: 0.1165 against 4 × 4's 0.1117 at scale
/// 0.35, 0.0927 against 0.0905 at 0.5, 0.0739 against 0.0735 at 0.7) for 0.0562 against
/// 0.0583 at 1 (2026-11-29, lavapipe: `obscura eval --all --estimators gtao --modes
/// deinterleaved2 --resolutions full --scales 0.35,0.5,0.7,1 --splits 3x5,4x4
/// --march-exponents 1,1.3 --denoise spatial --runs 3 --no-pictures --no-screen-reference`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Preset {
    Low,
    Medium,
    #[default]
    High,
    Ultra,
}

impl Preset {
    /// Every preset, cheapest first.
    pub const ALL: [Preset; 4] = [Preset::Low, Preset::Medium, Preset::High, Preset::Ultra];
}

/// The even march, [`AoOptions::march_exponent`] 1: GTAO's steps evenly spaced.
pub const EVEN_MARCH_EXPONENT: f32 = 1.0;

/// [`Preset::High`]'s march exponent for GTAO and the bitmask where the samples' lattice is
/// at most [`FINE_LATTICE_PX`] pixels, chosen over all shared views (docs/thickness.md).
pub const HIGH_MARCH_EXPONENT: f32 = 1.3;

/// The coarsest sampling lattice, in full-resolution pixels, at which `Preset::High`
/// crowds its steps toward the centre ([`AoOptions::lattice_px`]).
pub const FINE_LATTICE_PX: f32 = 2.0;

/// [`AoOptions::layered`]'s thickness prior ([`crate::AoParams::thickness`], times the
/// radius): thinner than the one-layer default, since the layer behind stands for what the
/// prior stood for alone (docs/thickness.md).
pub const LAYERED_THICKNESS: f32 = 0.75;

/// [`AoOptions::layered`]'s guard band in pixels on each side ([`crate::AoInput::guard_band`]).
pub const LAYERED_GUARD_BAND: u32 = 16;

impl AoOptions {
    /// The setting for a renderer that peels a second depth layer and draws a guard band
    /// around its image (`obscura render --layered`): the bitmask estimator reading the
    /// layer ([`AoOptions::second_layer`]), 3 slices × 7 steps at [`HIGH_MARCH_EXPONENT`],
    /// in the default layout; give it [`LAYERED_THICKNESS`] and a [`LAYERED_GUARD_BAND`]-pixel
    /// band. The most accurate single frame on the shared views (BENCHMARKS.md, "The
    /// README's settings").
    pub fn layered() -> Self {
        Self {
            estimator: Estimator::Bitmask,
            directions: 3,
            steps: 7,
            march_exponent: HIGH_MARCH_EXPONENT,
            second_layer: true,
            ..Self::default()
        }
    }

    /// The options of `preset` for `estimator` in the default layout and resolution (2×2
    /// layers, full resolution, fused); see [`Preset`]. For another layout or resolution,
    /// set them and then [`AoOptions::with_preset`].
    pub fn preset(estimator: Estimator, preset: Preset) -> Self {
        Self {
            estimator,
            ..Self::default()
        }
        .with_preset(preset)
    }

    /// These options with `preset`'s directions, steps and march exponent for their
    /// estimator, layout and resolution (see [`Preset`]); everything else is kept.
    pub fn with_preset(self, preset: Preset) -> Self {
        let marches = matches!(self.estimator, Estimator::Gtao | Estimator::Bitmask);
        let fine = self.lattice_px() <= FINE_LATTICE_PX;
        let (directions, steps, march_exponent) = match (marches, preset) {
            (true, Preset::Low) => (2, 2, EVEN_MARCH_EXPONENT),
            (true, Preset::Medium) => (2, 4, EVEN_MARCH_EXPONENT),
            (true, Preset::High) if fine => (3, 6, HIGH_MARCH_EXPONENT),
            (true, Preset::High) => (4, 4, EVEN_MARCH_EXPONENT),
            (true, Preset::Ultra) => (8, 6, EVEN_MARCH_EXPONENT),
            (false, Preset::Low) => (4, 2, EVEN_MARCH_EXPONENT),
            (false, Preset::Medium) => (4, 4, EVEN_MARCH_EXPONENT),
            (false, Preset::High) => (8, 4, EVEN_MARCH_EXPONENT),
            (false, Preset::Ultra) => (16, 6, EVEN_MARCH_EXPONENT),
        };
        Self {
            directions,
            steps,
            march_exponent,
            ..self
        }
    }

    /// The spacing of the lattice the AO pass samples on, in full-resolution pixels: the
    /// layout's split (1, 2 or 4) times the resolution's factor. `Scaled` counts at scale
    /// 1, where it is the full-resolution frame (its scale changes per frame; see
    /// [`Preset`]).
    pub fn lattice_px(&self) -> f32 {
        let factor = match self.resolution {
            Resolution::Scaled => 1.0,
            r => r.factor() as f32,
        };
        self.mode.split() as f32 * factor
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::AoMode;

    /// The layered setting and its prior validate, and it reads a second layer with the
    /// bitmask (the one estimator that reads one).
    #[test]
    fn the_layered_setting_validates_and_reads_a_second_layer() {
        let o = AoOptions::layered();
        o.validate().unwrap();
        assert!(o.second_layer && o.estimator == Estimator::Bitmask);
        let params = crate::AoParams {
            thickness: LAYERED_THICKNESS,
            ..Default::default()
        };
        params.validate().unwrap();
    }

    #[test]
    fn presets_cost_the_documented_samples_with_every_estimator() {
        for (preset, spp) in Preset::ALL.into_iter().zip([8, 16, 32, 96]) {
            for e in Estimator::ALL {
                AoOptions::preset(e, preset).validate().unwrap();
                for mode in AoMode::ALL {
                    for resolution in [
                        Resolution::Full,
                        Resolution::Half,
                        Resolution::Quarter,
                        Resolution::Scaled,
                    ] {
                        let o = AoOptions {
                            estimator: e,
                            mode,
                            resolution,
                            ..AoOptions::default()
                        }
                        .with_preset(preset);
                        // GTAO's and the bitmask's High on a fine lattice: 3 × 6 crowded.
                        let crowded = o.march_exponent != EVEN_MARCH_EXPONENT;
                        let expected = if crowded { 36 } else { spp };
                        assert_eq!(o.samples_per_pixel(), expected, "{e:?} {preset:?}");
                        assert_eq!(
                            crowded,
                            preset == Preset::High
                                && matches!(e, Estimator::Gtao | Estimator::Bitmask)
                                && (mode == AoMode::Randomized
                                    && resolution != Resolution::Quarter
                                    || mode == AoMode::Deinterleaved2
                                        && matches!(
                                            resolution,
                                            Resolution::Full | Resolution::Scaled
                                        )),
                            "{e:?} {preset:?} {mode:?} {resolution:?}"
                        );
                    }
                }
            }
        }
    }

    /// The working scale at scale 1 is the default frame: `High` gives the scaled
    /// resolution full resolution's samples in every layout, and the GPU test
    /// `scaled_resolution_matches_cpu_reference_and_is_full_resolution_at_scale_one` holds
    /// the two frames of the same options to rounding.
    #[test]
    fn the_scaled_resolution_takes_full_resolutions_samples() {
        for mode in AoMode::ALL {
            for e in [Estimator::Gtao, Estimator::Bitmask, Estimator::Hbao] {
                let at = |resolution| {
                    let o = AoOptions {
                        estimator: e,
                        mode,
                        resolution,
                        ..AoOptions::default()
                    }
                    .with_preset(Preset::High);
                    (o.directions, o.steps, o.march_exponent)
                };
                assert_eq!(
                    at(Resolution::Scaled),
                    at(Resolution::Full),
                    "{e:?} {mode:?}"
                );
            }
        }
        assert_eq!(
            AoOptions {
                resolution: Resolution::Scaled,
                ..AoOptions::default()
            }
            .with_preset(Preset::High),
            AoOptions {
                resolution: Resolution::Scaled,
                ..AoOptions::default()
            }
        );
    }
}
