//! The text of `eval`'s results: the markdown tables (mixed resolution, sampling bias, bent
//! normals, every row, temporal accumulation), the JSON records, and picture links.

use super::args::EvalArgs;
use super::rows::{BentError, Row, TemporalFigures, OCCLUDED};
use crate::output::fmt_ms;
use std::fmt::Write as _;
use std::path::Path;

/// `dir` as seen from the markdown file's folder, with a trailing slash ("" if the same).
pub(super) fn relative_dir(dir: &Path, md: &Path) -> String {
    let base = md.parent().unwrap_or(Path::new(""));
    match dir.strip_prefix(base) {
        Ok(r) if r.as_os_str().is_empty() => String::new(),
        Ok(r) => format!("{}/", r.display()),
        Err(_) => format!("{}/", dir.display()),
    }
}

/// Below full resolution: each variant's errors averaged over the views, and its speed-up
/// over the full-resolution run of the same estimator and mode (mean of per-view ratios).
pub(super) fn mixed_summary(rows: &[Row]) -> String {
    let mut names: Vec<&str> = Vec::new();
    for r in rows.iter().filter(|r| r.ms.is_some()) {
        if !names.contains(&r.variant.as_str()) {
            names.push(&r.variant);
        }
    }
    if !rows.iter().any(|r| r.full_rmse.is_some()) {
        return String::new();
    }
    let mut s = String::from("Mean over the views. *Band ratio*: band RMSE against ray-traced AO divided by that of the same estimator and mode at full resolution (1 is full resolution's own edge error; 1.25 is a quarter more). An accumulated variant (×N) is compared with the single full-resolution frame of its estimator, mode and samples.\n\n| variant | RMSE | band RMSE | band ratio | RMSE vs full res | band RMSE vs full res | speed-up over full res |\n|---|---|---|---|---|---|---|\n");
    for name in names {
        let mine: Vec<&Row> = rows.iter().filter(|r| r.variant == name).collect();
        let n = mine.len() as f32;
        let mean = |f: &dyn Fn(&Row) -> f32| mine.iter().map(|r| f(r)).sum::<f32>() / n;
        // The same estimator, mode and samples at full resolution without denoising on the
        // same view: this variant itself if it is one, else the timed variant whose name,
        // plus a space, begins this one's (the longest, so "gtao randomized high" and not
        // "gtao randomized" for a preset).
        let full_of = |r: &Row| {
            rows.iter()
                .filter(|f| {
                    f.view == r.view
                        && f.estimator == r.estimator
                        && f.mode == r.mode
                        && f.ms.is_some()
                        && f.full_rmse.is_none()
                        && (r.variant == f.variant
                            || r.variant.starts_with(&format!("{} ", f.variant)))
                })
                .max_by_key(|f| f.variant.len())
        };
        let speedups: Vec<f64> = mine
            .iter()
            .filter_map(|r| Some(full_of(r)?.ms? / r.ms?))
            .collect();
        let speedup = if speedups.is_empty() {
            "–".to_string()
        } else {
            format!(
                "{:.2}×",
                speedups.iter().sum::<f64>() / speedups.len() as f64
            )
        };
        let full_band: Vec<f32> = mine
            .iter()
            .filter_map(|r| full_of(r).map(|f| f.band_rmse))
            .collect();
        let band_ratio = if full_band.len() == mine.len() {
            format!(
                "{:.2}",
                mean(&|r| r.band_rmse) / (full_band.iter().sum::<f32>() / n)
            )
        } else {
            "–".into()
        };
        let full = mine.iter().all(|r| r.full_rmse.is_some());
        let _ = writeln!(
            s,
            "| {name} | {:.4} | {:.4} | {band_ratio} | {} | {} | {speedup} |",
            mean(&|r| r.rmse),
            mean(&|r| r.band_rmse),
            if full {
                format!("{:.4}", mean(&|r| r.full_rmse.map_or(0.0, |f| f.0)))
            } else {
                "–".into()
            },
            if full {
                format!("{:.4}", mean(&|r| r.full_rmse.map_or(0.0, |f| f.1)))
            } else {
                "–".into()
            },
        );
    }
    s.push('\n');
    s
}

/// Per variant, the mean and the largest (in magnitude) over the views of its bias minus
/// that of its estimator's screen-space reference: how far sampling moves the mean AO from
/// the integral it samples (within ±0.01 on every view is the goal for GTAO). Empty
/// without screen-space references.
pub(super) fn sampling_bias_table(rows: &[Row]) -> String {
    let mut names: Vec<&str> = Vec::new();
    for r in rows.iter().filter(|r| r.screen_bias.is_some()) {
        if !names.contains(&r.variant.as_str()) {
            names.push(&r.variant);
        }
    }
    if names.is_empty() {
        return String::new();
    }
    let mut s = String::from("\n### Sampling bias\n\nBias minus the bias of the estimator's own screen-space reference (= mean(estimate − screen ref)), over the views: positive means sampling leaves the image brighter than the integral it samples.\n\n| variant | mean | largest | on |\n|---|---|---|---|\n");
    for name in names {
        let mine: Vec<(&str, f32)> = rows
            .iter()
            .filter(|r| r.variant == name)
            .filter_map(|r| Some((r.view.as_str(), r.screen_bias?)))
            .collect();
        let mean = mine.iter().map(|m| m.1).sum::<f32>() / mine.len() as f32;
        let (view, largest) = mine
            .iter()
            .copied()
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .unwrap_or(("–", 0.0));
        let _ = writeln!(s, "| {name} | {mean:+.4} | {largest:+.4} | {view} |");
    }
    s.push('\n');
    s
}

pub(super) fn bent_table(rows: &[Row]) -> String {
    let mut names: Vec<&str> = Vec::new();
    for r in rows.iter().filter(|r| r.bent.is_some()) {
        if !names.contains(&r.variant.as_str()) {
            names.push(&r.variant);
        }
    }
    if names.is_empty() {
        return String::new();
    }
    let mut s = format!("\n### Bent normals\n\nMean angle to the ray tracer's bent normal (the mean direction of its unoccluded cosine-weighted rays), over the views: of the estimator's bent normals (GTAO, HBAO, bitmask), and of the surface normal it was given or reconstructed (what a renderer uses without bent normals); *occluded*: pixels whose traced AO is below {OCCLUDED}, where the two differ most.\n\n| variant | bent normals | surface normal | bent normals, occluded | surface normal, occluded |\n|---|---|---|---|---|\n");
    for name in names {
        let mine: Vec<BentError> = rows
            .iter()
            .filter(|r| r.variant == name)
            .filter_map(|r| r.bent)
            .collect();
        let mean = |f: fn(&BentError) -> f32| mine.iter().map(f).sum::<f32>() / mine.len() as f32;
        let _ = writeln!(
            s,
            "| {name} | {:.1}° | {:.1}° | {:.1}° | {:.1}° |",
            mean(|e| e.bent),
            mean(|e| e.normal),
            mean(|e| e.bent_occluded),
            mean(|e| e.normal_occluded)
        );
    }
    s.push('\n');
    s
}

pub(super) fn summary_table(rows: &[Row]) -> String {
    let mixed = rows.iter().any(|r| r.full_rmse.is_some());
    let mut s = String::from(
        "| view | estimator / mode | RMSE | bias | SSIM | ꟻLIP | band RMSE | RMSE vs screen ref | bias vs screen ref | ꟻLIP vs screen ref |",
    );
    s.push_str(if mixed {
        " RMSE vs full res | band RMSE vs full res | ms |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n"
    } else {
        " ms |\n|---|---|---|---|---|---|---|---|---|---|---|\n"
    });
    for r in rows {
        let full = match (mixed, r.full_rmse) {
            (false, _) => String::new(),
            (true, None) => " – | – |".into(),
            (true, Some((a, b))) => format!(" {a:.4} | {b:.4} |"),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {:.4} | {:+.4} | {:.3} | {:.4} | {:.4} | {} | {} | {} |{full} {} |",
            r.view,
            r.variant,
            r.rmse,
            r.bias,
            r.ssim,
            r.flip,
            r.band_rmse,
            r.screen_rmse.map_or("–".to_string(), |m| format!("{m:.4}")),
            r.screen_bias
                .map_or("–".to_string(), |b| format!("{b:+.4}")),
            r.screen_flip.map_or("–".to_string(), |m| format!("{m:.4}")),
            r.ms.map_or("–".to_string(), fmt_ms)
        );
    }
    s
}

/// The temporal figures of `eval --frames N`, per view and variant, and their means.
/// A row of the temporal table: an accumulated variant's figures, or a single frame's.
type TemporalRow<'a> = (&'a Row, Option<TemporalFigures>);

pub(super) fn temporal_table(rows: &[Row], a: &EvalArgs) -> String {
    // Accumulated variants, and single frames with the orbit's flicker.
    let t: Vec<TemporalRow> = rows
        .iter()
        .filter(|r| r.temporal.is_some() || r.orbit_flicker.is_some())
        .map(|r| (r, r.temporal))
        .collect();
    if t.is_empty() {
        return String::new();
    }
    let mut s = format!(
        "\n### Temporal accumulation (history {})\n\n*×N*: scored after N frames of a still camera. *Flicker*: mean |AO(frame N+1) − AO(frame N)| of the still camera. *Orbit*: N frames {}° apart about the vertical axis through the target, ending at the view; RMSE of its last frame (a single frame's is its still RMSE: the same camera). *Orbit flicker*: the orbit's last frame against the one before, reprojected (pixels that see the same surface in both), less the truth's own change: mean |(AO − AO′) − (truth − truth′)|; single frames take the orbit's last two frames too. *Disoccluded*: pixels of the last frame that became visible 4 frames earlier (history of 5 frames): their RMSE after the orbit, against the same pixels in the still camera's N-frame image (ratio: 1 is as good as the still camera).\n\n| view | variant | RMSE (still, N frames) | flicker | orbit RMSE | orbit flicker | disoccluded pixels | their RMSE | same pixels still | ratio |\n|---|---|---|---|---|---|---|---|---|---|\n",
        a.history, a.orbit_step
    );
    let opt = |v: Option<f32>| v.map_or("–".to_string(), |v| format!("{v:.4}"));
    for (r, f) in &t {
        let d = f
            .and_then(|f| f.disoccluded)
            .map_or(" – | – | – | – |".to_string(), |(o, st, n)| {
                format!(" {n} | {o:.4} | {st:.4} | {:.2} |", o / st.max(1e-6))
            });
        let _ = writeln!(
            s,
            "| {} | {} | {:.4} | {} | {:.4} | {} |{d}",
            r.view,
            r.variant,
            r.rmse,
            opt(f.map(|f| f.flicker)),
            f.map_or(r.rmse, |f| f.orbit_rmse),
            opt(r.orbit_flicker),
        );
    }
    let mut variants: Vec<&str> = t.iter().map(|(r, _)| r.variant.as_str()).collect();
    variants.dedup();
    variants.sort();
    variants.dedup();
    for v in variants {
        let of: Vec<&TemporalRow> = t.iter().filter(|(r, _)| r.variant == v).collect();
        let n = of.len() as f32;
        let mean = |f: &dyn Fn(&TemporalRow) -> Option<f32>| {
            let got: Vec<f32> = of.iter().filter_map(|x| f(x)).collect();
            (got.len() == of.len()).then(|| got.iter().sum::<f32>() / n)
        };
        let (o, st): (f32, f32) = of
            .iter()
            .filter_map(|(_, f)| f.and_then(|f| f.disoccluded))
            .fold((0.0, 0.0), |acc, (o, st, _)| {
                (acc.0 + o * o, acc.1 + st * st)
            });
        // An orbit shorter than 5 frames has no pixel with a 5-frame history.
        let pooled = if st > 0.0 {
            format!("{:.2} (pooled)", (o / st).sqrt())
        } else {
            "–".to_string()
        };
        let _ = writeln!(
            s,
            "| **mean** | {v} | {} | {} | {} | {} | | | | {pooled} |",
            opt(mean(&|x| Some(x.0.rmse))),
            opt(mean(&|x| x.1.map(|f| f.flicker))),
            opt(mean(&|x| Some(x.1.map_or(x.0.rmse, |f| f.orbit_rmse)))),
            opt(mean(&|x| x.0.orbit_flicker)),
        );
    }
    s
}

/// A JSON number at full precision (the shortest decimal that reads back as the same
/// value), or null for a missing or non-finite one.
fn num<T: Into<f64>>(v: Option<T>) -> String {
    match v.map(Into::into) {
        Some(x) if x.is_finite() => format!("{x}"),
        _ => "null".into(),
    }
}

/// The eval's JSON: each view's radius, reference error and triangle count, then one record
/// per view and variant, every figure at full precision (f32 errors and angles as the f32
/// they are, so two runs can be compared to the last bit).
pub(super) fn json(rows: &[Row], info: &[(String, f32, f32, usize)]) -> String {
    let text = |t: &str| serde_json::to_string(t).expect("a string serializes");
    let mut s = String::from("{\n  \"views\": [\n");
    for (i, (name, radius, se, tris)) in info.iter().enumerate() {
        let _ = writeln!(
            s,
            "    {{\"view\": {}, \"radius\": {}, \"reference_mean_std_error\": {}, \"triangles\": {tris}}}{}",
            text(name),
            num32(Some(*radius)),
            num32(Some(*se)),
            if i + 1 == info.len() { "" } else { "," }
        );
    }
    s.push_str("  ],\n  \"records\": [\n");
    for (i, r) in rows.iter().enumerate() {
        let t = r.temporal;
        let d = t.and_then(|t| t.disoccluded);
        let _ = writeln!(
            s,
            "    {{\"view\": {}, \"variant\": {}, \"estimator\": {}, \"mode\": {}, \"rmse\": {}, \"bias\": {}, \"ssim\": {}, \"flip\": {}, \"default\": {}, \"band_rmse\": {}, \"screen_rmse\": {}, \"screen_bias\": {}, \"screen_flip\": {}, \"full_rmse\": {}, \"full_band_rmse\": {}, \"median_ms\": {}, \"frames\": {}, \"flicker\": {}, \"orbit_rmse\": {}, \"orbit_flicker\": {}, \"disoccluded_rmse\": {}, \"disoccluded_still_rmse\": {}, \"bent_deg\": {}, \"bent_occluded_deg\": {}, \"normal_deg\": {}, \"normal_occluded_deg\": {}}}{}",
            text(&r.view),
            text(&r.variant),
            text(&r.estimator),
            text(&r.mode),
            num32(Some(r.rmse)),
            num32(Some(r.bias)),
            num32(Some(r.ssim)),
            num32(Some(r.flip)),
            r.default,
            num32(Some(r.band_rmse)),
            num32(r.screen_rmse),
            num32(r.screen_bias),
            num32(r.screen_flip),
            num32(r.full_rmse.map(|m| m.0)),
            num32(r.full_rmse.map(|m| m.1)),
            num(r.ms),
            t.map_or(1, |t| t.frames),
            num32(t.map(|t| t.flicker)),
            num32(t.map(|t| t.orbit_rmse)),
            num32(r.orbit_flicker),
            num32(d.map(|d| d.0)),
            num32(d.map(|d| d.1)),
            num32(r.bent.map(|e| e.bent)),
            num32(r.bent.map(|e| e.bent_occluded)),
            num32(r.bent.map(|e| e.normal)),
            num32(r.bent.map(|e| e.normal_occluded)),
            if i + 1 == rows.len() { "" } else { "," }
        );
    }
    s.push_str("  ]\n}\n");
    s
}

/// [`num`] of an f32, written as the shortest decimal that reads back as that f32.
fn num32(v: Option<f32>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{x}"),
        _ => "null".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::{json, mixed_summary, Row};

    /// A row of one view with only what the mixed summary reads.
    fn row(variant: &str, ms: f64, full_rmse: Option<(f32, f32)>) -> Row {
        let words: Vec<&str> = variant.split(' ').collect();
        Row {
            view: "v".into(),
            variant: variant.into(),
            estimator: words[0].into(),
            mode: words[1].into(),
            rmse: 0.05,
            bias: 0.0,
            ssim: 1.0,
            flip: 0.1,
            default: false,
            band_rmse: 0.1,
            screen_rmse: None,
            screen_bias: None,
            screen_flip: None,
            full_rmse,
            ms: Some(ms),
            temporal: None,
            orbit_flicker: None,
            bent: None,
        }
    }

    /// With several presets, a denoised or low-resolution variant's speed-up is over the
    /// full-resolution variant of its own preset ("gtao randomized high"), not of another
    /// one nor of none; a variant that is its own full-resolution one reads 1.00×.
    #[test]
    fn the_mixed_summary_compares_each_preset_with_its_own_full_resolution() {
        let rows = [
            row("gtao randomized low", 10.0, None),
            row("gtao randomized high", 20.0, None),
            row(
                "gtao randomized high full spatial",
                40.0,
                Some((0.01, 0.01)),
            ),
            row(
                "gtao randomized low half bilateral",
                5.0,
                Some((0.02, 0.02)),
            ),
        ];
        let s = mixed_summary(&rows);
        let speedup = |name: &str| {
            let line = s
                .lines()
                .find(|l| l.starts_with(&format!("| {name} |")))
                .unwrap_or_else(|| panic!("{name} missing: {s}"));
            line.rsplit('|').nth(1).unwrap().trim().to_string()
        };
        assert_eq!(speedup("gtao randomized high full spatial"), "0.50×", "{s}");
        assert_eq!(
            speedup("gtao randomized low half bilateral"),
            "2.00×",
            "{s}"
        );
        assert_eq!(speedup("gtao randomized high"), "1.00×", "{s}");
    }

    /// Every figure reads back as the very f32 (or f64) it was, so two runs' JSON compare
    /// to the last bit; names are escaped; missing figures are null.
    #[test]
    fn json_keeps_every_figure_to_the_last_bit() {
        let mut r = row("gtao \"odd\" name", 12.345_678_901_234, Some((0.1, 0.2)));
        r.rmse = 0.123_456_79;
        r.bias = -1.234_567_9e-7;
        r.ssim = 0.999_999_9;
        let s = json(&[r], &[("v".into(), 1.234_567_9, 3.0e-5, 7)]);
        let v: serde_json::Value = serde_json::from_str(&s).expect("valid JSON");
        let rec = &v["records"][0];
        let f32_of = |x: &serde_json::Value| x.as_f64().expect("a number") as f32;
        assert_eq!(f32_of(&rec["rmse"]), 0.123_456_79);
        assert_eq!(f32_of(&rec["bias"]), -1.234_567_9e-7);
        assert_eq!(f32_of(&rec["ssim"]), 0.999_999_9);
        assert_eq!(f32_of(&rec["full_rmse"]), 0.1);
        assert_eq!(rec["median_ms"].as_f64(), Some(12.345_678_901_234));
        assert_eq!(rec["variant"], "gtao \"odd\" name");
        assert_eq!(rec["default"], false);
        assert_eq!(f32_of(&rec["flip"]), 0.1);
        assert!(rec["screen_rmse"].is_null() && rec["flicker"].is_null());
        assert_eq!(f32_of(&v["views"][0]["radius"]), 1.234_567_9);
    }
}
