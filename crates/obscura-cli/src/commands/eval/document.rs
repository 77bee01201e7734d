//! The markdown document `eval --report` writes: its introduction, and one section per
//! view with the pictures of every variant, their signed errors, ꟻLIP maps and pattern
//! errors.

use super::args::{EvalArgs, FalloffArg, TruthArg};
use super::pictures::{write_error, write_flip, write_gray};
use super::report::relative_dir;
use crate::views::Job;
use anyhow::Result;
use obscura::{AoOptions, GpuContext, Resolution, Timing};
use std::fmt::Write as _;
use std::path::Path;

/// A scored image: (label, estimator, mode, image, median time, options); times and options
/// for the timed variants only.
pub(super) type Scored = (
    String,
    String,
    String,
    Vec<f32>,
    Option<f64>,
    Option<AoOptions>,
);

/// What a view's section says of it.
pub(super) struct ViewFacts<'a> {
    pub(super) job: &'a Job,
    pub(super) triangles: usize,
    pub(super) radius: f32,
    /// The reference's mean standard error.
    pub(super) std_error: f32,
    /// Seconds the view took, reference included.
    pub(super) seconds: f64,
}

/// What a view's pictures show: the truth, the compared pixels, and each scored image with
/// its ꟻLIP map against the truth and its estimator's screen-space reference, if any.
pub(super) struct Pictures<'a> {
    pub(super) truth: &'a [f32],
    pub(super) mask: &'a [bool],
    pub(super) scored: &'a [Scored],
    pub(super) maps: &'a [(Vec<f32>, Option<&'a [f32]>)],
}

/// The range of the pattern error's heat map: a sampling pattern's streaks are a few
/// hundredths, so a narrower scale than the error's.
const PATTERN_RANGE: f32 = 0.1;

/// Appends `view`'s section to `sections`, writing its pictures beside the markdown `md` in
/// `dir`: the truth, then each scored image, its signed error and ꟻLIP map against the
/// truth, and its pattern error (against its own screen-space reference).
pub(super) fn view_section(
    sections: &mut String,
    a: &EvalArgs,
    (dir, md): (&Path, &Path),
    view: &ViewFacts,
    p: &Pictures,
) -> Result<()> {
    let (w, h) = (a.width, a.height);
    let (scale, mask) = (a.picture_scale, p.mask);
    let rel = relative_dir(dir, md);
    let pic = |stem: &str| format!("{}-{}.png", view.job.name, stem.replace(' ', "-"));
    write_gray(&dir.join(pic("reference")), p.truth, w, h, scale)?;
    let _ = write!(
        sections,
        "\n### {}\n\n`{}`, {} triangles, radius {:.3}, reference {} rays/pixel (mean standard error {:.4}), eval {}×{}; evaluated in {:.0} s. ꟻLIP at {} pixels per degree.\n\n| reference | {} |\n|---|{}\n| ![]({rel}{}) |",
        view.job.name,
        view.job.file.display(),
        view.triangles,
        view.radius,
        a.rays,
        view.std_error,
        w,
        h,
        view.seconds,
        obscura_eval::flip::PIXELS_PER_DEGREE,
        p.scored
            .iter()
            .map(|r| r.0.as_str())
            .collect::<Vec<_>>()
            .join(" | "),
        "---|".repeat(p.scored.len()),
        pic("reference"),
    );
    for ((name, _, _, img, _, _), (map, screen)) in p.scored.iter().zip(p.maps) {
        write_gray(&dir.join(pic(name)), img, w, h, scale)?;
        let error = pic(&format!("{name}-error"));
        write_error(&dir.join(error), img, p.truth, mask, (w, h), 0.5, scale)?;
        write_flip(
            &dir.join(pic(&format!("{name}-flip"))),
            map,
            mask,
            (w, h),
            scale,
        )?;
        if let Some(s) = screen {
            let pattern = pic(&format!("{name}-pattern"));
            write_error(
                &dir.join(pattern),
                img,
                s,
                mask,
                (w, h),
                PATTERN_RANGE,
                scale,
            )?;
        }
        let _ = write!(sections, " ![]({rel}{}) |", pic(name));
    }
    let rows: [(&str, &str); 3] = [
        (
            "error",
            "signed error (red: too bright, blue: too dark, ±0.5)",
        ),
        ("flip", "ꟻLIP against the truth (black: none, yellow: most)"),
        (
            "pattern",
            "pattern error: against its own screen-space reference (±0.1)",
        ),
    ];
    for (suffix, title) in rows {
        if suffix == "pattern" && p.maps.iter().all(|m| m.1.is_none()) {
            continue;
        }
        let _ = write!(sections, "\n| {title} |");
        for ((name, ..), (_, screen)) in p.scored.iter().zip(p.maps) {
            if suffix == "pattern" && screen.is_none() {
                sections.push_str(" – |");
            } else {
                let _ = write!(
                    sections,
                    " ![]({rel}{}) |",
                    pic(&format!("{name}-{suffix}"))
                );
            }
        }
    }
    sections.push('\n');
    Ok(())
}

/// The document's title and introduction: the command, the truth, the metrics and the
/// adapter.
pub(super) fn header(a: &EvalArgs, ctx: &GpuContext, variants: &[(String, AoOptions)]) -> String {
    let (w, h) = (a.width, a.height);
    // The mixed-resolution introduction only when some variant runs below full
    // resolution (a denoiser alone also gets the full-resolution comparison columns).
    let title = if variants
        .iter()
        .any(|(_, o)| o.resolution != Resolution::Full)
    {
        &format!("# Mixed resolution against ray-traced ground truth\n\nAO computed at half or quarter resolution (depth downsampled 2×2 → 1 by a rule, picks recentred on their tangent plane) or at a continuous scale *s* (`scaled s`: each working texel one of the full-resolution pixels it covers, by the same rule among the 2×2 nearest its centre, recentred; temporal accumulation, when on, on the working grid), upsampled to full resolution, compared with ray-traced AO and with the same estimator at full resolution. The evaluation size is {w}×{h} (half resolution is a {}×{} AO){}; speed-ups at 1920×1080 and 3840×2160, and what the numbers mean, are in BENCHMARKS.md (`obscura bench --compare resolutions`). *Speed-up* here is the mean over the views of full-resolution time / variant time at {w}×{h}, where the full-resolution prepare and upsample passes weigh most.", w.div_ceil(2), h.div_ceil(2), if w * h <= 640 * 400 { ", small: the harshest case for low resolutions" } else { "" })
    } else {
        "# Quality against ray-traced ground truth"
    };
    format!(
        "{title}\n\nGenerated by `{}`.\n\nReference: CPU ray tracing of the scene triangles, cosine-weighted hemisphere, {} rays per pixel{}, hits within the radius {} (see `crates/obscura-eval`). Metrics over pixels where both the reference and the G-buffer see a surface; the band is the pixels within 2 px of a depth discontinuity (> 5% relative). Bias = mean(estimate − reference): positive means too bright. Each estimator's *screen-space reference* is its own integral brute-forced (64 × 64 samples, no jitter, `AoOptions::screen_reference`): its error against the ray tracer is what one depth layer allows that estimator, and *RMSE vs screen ref* and *bias vs screen ref* are an estimate's sampling error and sampling bias (for vo-area, whose 64 × 64 samples each cover under 4 px², the reference is the line integral's, so it is the area integral's distance from it). Times: median {} on {}.\n\n",
        std::env::args().collect::<Vec<_>>().join(" "),
        a.rays,
        match a.truth {
            TruthArg::Centre => "",
            TruthArg::Msaa4 =>
                " (a quarter through each of the four 4× MSAA sample positions, averaged; sky samples unoccluded)",
        },
        match a.falloff {
            FalloffArg::None => "occlude fully",
            FalloffArg::Quadratic => "occlude by 1 − t²/R²",
        },
        match Timing::best_for(ctx) {
            Timing::Timestamps => "GPU time of the whole AO frame (the sum of its passes' timestamps)",
            Timing::WallClock => "wall clock of the whole AO frame (every pass, submit to completion)",
        },
        ctx.describe()
    )
}
