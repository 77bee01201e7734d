//! Not a test but the native twin of the browser's frame time (tests/web.rs,
//! `default_frame_time_at_720p`): the same scene, frame and count on this machine's
//! adapter, timed by the wall clock around each frame's submit and wait. Run with
//! `cargo test --release -p obscura --test gpu -- --ignored default_frame_time --nocapture`;
//! nothing is asserted on the time.

use crate::analytic;
use obscura::{Ao, AoOptions, AoParams};

#[test]
#[ignore = "a timing for BENCHMARKS.md, not a test: run with --ignored"]
fn default_frame_time_at_720p_native() {
    let _g = crate::lock();
    let c = crate::ctx();
    let (w, h) = (1280u32, 720u32);
    let tex = crate::upload_r32(&analytic::scene(w, h), w, h);
    let view = tex.create_view(&Default::default());
    let mut ao = Ao::new(&c.device, AoOptions::default()).unwrap();
    let input = analytic::input(&view, w, h);
    let params = AoParams {
        radius: 1.2,
        ..Default::default()
    };
    let mut times = Vec::new();
    for k in 0..13 {
        let t = std::time::Instant::now();
        c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &params))
            .unwrap();
        if k >= 3 {
            times.push(t.elapsed().as_secs_f64() * 1e3);
        }
    }
    times.sort_by(f64::total_cmp);
    println!(
        "native frame 1280x720 default on {}: median {:.1} ms (min {:.1}, max {:.1}) over {} frames",
        c.describe(),
        times[times.len() / 2],
        times[0],
        times[times.len() - 1],
        times.len()
    );
}
