use super::*;
use crate::passes::estimators::{bitmask_pixel, gtao_pixel, Pixels, READS};
use crate::passes::uniforms::ortho_test_frame;
use crate::AoMode;
use glam::Vec4;

/// The model's fetches per AO invocation equal the texel reads of the CPU mirror (which
/// reads where the WGSL fetches) at a pixel whose samples all land on screen and on a
/// surface: a plane facing the camera, the radius (4 px) well inside a 33 × 33 frame.
/// GTAO and the bitmask, one and two depth layers, even and crowded marches, full
/// resolution and the 2×2 lattice. Exact.
#[test]
fn fetch_counts_match_the_mirrors_reads() {
    let (w, h) = (33u32, 33u32);
    let f = ortho_test_frame(w, h);
    let prepared = vec![Vec4::new(10.0, 0.0, 0.0, 1.0); (w * h) as usize];
    let behind = vec![12.0f32; (w * h) as usize];
    let centre = [16, 16];
    for estimator in [Estimator::Gtao, Estimator::Bitmask] {
        for (directions, steps) in [(3, 5), (2, 6), (4, 4), (1, 1)] {
            for march_exponent in [1.0, 1.3] {
                for lattice in [1, 2] {
                    for second_layer in [false, true] {
                        if second_layer && estimator != Estimator::Bitmask {
                            continue;
                        }
                        let px = Pixels {
                            f: &f,
                            directions,
                            steps,
                            march_exponent,
                            prepared: &prepared,
                            lattice,
                            pyramid: &[],
                            moments: &[],
                            second: if second_layer { &behind } else { &[] },
                        };
                        READS.with(|r| r.set(0));
                        let pattern = [0.6, 0.8, 0.37, 0.0];
                        match estimator {
                            Estimator::Gtao => gtao_pixel(&px, centre, pattern),
                            _ => bitmask_pixel(&px, centre, pattern),
                        };
                        let reads = READS.with(|r| r.get()) as f64;
                        let o = AoOptions {
                            estimator,
                            directions,
                            steps,
                            march_exponent,
                            ..Default::default()
                        };
                        let model = ao_work(&o, second_layer).unwrap().fetches;
                        assert_eq!(
                            model, reads,
                            "{estimator:?} {directions}×{steps} e {march_exponent} lattice \
                             {lattice} second layer {second_layer}"
                        );
                    }
                }
            }
        }
    }
}

/// Every pass of every layout's plan is listed once, prepare first, with invocations and
/// bytes; the default's three passes are all counted, and a bitmask invocation does more of
/// every kind of work than GTAO's at the same samples (a second layer more again).
#[test]
fn every_pass_is_listed_and_the_default_is_counted() {
    for mode in [
        AoMode::Randomized,
        AoMode::Deinterleaved2,
        AoMode::Deinterleaved4,
    ] {
        for fused in [false, true] {
            let o = AoOptions {
                mode,
                fused,
                ..Default::default()
            };
            let plan = Plan::new(&o, 1);
            let cost = frame_cost(&o, [1920, 1080], true);
            assert_eq!(cost.len(), plan.steps.len() + 1, "{mode:?} fused {fused}");
            assert!(cost[0].label.starts_with("prepare"));
            for (c, st) in cost[1..].iter().zip(&plan.steps) {
                assert_eq!(c.label, st.pass.label());
            }
            assert!(cost
                .iter()
                .all(|c| c.invocations >= 1920 * 1080 && c.bytes > 0));
        }
    }
    let default = frame_cost(&AoOptions::default(), [1920, 1080], true);
    assert_eq!(default.len(), 3);
    assert!(default.iter().all(|c| c.per_invocation.is_some()));
    let gtao = ao_work(&AoOptions::default(), false).unwrap();
    let bitmask_options = AoOptions {
        estimator: Estimator::Bitmask,
        ..Default::default()
    };
    let bitmask = ao_work(&bitmask_options, false).unwrap();
    let layered = ao_work(&bitmask_options, true).unwrap();
    for (a, b) in [(gtao, bitmask), (bitmask, layered)] {
        assert!(a.fetches <= b.fetches && a.special < b.special && a.alu < b.alu);
    }
}

/// The roofline takes the slowest unit on a GPU and the sum on lavapipe, and a pass the
/// model does not count has no time.
#[test]
fn the_roofline_takes_the_slowest_unit_and_lavapipe_the_sum() {
    let p = PassCost {
        label: "probe",
        invocations: 1000,
        per_invocation: Some(Work {
            fetches: 10.0,
            special: 2.0,
            alu: 100.0,
        }),
        bytes: 16_000,
    };
    let parts = |d: &Device| {
        [
            1000.0 * 10.0 * d.fetch,
            16_000.0 * d.byte,
            1000.0 * 100.0 * d.alu,
            1000.0 * 2.0 * d.special,
        ]
    };
    let (t, bound) = H200.time(&p).unwrap();
    let h = parts(&H200);
    assert_eq!(t, h.iter().cloned().fold(0.0, f64::max));
    assert_eq!(bound, Bound::Fetch, "{h:?}");
    let (t, bound) = LAVAPIPE.time(&p).unwrap();
    let sum: f64 = parts(&LAVAPIPE).iter().sum::<f64>() + 1000.0 * LAVAPIPE.invocation;
    assert!((t - sum).abs() <= 1e-12 * sum && bound == Bound::Sum);
    let uncounted = PassCost {
        per_invocation: None,
        ..p
    };
    assert_eq!(H200.time(&uncounted), None);
}
