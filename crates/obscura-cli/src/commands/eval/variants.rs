//! The variants one `eval` run compares: every estimator × layout × sample choice ×
//! resolution (downsample rule, upsampler) × denoiser, the continuous scales, and each
//! `--frames` count and guard band, and the bitmask's with a second depth layer.

use super::args::EvalArgs;
use crate::options::PresetArg;
use anyhow::{bail, Result};
use clap::ValueEnum;
use obscura::{AoMode, AoOptions, Denoise, Estimator, Resolution, Upsampler};

/// The label of the library's default frame (`EvalArgs::default_frame`: `AoOptions::default()`,
/// or the depth-map estimator with normals from the depth), a row of every run whose command
/// line picks no variant (`VARIANT_FLAGS`).
pub(super) const DEFAULT_LABEL: &str = "default";

/// The flags that pick variants (clap's ids): with none of them given, eval adds the
/// default frame.
const VARIANT_FLAGS: [&str; 18] = [
    "estimators",
    "splits",
    "presets",
    "modes",
    "resolutions",
    "scales",
    "thickness",
    "march_exponents",
    "guard_bands",
    "second_layer",
    "downsamples",
    "upsamplers",
    "denoise",
    "frames",
    "history",
    "preset",
    "directions",
    "steps",
];

/// How one group of variants chooses its sample counts.
#[derive(Clone, Copy)]
enum SampleChoice {
    Given,
    Split((u32, u32)),
    Preset(PresetArg),
}

/// A variant's sample choice: the index of its split or preset, and its march exponent's
/// bits when --march-exponents names them (0 otherwise).
pub(super) type SampleKey = (usize, u32);

/// The variants of a run, index by index.
pub(super) struct Variants {
    /// Each variant's label and options.
    pub(super) list: Vec<(String, AoOptions)>,
    /// Each variant's `AoParams::scale` (1 but for the scaled ones).
    pub(super) scales: Vec<f32>,
    /// Each variant's `AoParams::thickness` (the bitmask's prior; the default for the
    /// other estimators).
    pub(super) thickness_of: Vec<f32>,
    /// Each variant's frame count.
    pub(super) frames_of: Vec<u32>,
    /// Each variant's guard band, pixels (`AoInput::guard_band`).
    pub(super) guard_of: Vec<u32>,
    /// Each variant's sample choice. Variants at other resolutions compare with the
    /// full-resolution one of the same choice, whose counts may differ (a preset's follow
    /// the lattice, `AoOptions::with_preset`).
    pub(super) samples_of: Vec<SampleKey>,
    /// The longest frame count: the orbit's length.
    pub(super) orbit_frames: u32,
}

/// The variants of `a`: each sample choice crossed with everything else, then with each
/// frame count (N > 1 keeps a history and is labelled ×N).
pub(super) fn variant_list(a: &EvalArgs) -> Result<Variants> {
    let mut variants: Vec<(String, AoOptions)> = Vec::new();
    // Each variant's `AoParams::scale` (1 but for the scaled ones).
    let mut scales: Vec<f32> = Vec::new();
    // Each variant's index in `choices`.
    let mut choice_of: Vec<usize> = Vec::new();
    // The sample choices crossed with everything else: explicit splits, presets, or the
    // one choice of --preset / --directions / --steps (no label suffix).
    let choices: Vec<SampleChoice> = if !a.splits.is_empty() {
        a.splits.iter().map(|&s| SampleChoice::Split(s)).collect()
    } else if !a.presets.is_empty() {
        a.presets.iter().map(|&p| SampleChoice::Preset(p)).collect()
    } else {
        vec![SampleChoice::Given]
    };
    for &e in &a.estimators {
        for (&m, (choice_index, choice)) in a
            .modes
            .iter()
            .flat_map(|m| choices.iter().enumerate().map(move |c| (m, c)))
        {
            let (estimator, mode): (Estimator, AoMode) = (e.into(), m.into());
            let base = AoOptions {
                estimator,
                mode,
                ..AoOptions::default()
            };
            let mut name = format!("{} {}", estimator.name(), mode.name());
            match *choice {
                SampleChoice::Given => {}
                SampleChoice::Split((directions, steps)) => {
                    name = format!("{name} {directions}×{steps}");
                }
                SampleChoice::Preset(p) => {
                    let label = p.to_possible_value().map(|v| v.get_name().to_owned());
                    name = format!("{name} {}", label.unwrap_or_default());
                }
            }
            // The samples of a variant once its resolution is set: a preset's depend on
            // the lattice (`AoOptions::with_preset`); hand-picked splits march evenly.
            let samples = |o: AoOptions| match *choice {
                SampleChoice::Given => a.samples.apply(o),
                SampleChoice::Split((directions, steps)) => AoOptions {
                    directions,
                    steps,
                    march_exponent: obscura::EVEN_MARCH_EXPONENT,
                    ..o
                },
                SampleChoice::Preset(p) => o.with_preset(p.into()),
            };
            for &resolution in &a.resolutions {
                for &denoise in &a.denoise {
                    if resolution == Resolution::Full {
                        let label = match denoise {
                            Denoise::None => name.clone(),
                            d => format!("{name} full {}", d.name()),
                        };
                        let o = samples(AoOptions { denoise, ..base });
                        variants.push((label, o));
                        scales.push(1.0);
                        choice_of.push(choice_index);
                        continue;
                    }
                    for &downsample in &a.downsamples {
                        for &upsample in &a.upsamplers {
                            let o = samples(AoOptions {
                                resolution,
                                downsample,
                                upsample,
                                denoise,
                                ..base
                            });
                            let mut label = format!(
                                "{name} {} {} {}",
                                resolution.name(),
                                downsample.name(),
                                upsample.name()
                            );
                            if denoise != Denoise::None {
                                label = format!("{label} {}", denoise.name());
                            }
                            variants.push((label, o));
                            scales.push(1.0);
                            choice_of.push(choice_index);
                        }
                    }
                }
            }
            for &scale in &a.scales {
                if estimator.uses_pyramid() || estimator.uses_moments() {
                    break;
                }
                for &denoise in &a.denoise {
                    if !matches!(denoise, Denoise::None | Denoise::Spatial) {
                        continue;
                    }
                    let o = samples(AoOptions {
                        resolution: Resolution::Scaled,
                        upsample: Upsampler::Bilateral,
                        denoise,
                        ..base
                    });
                    let mut label = format!("{name} scaled {scale}");
                    if denoise != Denoise::None {
                        label = format!("{label} {}", denoise.name());
                    }
                    variants.push((label, o));
                    scales.push(scale);
                    choice_of.push(choice_index);
                }
            }
        }
    }
    if variants.is_empty() {
        bail!("no variant to evaluate");
    }
    // Each frame count crossed with the variants above: N > 1 keeps a history and is
    // labelled ×N. `frames_of[i]`: variant i's frame count.
    let mut counts: Vec<u32> = Vec::new();
    for &f in &a.frames {
        if !counts.contains(&f) {
            counts.push(f);
        }
    }
    // Each thickness prior (bitmask) and march exponent (GTAO, bitmask) crossed with those
    // estimators' variants ("tT", "eE" after the estimator's name when more than one is
    // given); other estimators run once.
    let mut single: Vec<(String, AoOptions, f32, f32, SampleKey)> = Vec::new();
    let (priors, exponents) = (a.priors(), a.exponents());
    for (((label, o), scale), choice) in variants
        .drain(..)
        .zip(scales.drain(..))
        .zip(choice_of.drain(..))
    {
        let marches = matches!(o.estimator, Estimator::Gtao | Estimator::Bitmask);
        let thick = o.estimator == Estimator::Bitmask;
        let priors = if thick {
            &priors[..]
        } else {
            &[obscura::DEFAULT_THICKNESS]
        };
        // Without --march-exponents each variant keeps its own (the preset's, or even).
        let own = [o.march_exponent];
        let exponents = match &exponents {
            Some(e) if marches => &e[..],
            _ => &own[..],
        };
        for &thickness in priors {
            for &exponent in exponents {
                let mut name = o.estimator.name().to_string();
                if priors.len() > 1 {
                    name = format!("{name} {}", thickness_label(thickness));
                }
                if exponents.len() > 1 {
                    name = format!("{name} e{exponent}");
                }
                let label = label.replacen(o.estimator.name(), &name, 1);
                let o = AoOptions {
                    march_exponent: exponent,
                    ..o
                };
                let named = if marches && !a.march_exponents.is_empty() {
                    exponent.to_bits()
                } else {
                    0
                };
                single.push((label, o, scale, thickness, (choice, named)));
            }
        }
    }
    let mut frames_of: Vec<u32> = Vec::new();
    let mut thickness_of: Vec<f32> = Vec::new();
    let mut guard_of: Vec<u32> = Vec::new();
    let mut samples_of: Vec<SampleKey> = Vec::new();
    // Each full-resolution bitmask variant with a finite prior, with a second layer too.
    if a.second_layer {
        for (label, o, scale, thickness, samples) in std::mem::take(&mut single) {
            let layered = o.estimator == Estimator::Bitmask
                && o.resolution == Resolution::Full
                && thickness.is_finite();
            single.push((label.clone(), o, scale, thickness, samples));
            if layered {
                let o = AoOptions {
                    second_layer: true,
                    ..o
                };
                single.push((format!("{label} L2"), o, scale, thickness, samples));
            }
        }
        if !single.iter().any(|s| s.1.second_layer) {
            bail!(
                "--second-layer needs a full-resolution bitmask variant with a finite --thickness"
            );
        }
    }
    for &f in &counts {
        for &guard in &a.guards() {
            for (label, o, scale, thickness, samples) in &single {
                let (mut label, mut o) = (label.clone(), *o);
                if f > 1 {
                    o.history = a.history;
                    label = format!("{label} ×{f}");
                }
                if a.guard_labels() {
                    label = format!("{label} g{guard}");
                }
                variants.push((label, o));
                scales.push(*scale);
                frames_of.push(f);
                thickness_of.push(*thickness);
                guard_of.push(guard);
                samples_of.push(*samples);
            }
        }
    }
    // With no flag that picks variants, the library's default frame too: what users get.
    if !VARIANT_FLAGS.iter().any(|f| a.given.contains(*f)) {
        variants.push((DEFAULT_LABEL.into(), a.default_frame()));
        scales.push(1.0);
        frames_of.push(1);
        thickness_of.push(obscura::DEFAULT_THICKNESS);
        guard_of.push(0);
        samples_of.push((usize::MAX, 0));
    }
    let orbit_frames = counts.iter().copied().max().unwrap_or(1);
    Ok(Variants {
        list: variants,
        scales,
        thickness_of,
        frames_of,
        guard_of,
        samples_of,
        orbit_frames,
    })
}

/// "tT" for a thickness prior, "tinf" for infinitely thick.
pub(super) fn thickness_label(t: f32) -> String {
    if t.is_finite() {
        format!("t{t}")
    } else {
        "tinf".into()
    }
}
