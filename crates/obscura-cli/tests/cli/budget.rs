//! `obscura render --orbit --budget-ms`: a frame-time budget held by level, by scale and
//! samples, and one that cannot be held.

use super::*;

/// `render --orbit --budget-ms`: with a budget no level can miss, the controller climbs to
/// the top of the ladder once the first level has settled (3 frames); with one no level
/// can meet, it never leaves the cheapest. Each frame is a row of budget.csv, the plot is
/// written, and a bad budget is refused before any work.
#[test]
fn render_orbit_holds_a_budget_by_level() {
    let levels = |budget: &str| -> Vec<String> {
        let (err, rows) = budget_orbit(&format!("budget-{budget}"), budget, 6, Some("ladder"));
        assert!(err.contains("frame    5: level"), "per-frame lines: {err}");
        rows.iter().map(|c| c[2].clone() + " " + &c[3]).collect()
    };
    // The first level is the cheapest one kept: at this size the quarter and half levels
    // cost about the same, and a level that a better one undercuts is skipped.
    let generous = levels("1000000");
    assert_eq!(generous.len(), 6);
    assert!(
        generous[..3].iter().all(|l| *l == generous[0]) && generous[0] != "full ultra",
        "{generous:?}"
    );
    assert!(
        generous[3..].iter().all(|l| l == "full ultra"),
        "{generous:?}"
    );
    let impossible = levels("0.001");
    assert!(
        impossible.iter().all(|l| *l == impossible[0]) && impossible[0] != "full ultra",
        "{impossible:?}"
    );
    let d = scratch("budget-bad");
    assert_fails(
        "budget-negative",
        &[
            "render",
            "--orbit",
            "10",
            "--out-dir",
            s(&d),
            "--budget-ms=-5",
        ],
        "--budget-ms must be",
    );
    assert_fails(
        "budget-nan",
        &[
            "render",
            "--orbit",
            "10",
            "--out-dir",
            s(&d),
            "--budget-ms",
            "NaN",
        ],
        "--budget-ms must be",
    );
    assert_fails(
        "budget-without-orbit",
        &["render", "--budget-ms", "20"],
        "--orbit",
    );
    std::fs::remove_dir_all(d).unwrap();
}

/// `render --orbit --budget-ms` with both knobs (the default, `--budget-control joint`):
/// the scale up to the measured top, then full-resolution sample counts; budget.csv names
/// each frame's resolution, scale and preset.
#[test]
fn render_orbit_holds_a_budget_by_scale_and_samples() {
    // Each frame's (resolution, scale, preset) from budget.csv.
    let knobs = |budget: &str| -> Vec<(String, f32, String)> {
        let (err, rows) = budget_orbit(&format!("budget-joint-{budget}"), budget, 10, None);
        assert!(err.contains("top scale"), "the measured top scale: {err}");
        rows.iter()
            .map(|c| (c[1].clone(), c[2].parse().unwrap(), c[3].clone()))
            .collect()
    };
    // A budget nothing can miss: the scale climbs to its top (one frame), holds it for the
    // three frames that hand over, then the ladder's cheapest rung settles for three frames
    // and the controller goes to the top rung, full ultra. The joint controller is the
    // default.
    let generous = knobs("1000000");
    let scaled = generous.iter().take_while(|k| k.0 == "scaled").count();
    assert!((3..=4).contains(&scaled), "{generous:?}");
    assert!(generous[scaled..]
        .iter()
        .all(|k| k.0 == "full" && k.1 == 1.0));
    assert!(
        generous[scaled + 3..].iter().all(|k| k.2 == "ultra"),
        "{generous:?}"
    );
    assert!(generous[0].2 == "high" && generous[0].1 <= 0.5);
    // One nothing can meet: the smallest scale from the second frame on, never full.
    let impossible = knobs("0.001");
    assert!(
        impossible[1..]
            .iter()
            .all(|k| k.0 == "scaled" && k.1 == 0.25),
        "{impossible:?}"
    );
}

/// `render --orbit --budget-ms --budget-control scale` (the continuous scale alone): from
/// half resolution's scale, a budget every scale meets takes it to 1 after one frame, one
/// no scale can meet to the smallest, 0.25. `--resolution scaled --scale S` renders one
/// frame at scale S; `--scale` with another resolution, or out of range, is refused.
#[test]
fn render_orbit_holds_a_budget_by_scale() {
    let scales = |budget: &str| -> Vec<f32> {
        let (err, rows) = budget_orbit(&format!("budget-scale-{budget}"), budget, 4, Some("scale"));
        assert!(err.contains("frame    3: scale"), "per-frame lines: {err}");
        rows.iter().map(|c| c[1].parse().unwrap()).collect()
    };
    assert_eq!(scales("1000000"), [0.5, 1.0, 1.0, 1.0]);
    assert_eq!(scales("0.001"), [0.5, 0.25, 0.25, 0.25]);
    let d = scratch("scaled-one");
    let out = obscura(&[
        "render",
        "--width",
        "96",
        "--height",
        "64",
        "--resolution",
        "scaled",
        "--scale",
        "0.6",
        "--out",
        s(&d.join("ao.png")),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(d.join("ao.png").exists());
    std::fs::remove_dir_all(d).unwrap();
    assert_fails(
        "scale-without-scaled",
        &["render", "--scale", "0.5"],
        "--scale 0.5 needs --resolution scaled",
    );
    assert_fails(
        "scale-out-of-range",
        &["render", "--resolution", "scaled", "--scale", "0.1"],
        "scale",
    );
}

/// A budget below what the view costs at the cheapest setting is said once, by each
/// controller, and the run goes on (frames are written, exit 0).
#[test]
fn a_budget_that_cannot_be_held_says_so_once() {
    for control in ["joint", "scale", "ladder"] {
        let d = scratch(&format!("floor-{control}"));
        let out = obscura(&[
            "render",
            "--width",
            "160",
            "--height",
            "100",
            "--orbit",
            "20",
            "--frames",
            "6",
            "--out-dir",
            s(&d),
            "--budget-ms",
            "0.01",
            "--budget-control",
            control,
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{control}: {err}");
        assert_eq!(
            err.matches("cannot be held on this view").count(),
            1,
            "{control}: {err}"
        );
        assert!(
            d.join("frame_0005.png").exists(),
            "{control}: the orbit ran on"
        );
        std::fs::remove_dir_all(d).unwrap();
    }
}
