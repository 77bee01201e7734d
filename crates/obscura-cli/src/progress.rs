//! Progress on stderr: a bar redrawn in place over an orbit's frames, and a ray tracer's
//! tenths done.

use std::time::Instant;

/// One line of progress on stderr, redrawn in place: `[=====     ] 5/10 path`.
pub(crate) fn progress(done: u32, total: u32, what: &std::path::Path) {
    let width = 30;
    let filled = (done as usize * width) / total.max(1) as usize;
    eprint!(
        "\r[{}{}] {done}/{total} {}",
        "=".repeat(filled),
        " ".repeat(width - filled),
        what.display()
    );
}

/// A tracer's progress callback: prints `  LABEL: N% (T s)` at each tenth of the rows,
/// T counted from `start`.
pub(crate) fn tenths(label: &str, start: Instant) -> impl Fn(usize, usize) + Sync + '_ {
    let last = std::sync::atomic::AtomicUsize::new(0);
    move |done, total| {
        let pct = done * 10 / total;
        if last.fetch_max(pct, std::sync::atomic::Ordering::Relaxed) < pct {
            eprintln!(
                "  {label}: {}% ({:.0} s)",
                pct * 10,
                start.elapsed().as_secs_f64()
            );
        }
    }
}
