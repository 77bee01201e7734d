//! `eval`'s SVG plots: quality against time per view and variant, and the frontier.

use super::frontier::VariantMean;
use super::rows::Row;
use obscura::AoOptions;
use std::fmt::Write as _;

/// The frontier as a picture: one point per variant (mean time, mean RMSE), coloured by
/// estimator; frontier points filled, labelled and joined.
pub(super) fn frontier_plot(means: &[VariantMean]) -> String {
    let (w, h, m, right) = (640.0, 400.0, 60.0, 440.0);
    let tmax = means.iter().map(|v| v.ms).fold(1e-9, f64::max) * 1.05;
    let emax = means.iter().map(|v| v.error()).fold(1e-9, f64::max) * 1.05;
    let px = |t: f64| m + t / tmax * w;
    let py = |e: f64| 20.0 + h - e / emax * h;
    let estimators = ["gtao", "hbao", "vo", "vao", "sao", "vo-area", "bitmask"];
    let colors = [
        "#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#e6730f", "#17becf", "#8c564b",
    ];
    let color = |e: &str| {
        estimators
            .iter()
            .position(|x| *x == e)
            .map_or("#222222", |i| colors[i])
    };
    let mut s = plot_axes(
        w + m + right,
        (w, h, m),
        (tmax, emax),
        (
            "mean ms per frame (every pass)",
            if means.iter().any(|v| v.moving.is_some()) {
                "mean RMSE vs ray-traced (×N: the worse of still and moving)"
            } else {
                "mean RMSE vs ray-traced"
            },
        ),
    );
    let mut front: Vec<usize> = (0..means.len())
        .filter(|&i| means[i].beaten_by.is_none())
        .collect();
    front.sort_by(|&a, &b| means[a].ms.total_cmp(&means[b].ms));
    let line: Vec<String> = front
        .iter()
        .map(|&i| format!("{:.1},{:.1}", px(means[i].ms), py(means[i].error())))
        .collect();
    let _ = writeln!(
        s,
        "<polyline points=\"{}\" fill=\"none\" stroke=\"#555\" stroke-dasharray=\"4 3\"/>",
        line.join(" ")
    );
    for v in means {
        let c = color(&v.estimator);
        let fill = if v.beaten_by.is_none() { c } else { "none" };
        let _ = writeln!(
            s,
            "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"4\" fill=\"{fill}\" stroke=\"{c}\"><title>{}: {:.4}, {:.1} ms</title></circle>",
            px(v.ms),
            py(v.error()),
            v.variant,
            v.error(),
            v.ms
        );
    }
    // Frontier labels in a column on the right, joined to their points.
    for (k, &i) in front.iter().enumerate() {
        let v = &means[i];
        let y = 30.0 + 16.0 * k as f64;
        let _ = writeln!(
            s,
            "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{}\" y2=\"{}\" stroke=\"#ccc\"/>\n<text x=\"{}\" y=\"{}\" fill=\"{}\">{} ({:.4}, {:.0} ms)</text>",
            px(v.ms),
            py(v.error()),
            m + w + 8.0,
            y - 4.0,
            m + w + 10.0,
            y,
            color(&v.estimator),
            v.variant,
            v.error(),
            v.ms
        );
    }
    s.push_str("</svg>\n");
    s
}

/// An SVG plot up to its points: a `width`-wide canvas, the w × h frame at (m, 20), five
/// tick labels per axis from 0 to `tmax` ms and `emax` RMSE, and the two axis titles.
fn plot_axes(
    width: f64,
    (w, h, m): (f64, f64, f64),
    (tmax, emax): (f64, f64),
    (xlabel, ylabel): (&str, &str),
) -> String {
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{}\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<rect x=\"{m}\" y=\"20\" width=\"{w}\" height=\"{h}\" fill=\"none\" stroke=\"#999\"/>\n",
        h + m + 30.0
    );
    for k in 0..=4 {
        let (t, e) = (tmax * k as f64 / 4.0, emax * k as f64 / 4.0);
        let _ = writeln!(
            s,
            "<text x=\"{:.1}\" y=\"{}\" text-anchor=\"middle\">{t:.0}</text>\n<text x=\"{}\" y=\"{:.1}\" text-anchor=\"end\">{e:.3}</text>",
            m + t / tmax * w,
            20.0 + h + 15.0,
            m - 4.0,
            20.0 + h - e / emax * h + 4.0
        );
    }
    let _ = writeln!(
        s,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{xlabel}</text>\n<text x=\"14\" y=\"{2}\" transform=\"rotate(-90 14 {2})\" text-anchor=\"middle\">{ylabel}</text>",
        m + w / 2.0,
        20.0 + h + 32.0,
        20.0 + h / 2.0
    );
    s
}

/// Quality (RMSE) against time, one point per view and mode.
pub(super) fn scatter(rows: &[Row], variants: &[(String, AoOptions)]) -> String {
    let pts: Vec<&Row> = rows.iter().filter(|r| r.ms.is_some()).collect();
    let (w, h, m) = (560.0, 360.0, 60.0);
    let tmax = pts.iter().filter_map(|r| r.ms).fold(1e-9, f64::max) * 1.1;
    let emax = pts.iter().map(|r| r.rmse as f64).fold(1e-9, f64::max) * 1.1;
    let colors = ["#222222", "#1f77b4", "#e6730f", "#2ca02c", "#9467bd"];
    let mut s = plot_axes(
        w + 2.0 * m + 140.0,
        (w, h, m),
        (tmax, emax),
        ("median ms (prepare + AO)", "RMSE vs ray-traced"),
    );
    let px = |t: f64| m + t / tmax * w;
    let py = |e: f64| 20.0 + h - e / emax * h;
    for (vi, (name, _)) in variants.iter().enumerate() {
        let c = colors[vi % colors.len()];
        for r in pts.iter().filter(|r| &r.variant == name) {
            let _ = writeln!(
                s,
                "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"4\" fill=\"{c}\"><title>{} {}</title></circle>",
                px(r.ms.unwrap_or(0.0)),
                py(r.rmse as f64),
                r.view,
                name
            );
        }
        let y = 30.0 + 18.0 * vi as f64;
        let _ = writeln!(s, "<circle cx=\"{}\" cy=\"{y}\" r=\"4\" fill=\"{c}\"/><text x=\"{}\" y=\"{}\">{name}</text>", m + w + 15.0, m + w + 25.0, y + 4.0);
    }
    s.push_str("</svg>\n");
    s
}
