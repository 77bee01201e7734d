//! The controllers on fake clocks: scripted costs, recorded lavapipe noise, views that
//! change, against what a perfect controller would do.

use super::*;

/// Deterministic factors in [1 − `noise`, 1 + `noise`] (a linear congruential sequence).
fn jitter(noise: f64) -> impl FnMut() -> f64 {
    jitter_from(noise, 12345)
}

/// `jitter` with the sequence started at `seed`.
fn jitter_from(noise: f64, seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let u = (state >> 11) as f64 / (1u64 << 53) as f64;
        1.0 + noise * (2.0 * u - 1.0)
    }
}

/// A fake clock: level k costs `costs[k] × scene(frame)` ms, times a deterministic
/// ±`noise` jitter (a linear congruential sequence). Returns each frame's (level, ms).
fn run(
    c: &mut BudgetController,
    costs: &[f64],
    frames: u32,
    scene: impl Fn(u32) -> f64,
    noise: f64,
) -> Vec<(usize, f64)> {
    let mut jitter = jitter(noise);
    (0..frames)
        .map(|f| {
            let k = c.level();
            let ms = costs[k] * scene(f) * jitter();
            c.update(ms);
            (k, ms)
        })
        .collect()
}

/// The nominal costs are optimistic: each step truly costs 1.5–1.8× the one below where
/// the nominal ratio says 1.2–1.5× (fixed per-pass overheads make the opposite error
/// on real adapters; this one is the harder case, as the controller must try a level
/// and retreat).
const NOMINAL: [f64; 6] = [1.0, 1.5, 2.0, 2.5, 3.0, 4.0];
const TRUE: [f64; 6] = [3.0, 4.5, 7.0, 12.0, 20.0, 36.0];

fn changes(frames: &[(usize, f64)]) -> usize {
    frames.windows(2).filter(|w| w[0].0 != w[1].0).count()
}

/// Frames run at each level.
fn visits(frames: &[(usize, f64)], level: usize) -> usize {
    frames.iter().filter(|f| f.0 == level).count()
}

#[test]
fn settles_on_the_dearest_level_within_the_budget_and_stays() {
    // Budget 17 ms: level 3 (12 ms) fits; the optimistic nominal costs predict levels
    // 4 and 5 within it, so each is tried once (20, 36 ms), measured, and never again.
    let mut c = BudgetController::new(17.0, &NOMINAL).unwrap();
    let frames = run(&mut c, &TRUE, 100, |_| 1.0, 0.05);
    let after = &frames[20..];
    assert!(after.iter().all(|f| f.0 == 3), "levels {frames:?}");
    assert!(after.iter().all(|f| f.1 <= 17.0 * 1.15));
    assert!(
        visits(&frames, 4) <= 1 && visits(&frames, 5) <= 1,
        "{frames:?}"
    );
}

#[test]
fn measured_nominal_costs_reach_the_level_at_once() {
    // Nominal costs measured beforehand (the true ones): up to level 3 after the
    // settling frames, and nothing over the budget on the way.
    let mut c = BudgetController::new(17.0, &TRUE).unwrap();
    let frames = run(&mut c, &TRUE, 40, |_| 1.0, 0.05);
    assert!(
        frames[SETTLE_FRAMES as usize..].iter().all(|f| f.0 == 3),
        "{frames:?}"
    );
    assert!(frames.iter().all(|f| f.1 <= 17.0 * 1.05));
}

#[test]
fn a_budget_between_two_levels_does_not_oscillate() {
    // Level 2 costs 7 ms, level 3 12 ms: a 10 ms budget sits between them (level 3 is
    // predicted at 8.75 ms until tried). A PI loop on the level would cycle; this
    // settles on level 2 after one try of level 3.
    let mut c = BudgetController::new(10.0, &NOMINAL).unwrap();
    let frames = run(&mut c, &TRUE, 200, |_| 1.0, 0.05);
    assert_eq!(changes(&frames[20..]), 0, "levels {:?}", &frames[20..]);
    assert_eq!(frames[199].0, 2);
    assert_eq!(visits(&frames, 3), 1, "{frames:?}");
}

#[test]
fn follows_the_scene_down_and_back_up() {
    // The scene gets 1.8× dearer for frames 50..100 (a complex view), then cheap again.
    let mut c = BudgetController::new(15.0, &NOMINAL).unwrap();
    let scene = |f: u32| if (50..100).contains(&f) { 1.8 } else { 1.0 };
    let frames = run(&mut c, &TRUE, 160, scene, 0.05);
    // Down within 3 frames of the change, to the dearest level that fits (7 × 1.8 = 12.6).
    assert!(
        frames[53..100].iter().all(|f| f.0 == 2),
        "{:?}",
        &frames[48..100]
    );
    assert!(frames[53..100].iter().all(|f| f.1 <= 15.0 * 1.15));
    // Back to level 3 within 15 frames of the scene getting cheap again.
    assert!(
        frames[115..].iter().all(|f| f.0 == 3),
        "{:?}",
        &frames[100..]
    );
}

#[test]
fn bad_inputs_are_refused_or_ignored() {
    assert!(BudgetController::new(0.0, &NOMINAL).is_none());
    assert!(BudgetController::new(f64::NAN, &NOMINAL).is_none());
    assert!(BudgetController::new(10.0, &[]).is_none());
    assert!(BudgetController::new(10.0, &[1.0, -2.0]).is_none());
    let mut c = BudgetController::new(10.0, &NOMINAL).unwrap();
    assert_eq!(c.update(f64::NAN), 0);
    assert_eq!(c.update(-1.0), 0);
    // A zero time (an unsupported timestamp) would make the scene 0 and every later
    // prediction NaN: it is ignored, and the controller still climbs afterwards.
    assert_eq!(c.update(0.0), 0);
    assert!(c.predicted_ms(0).is_none());
    c.update(3.0);
    assert_eq!(c.predicted_ms(0), Some(3.0));
    assert!(c.predicted_ms(99).is_none());
    let frames = run(&mut c, &TRUE, 30, |_| 1.0, 0.0);
    assert!(frames[10..].iter().all(|f| f.0 == 2), "{frames:?}");
}

/// A fake clock for the scale controller: `floor + full × s²` ms times the scene, times
/// a deterministic ±`noise` jitter. Returns each frame's (scale, ms).
fn run_scaled(
    c: &mut ScaleController,
    floor: f64,
    full: f64,
    frames: u32,
    scene: impl Fn(u32) -> f64,
    noise: f64,
) -> Vec<(f32, f64)> {
    let mut jitter = jitter(noise);
    (0..frames)
        .map(|f| {
            let s = c.scale();
            let x = f64::from(s).powi(2);
            let ms = (floor + full * x) * scene(f) * jitter();
            c.update(ms);
            (s, ms)
        })
        .collect()
}

#[test]
fn scale_converges_without_overshoot_and_holds_the_budget() {
    // A floor of 15 ms and 50 ms more at scale 1 (lavapipe's 640×400 frame is about
    // that): a 30 ms budget needs s² = 0.3. Without noise the scale falls monotonically
    // from 1 to it (no overshoot, so no oscillation) and holds within the dead band.
    let mut c = ScaleController::new(30.0, 1.0).unwrap();
    let frames = run_scaled(&mut c, 15.0, 50.0, 60, |_| 1.0, 0.0);
    assert!(
        frames.windows(2).all(|w| w[1].0 <= w[0].0),
        "not monotone: {frames:?}"
    );
    assert!(
        frames[20..]
            .iter()
            .all(|f| (f.1 / 30.0 - 1.0).abs() <= 0.04),
        "{frames:?}"
    );
    // From below, the same: monotone up.
    let mut c = ScaleController::new(30.0, 0.25).unwrap();
    let frames = run_scaled(&mut c, 15.0, 50.0, 60, |_| 1.0, 0.0);
    assert!(frames.windows(2).all(|w| w[1].0 >= w[0].0), "{frames:?}");
    assert!(frames[20..]
        .iter()
        .all(|f| (f.1 / 30.0 - 1.0).abs() <= 0.04));
    // With ±10% noise per frame, every frame after the first 20 within 15%.
    let mut c = ScaleController::new(30.0, 0.5).unwrap();
    let frames = run_scaled(&mut c, 15.0, 50.0, 200, |_| 1.0, 0.10);
    let off = frames[20..]
        .iter()
        .filter(|f| (f.1 / 30.0 - 1.0).abs() > 0.15)
        .count();
    assert_eq!(off, 0, "{:?}", &frames[20..]);
}

/// Two recorded sequences of lavapipe's frame-to-frame noise: each frame's time over
/// the median of the nine frames around it, at a pinned scale on the Sponza orbit of
/// docs/budget.md (frames 2..100 of docs/budget/noise/scale1-round1.csv and
/// scale025-round2.csv; llvmpipe, 2 cores, 2026-11-25). Measured inputs to the fake
/// clock, not outputs of the controller.
const LAVAPIPE_NOISE: [[f64; 98]; 2] = [
    [
        0.8821, 1.2102, 1.1388, 0.9946, 1.0644, 0.9395, 0.9762, 0.9985, 1.0832, 1.2496, 0.7623,
        0.7443, 1.0000, 1.0000, 0.9760, 1.0000, 1.0015, 1.0887, 1.0000, 0.9636, 1.1345, 1.1255,
        1.0168, 1.0331, 1.0000, 0.9890, 1.0000, 0.9829, 0.9601, 1.0000, 1.0210, 1.0055, 0.9787,
        1.4378, 1.3177, 0.9506, 0.8990, 0.9290, 1.1247, 1.1079, 0.9942, 1.0042, 0.9986, 0.9872,
        1.0014, 1.3538, 0.9803, 1.0000, 0.7165, 1.0787, 1.4577, 1.4444, 1.4303, 0.9837, 1.0000,
        0.9816, 1.0166, 0.9949, 1.0000, 1.0325, 0.9691, 0.9886, 1.1546, 1.0018, 0.8214, 1.0707,
        1.0000, 1.2161, 1.1534, 1.1362, 0.9660, 0.8008, 1.1379, 0.9615, 0.9957, 1.0555, 1.0308,
        0.8753, 1.2360, 1.0000, 0.9735, 0.9825, 0.8985, 1.0321, 1.0068, 1.0013, 0.9921, 1.0438,
        0.9841, 0.9987, 1.0000, 1.0000, 1.0335, 0.9044, 1.0177, 1.2173, 1.0945, 1.0731,
    ],
    [
        1.0359, 0.9768, 0.9739, 0.9845, 1.0065, 1.0213, 1.0262, 0.9849, 0.9935, 0.9400, 1.0860,
        1.1741, 1.0000, 0.9937, 1.0863, 0.9882, 0.9822, 1.0461, 0.9845, 1.0525, 1.0822, 1.0087,
        1.0070, 1.0000, 0.9920, 0.9993, 1.0007, 1.0080, 0.9939, 0.9774, 0.9890, 0.9765, 1.0733,
        1.0762, 1.0071, 1.2497, 0.9930, 0.9746, 0.9741, 0.9628, 1.0083, 1.4499, 1.1269, 1.0000,
        0.9556, 0.9148, 1.0000, 0.9519, 1.5938, 1.1807, 1.0239, 1.0724, 0.6560, 0.8504, 1.0843,
        1.3253, 1.0279, 1.0088, 0.9747, 0.9998, 0.9956, 1.0261, 0.9923, 0.9935, 1.0966, 1.0000,
        0.9651, 1.0000, 1.0000, 0.9483, 1.0000, 1.1212, 1.0000, 0.9745, 0.9892, 1.0731, 0.9755,
        0.9766, 1.0131, 1.0001, 0.9689, 1.0280, 0.9987, 1.0000, 0.9837, 1.0065, 1.2087, 0.9780,
        0.9773, 1.0047, 0.9900, 1.0229, 1.0000, 1.0134, 0.9992, 0.9982, 1.0185, 0.9945,
    ],
];

#[test]
fn scale_holds_the_budget_as_well_as_lavapipe_noise_allows() {
    // The Sponza orbit's cost (about 8 ms + 44 ms·s² on the pinned runs), a view whose
    // cost swings ±25% over the orbit, and the recorded noise. The reference is a
    // controller with no tracking error, running each frame's expected cost exactly on
    // the budget: its frames are within 15% wherever the noise is. (A reference, not a
    // bound: the noise is taken about a centred median, and a controller aiming a little
    // off the budget can beat it by a frame or two.) From frame 10 on, the controller
    // must come within 8 of 88 frames of it; it is 7 and 3 short (docs/budget.md, "The
    // noise floor, replayed"), and fails with a gain of 0.1 (too slow for the view) or
    // 1.5 (chasing the noise).
    for (i, noise) in LAVAPIPE_NOISE.iter().enumerate() {
        let scene = |f: u32| 1.0 + 0.25 * (std::f64::consts::TAU * f64::from(f) / 98.0).sin();
        let mut c = ScaleController::new(25.0, 0.5).unwrap();
        let mut frame = 0;
        let frames: Vec<(f32, f64)> = noise
            .iter()
            .map(|&n| {
                let s = c.scale();
                let ms = (8.0 + 44.0 * f64::from(s).powi(2)) * scene(frame) * n;
                c.update(ms);
                frame += 1;
                (s, ms)
            })
            .collect();
        let within = |t: f64| (t / 25.0 - 1.0).abs() <= 0.15;
        let held = frames[10..].iter().filter(|f| within(f.1)).count();
        let best = noise[10..].iter().filter(|&&n| within(25.0 * n)).count();
        assert!(
            held + 8 >= best,
            "sequence {i}: {held} frames within 15%, the reference {best}"
        );
    }
}

#[test]
fn scale_follows_the_scene_and_stops_at_its_limits() {
    // The scene gets 1.8× dearer for frames 50..100, then cheap again: the time is back
    // within 10% of the budget 15 frames after each change.
    let mut c = ScaleController::new(40.0, 0.5).unwrap();
    let scene = |f: u32| if (50..100).contains(&f) { 1.8 } else { 1.0 };
    let frames = run_scaled(&mut c, 10.0, 60.0, 160, scene, 0.05);
    for range in [65..100, 115..160] {
        assert!(
            frames[range.clone()]
                .iter()
                .all(|f| (f.1 / 40.0 - 1.0).abs() <= 0.1),
            "{range:?}: {:?}",
            &frames[range.clone()]
        );
    }
    assert!(frames[99].0 < frames[49].0);
    // A budget no scale can meet stays at the smallest scale; one every scale meets
    // climbs to 1.
    let mut c = ScaleController::new(5.0, 1.0).unwrap();
    let frames = run_scaled(&mut c, 10.0, 60.0, 40, |_| 1.0, 0.0);
    assert_eq!(frames[39].0, crate::MIN_SCALE);
    let mut c = ScaleController::new(500.0, 0.25).unwrap();
    let frames = run_scaled(&mut c, 10.0, 60.0, 40, |_| 1.0, 0.0);
    assert_eq!(frames[39].0, 1.0);
    // Bad inputs.
    assert!(ScaleController::new(0.0, 1.0).is_none());
    assert!(ScaleController::new(10.0, f32::NAN).is_none());
    let mut c = ScaleController::new(10.0, 0.5).unwrap();
    assert_eq!(c.update(f64::NAN), 0.5);
    assert_eq!(c.update(0.0), 0.5);
}

/// A fake clock for the joint controller: the scaled AO costs `floor + full × s²`, ladder
/// level k costs `ladder[k]`, all times the scene and a deterministic ±`noise` jitter.
fn run_joint(
    c: &mut JointController,
    costs: (f64, f64, &[f64]),
    frames: u32,
    scene: impl Fn(u32) -> f64,
    noise: f64,
) -> Vec<(Knob, f64)> {
    run_joint_seeded(c, costs, frames, scene, noise, 12345)
}

/// `run_joint` with the jitter's sequence started at `seed`.
fn run_joint_seeded(
    c: &mut JointController,
    (floor, full, ladder): (f64, f64, &[f64]),
    frames: u32,
    scene: impl Fn(u32) -> f64,
    noise: f64,
    seed: u64,
) -> Vec<(Knob, f64)> {
    let mut jitter = jitter_from(noise, seed);
    (0..frames)
        .map(|f| {
            let k = c.knob();
            let cost = match k {
                Knob::Scale(s) => floor + full * f64::from(s).powi(2),
                Knob::Level(l) => ladder[l],
            };
            let ms = cost * scene(f) * jitter();
            c.update(ms);
            (k, ms)
        })
        .collect()
}

/// The scaled AO: a 10 ms floor and 40 ms more at scale 1, so it costs ladder level 0's
/// 26 ms at s² = 0.4 (the top). The ladder: 26, 29, 45 ms.
const LADDER_MS: [f64; 3] = [26.0, 29.0, 45.0];
const JOINT: (f64, f64, &[f64]) = (10.0, 40.0, &LADDER_MS);

fn joint(budget: f64, handover: f64) -> JointController {
    JointController::new(budget, 0.5, 0.4f32.sqrt(), &LADDER_MS, handover).unwrap()
}

fn ladder_changes(frames: &[(Knob, f64)]) -> usize {
    let on = |k: &Knob| matches!(k, Knob::Level(_));
    frames
        .windows(2)
        .filter(|w| on(&w[0].0) != on(&w[1].0))
        .count()
}

#[test]
fn joint_turns_the_scale_below_the_top_and_climbs_the_ladder_above_it() {
    // 20 ms: the scale settles at s² = 0.25 and never reaches the ladder.
    let mut c = joint(20.0, 1.0);
    let frames = run_joint(&mut c, JOINT, 100, |_| 1.0, 0.05);
    assert!(
        frames.iter().all(|f| matches!(f.0, Knob::Scale(_))),
        "{frames:?}"
    );
    assert!(
        frames[20..].iter().all(|f| (f.1 / 20.0 - 1.0).abs() <= 0.1),
        "{frames:?}"
    );
    // 33 ms: up the scale to the top, onto the ladder, up to level 1 (29 ms), and no
    // further (level 2 costs 45 ms); nothing over the budget by more than the noise.
    let mut c = joint(33.0, 1.0);
    let frames = run_joint(&mut c, JOINT, 100, |_| 1.0, 0.05);
    assert!(
        frames[20..].iter().all(|f| f.0 == Knob::Level(1)),
        "{frames:?}"
    );
    assert!(frames.iter().all(|f| f.1 <= 33.0 * 1.05), "{frames:?}");
    // 28 ms: the top and ladder level 0 both cost 26 ms, within the budget, but only 7%
    // under it, short of the 10% a climb asks for: the controller holds the top, or
    // (after three frames the noise puts 10% under) climbs once to level 0, which
    // fits, and stays. No switching back and forth, nothing over the budget but noise.
    for seed in [1, 2, 3, 12345] {
        let mut c = joint(28.0, 1.0);
        let frames = run_joint_seeded(&mut c, JOINT, 200, |_| 1.0, 0.05, seed);
        assert!(ladder_changes(&frames) <= 1, "seed {seed}: {frames:?}");
        assert!(frames[20..]
            .iter()
            .all(|f| f.0 == Knob::Scale(c.top_scale()) || f.0 == Knob::Level(0)));
        assert!(frames[20..].iter().all(|f| f.1 <= 28.0 * 1.05));
    }
}

#[test]
fn joint_leaves_the_ladder_for_the_scale_when_the_scene_gets_dearer_and_returns() {
    // 30 ms: ladder level 0 (26 ms) at first; 1.8× dearer for frames 50..100 puts it at
    // 47 ms, so the scale takes over and settles; then the ladder again.
    let mut c = joint(30.0, 1.0);
    let scene = |f: u32| if (50..100).contains(&f) { 1.8 } else { 1.0 };
    let frames = run_joint(&mut c, JOINT, 160, scene, 0.05);
    assert!(
        frames[20..50].iter().all(|f| f.0 == Knob::Level(0)),
        "{frames:?}"
    );
    assert!(
        frames[52..100]
            .iter()
            .all(|f| matches!(f.0, Knob::Scale(_))),
        "{:?}",
        &frames[48..100]
    );
    assert!(
        frames[65..100]
            .iter()
            .all(|f| (f.1 / 30.0 - 1.0).abs() <= 0.1),
        "{:?}",
        &frames[50..100]
    );
    assert!(
        frames[115..].iter().all(|f| f.0 == Knob::Level(0)),
        "{:?}",
        &frames[100..]
    );
    assert_eq!(ladder_changes(&frames), 3, "{frames:?}");
}

#[test]
fn joint_learns_a_wrong_handover_in_one_try() {
    // The caller says ladder level 0 costs what the top does; it costs 1.3× that (34 ms
    // against a 30 ms budget). One frame on the ladder, then the learned ratio keeps the
    // scale at the top for good.
    let mut c = joint(30.0, 1.0);
    let ladder = [26.0 * 1.3, 40.0, 60.0];
    let frames = run_joint(&mut c, (10.0, 40.0, &ladder), 200, |_| 1.0, 0.05);
    let on_ladder = frames
        .iter()
        .filter(|f| matches!(f.0, Knob::Level(_)))
        .count();
    assert_eq!(on_ladder, 1, "{frames:?}");
    assert!((c.handover() / 1.3 - 1.0).abs() < 0.1, "{}", c.handover());
    assert!(frames[30..]
        .iter()
        .all(|f| f.0 == Knob::Scale(c.top_scale())));
}

#[test]
fn joint_refuses_bad_inputs() {
    assert!(JointController::new(0.0, 0.5, 0.7, &LADDER_MS, 1.0).is_none());
    assert!(JointController::new(30.0, f32::NAN, 0.7, &LADDER_MS, 1.0).is_none());
    assert!(JointController::new(30.0, 0.5, f32::NAN, &LADDER_MS, 1.0).is_none());
    assert!(JointController::new(30.0, 0.5, 0.7, &[], 1.0).is_none());
    assert!(JointController::new(30.0, 0.5, 0.7, &LADDER_MS, 0.0).is_none());
    assert!(JointController::new(30.0, 0.5, 0.7, &LADDER_MS, f64::INFINITY).is_none());
    // The start is clamped to the top; bad times leave the knob as it is.
    let mut c = JointController::new(30.0, 1.0, 0.7, &LADDER_MS, 1.0).unwrap();
    assert_eq!(c.knob(), Knob::Scale(0.7));
    assert_eq!(c.update(f64::NAN), Knob::Scale(0.7));
    assert_eq!(c.update(-3.0), Knob::Scale(0.7));
}
