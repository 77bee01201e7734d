//! The quality-versus-time frontier: each timed variant's means over the views, which
//! variants no other beats (Pareto), and their table.

use super::rows::Row;
use crate::output::fmt_ms;
use std::fmt::Write as _;

/// One timed variant averaged over the evaluated views.
pub(super) struct VariantMean {
    pub(super) variant: String,
    pub(super) estimator: String,
    pub(super) rmse: f64,
    pub(super) bias: f64,
    pub(super) ms: f64,
    /// An accumulated variant's mean orbit RMSE (a moving camera's error).
    pub(super) moving: Option<f64>,
    /// The variant that beats it (`pareto`), or `None` on the frontier.
    pub(super) beaten_by: Option<usize>,
}

impl VariantMean {
    /// The error the frontier ranks by: the RMSE, or for an accumulated variant the worse
    /// of the still camera's and the orbit's (a still camera alone flatters it).
    pub(super) fn error(&self) -> f64 {
        self.moving.map_or(self.rmse, |m| m.max(self.rmse))
    }
}

/// Every timed variant's mean RMSE, bias and time over the views, in evaluation order.
pub(super) fn variant_means(rows: &[Row]) -> Vec<VariantMean> {
    let mut out: Vec<VariantMean> = Vec::new();
    for r in rows.iter().filter(|r| r.ms.is_some()) {
        if out.iter().any(|m| m.variant == r.variant) {
            continue;
        }
        let mine: Vec<&Row> = rows.iter().filter(|x| x.variant == r.variant).collect();
        let n = mine.len() as f64;
        out.push(VariantMean {
            variant: r.variant.clone(),
            estimator: r.estimator.clone(),
            rmse: mine.iter().map(|x| x.rmse as f64).sum::<f64>() / n,
            bias: mine.iter().map(|x| x.bias as f64).sum::<f64>() / n,
            ms: mine.iter().filter_map(|x| x.ms).sum::<f64>() / n,
            moving: r.temporal.map(|_| {
                mine.iter()
                    .filter_map(|x| x.temporal)
                    .map(|t| t.orbit_rmse as f64)
                    .sum::<f64>()
                    / n
            }),
            beaten_by: None,
        });
    }
    let beaten = pareto(&out.iter().map(|m| (m.ms, m.error())).collect::<Vec<_>>());
    for (m, b) in out.iter_mut().zip(beaten) {
        m.beaten_by = b;
    }
    out
}

/// For each point (time, error), the index of the point that dominates it, or `None` when
/// it is on the Pareto frontier: no other point is at most as slow and strictly more
/// accurate, or as accurate and strictly faster. The dominating point named is the most
/// accurate of those at most as slow (itself on the frontier).
fn pareto(points: &[(f64, f64)]) -> Vec<Option<usize>> {
    points
        .iter()
        .enumerate()
        .map(|(i, &(t, e))| {
            points
                .iter()
                .enumerate()
                .filter(|&(j, &(tj, ej))| {
                    j != i && tj <= t && ej <= e && (tj < t || ej < e || j < i)
                })
                .min_by(|a, b| {
                    (a.1 .1, a.1 .0)
                        .partial_cmp(&(b.1 .1, b.1 .0))
                        .unwrap_or(std::cmp::Ordering::Equal)
                })
                .map(|(j, _)| j)
        })
        .collect()
}

/// The quality-versus-time frontier: every timed variant by mean time, marked when no other
/// variant is both at most as slow and more accurate.
pub(super) fn frontier_table(means: &[VariantMean]) -> String {
    if means.len() < 2 {
        return String::new();
    }
    let mut order: Vec<usize> = (0..means.len()).collect();
    order.sort_by(|&a, &b| means[a].ms.total_cmp(&means[b].ms));
    let moving = means.iter().any(|m| m.moving.is_some());
    let mut s = String::from("\n### Quality-versus-time frontier\n\nMean over the views of RMSE against ray-traced AO and of the frame time, every variant by time. **frontier**: no other variant is at most as slow and more accurate; the others name the faster-or-equal variant that beats them. Pick the row that fits your budget.");
    if moving {
        s.push_str(" *×N*: N accumulated frames (a history), timed per frame; *RMSE* is the still camera's after N frames, *moving* the last frame of an orbit of N frames (`--orbit-step`), and the frontier ranks these by the worse of the two.\n\n| variant | RMSE | moving | bias | ms | |\n|---|---|---|---|---|---|\n");
    } else {
        s.push_str("\n\n| variant | RMSE | bias | ms | |\n|---|---|---|---|---|\n");
    }
    for i in order {
        let m = &means[i];
        let mark = match m.beaten_by {
            None => "**frontier**".to_string(),
            Some(j) => format!("beaten by {}", means[j].variant),
        };
        let mov = match (moving, m.moving) {
            (false, _) => String::new(),
            (true, None) => " – |".to_string(),
            (true, Some(o)) => format!(" {o:.4} |"),
        };
        let _ = writeln!(
            s,
            "| {} | {:.4} |{mov} {:+.4} | {} | {mark} |",
            m.variant,
            m.rmse,
            m.bias,
            fmt_ms(m.ms)
        );
    }
    s.push('\n');
    s
}

#[cfg(test)]
mod tests {
    use super::pareto;

    #[test]
    fn the_frontier_keeps_exactly_the_undominated_points() {
        // (ms, rmse). 0, 1 and 3 trade time for error; 2 is slower and worse than 1; 4 ties
        // 1's time with more error; 5 duplicates 3 (the first of equal points stays).
        let p = [
            (10.0, 0.08),
            (20.0, 0.06),
            (25.0, 0.07),
            (40.0, 0.05),
            (20.0, 0.065),
            (40.0, 0.05),
        ];
        let d = pareto(&p);
        assert_eq!(d, vec![None, None, Some(1), None, Some(1), Some(3)]);
        // Equal error and more time is beaten too; a single point is its own frontier.
        assert_eq!(pareto(&[(1.0, 0.1), (2.0, 0.1)]), vec![None, Some(0)]);
        assert_eq!(pareto(&[(3.0, 0.2)]), vec![None]);
    }
}
