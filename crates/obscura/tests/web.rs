//! obscura in a browser: the library compiled to wasm32 on WebGPU, run by wasm-bindgen-test
//! in headless Chromium (`bash scripts/web-test.sh`; docs/guide/web.md). The AO of an analytic
//! scene in each layout, with the denoiser and with a second depth layer, against the same
//! CPU mirrors the native GPU tests (tests/gpu/) hold lavapipe and real GPUs to, with the
//! same tolerance; bad input gives the same typed errors as natively.
#![cfg(target_arch = "wasm32")]

use obscura::{
    reference, AdapterChoice, Ao, AoInput, AoMode, AoOptions, AoParams, Denoise, Error, Estimator,
    GpuContext, Resolution, Viewport,
};
use wasm_bindgen_test::{wasm_bindgen_test, wasm_bindgen_test_configure};

#[path = "common/analytic.rs"]
mod analytic;

wasm_bindgen_test_configure!(run_in_browser);

const W: u32 = 96;
const H: u32 = 64;

async fn context() -> GpuContext {
    let ctx = GpuContext::request(&AdapterChoice::Auto, None)
        .await
        .unwrap_or_else(|e| panic!("no WebGPU adapter: {e}"));
    web_log(&format!("adapter: {}", ctx.describe()));
    ctx
}

fn web_log(s: &str) {
    wasm_bindgen_test::console_log!("{s}");
}

/// One frame of `options` on `depth` (and `second`, a second layer); the AO, the prepared
/// buffer where the layout has one, and the frame uniforms.
async fn run(
    ctx: &GpuContext,
    options: AoOptions,
    (depth, second): (&wgpu::Texture, Option<&wgpu::Texture>),
    params: &AoParams,
) -> (Vec<f32>, Vec<glam::Vec4>, obscura::uniforms::FrameUniforms) {
    let view = depth.create_view(&Default::default());
    let second_view = second.map(|t| t.create_view(&Default::default()));
    let mut ao = Ao::new(&ctx.device, options).unwrap();
    let input = AoInput {
        second_layer: second_view.as_ref(),
        ..analytic::input(&view, W, H)
    };
    let frame = ao.validate(&input, params).unwrap();
    ctx.run_async(|enc| ao.record(&ctx.device, &ctx.queue, enc, &input, params))
        .await
        .unwrap();
    let out = ctx.read_f32_async(ao.output().unwrap()).await.unwrap();
    let prepared = match ao.prepared_view() {
        Some(v) => ctx.read_f32_async(v.texture()).await.unwrap(),
        None => Vec::new(),
    };
    let prepared = prepared
        .chunks_exact(4)
        .map(glam::Vec4::from_slice)
        .collect();
    (out, prepared, frame)
}

/// [`analytic::assert_matches_mirror`], where something is occluded.
fn assert_matches_mirror(gpu: &[f32], cpu: &[f32], what: &str) {
    analytic::assert_matches_mirror(gpu, cpu, what);
    assert!(gpu.iter().any(|&a| a < 0.8), "{what}: nothing occluded");
}

/// GTAO and the bitmask, randomized, 2×2 and 4×4 (fused and unfused), without a denoiser;
/// the default frame (2×2 with the spatial denoiser); the bitmask with a second layer: each
/// against its CPU mirror on the browser's own prepared buffer.
#[wasm_bindgen_test]
async fn browser_ao_matches_the_cpu_mirrors() {
    let ctx = context().await;
    let depth = analytic::scene(W, H);
    let tex = ctx.upload_r32("depth", &depth, W, H);
    let params = AoParams {
        radius: 1.2,
        ..Default::default()
    };
    let randomized = AoOptions {
        mode: AoMode::Randomized,
        denoise: Denoise::None,
        ..Default::default()
    };
    let (_, prepared, _) = run(&ctx, randomized, (&tex, None), &params).await;
    assert_eq!(prepared.len(), (W * H) as usize);
    for estimator in [Estimator::Gtao, Estimator::Bitmask] {
        for (mode, fused) in [
            (AoMode::Randomized, true),
            (AoMode::Deinterleaved2, true),
            (AoMode::Deinterleaved4, true),
            (AoMode::Deinterleaved4, false),
        ] {
            let options = AoOptions {
                estimator,
                mode,
                fused,
                ..randomized
            };
            let (ao, _, frame) = run(&ctx, options, (&tex, None), &params).await;
            let cpu = reference::ao(&frame, &options, &prepared);
            assert_matches_mirror(&ao, &cpu, &format!("{options:?}"));
        }
    }
    // The default frame: the 2×2 AO, then the spatial denoiser.
    let options = AoOptions::default();
    let (ao, _, frame) = run(&ctx, options, (&tex, None), &params).await;
    let raw = reference::ao(
        &frame,
        &AoOptions {
            denoise: Denoise::None,
            ..options
        },
        &prepared,
    );
    let cpu = reference::denoise(&frame, &prepared, &raw, options.pattern_period());
    assert_matches_mirror(&ao, &cpu, "the default frame");
    // A second layer 0.8 behind the first on the image's left half.
    let second: Vec<f32> = depth
        .iter()
        .enumerate()
        .map(|(i, &d)| {
            if d > 0.0 && (i as u32 % W) < W / 2 {
                d + 0.8
            } else {
                0.0
            }
        })
        .collect();
    let back = ctx.upload_r32("second layer", &second, W, H);
    let options = AoOptions {
        estimator: Estimator::Bitmask,
        second_layer: true,
        ..randomized
    };
    let layered = AoParams {
        thickness: 0.25,
        ..params
    };
    let (ao, _, frame) = run(&ctx, options, (&tex, Some(&back)), &layered).await;
    let cpu = reference::ao_second_layer(&frame, &options, &prepared, &second);
    assert_matches_mirror(&ao, &cpu, "the bitmask with a second layer");
}

/// Every estimator at every fixed resolution, with the denoiser, a history and bent
/// normals where the estimator has them, and the scaled resolution: each compiles and runs
/// two frames in the browser with no WebGPU error (the uncaptured-error handler stays
/// empty), and its AO lies in [0, 1] with some occlusion.
#[wasm_bindgen_test]
async fn every_estimator_and_resolution_runs_in_the_browser() {
    let ctx = context().await;
    let tex = ctx.upload_r32("depth", &analytic::scene(W, H), W, H);
    let view = tex.create_view(&Default::default());
    let input = analytic::input(&view, W, H);
    let mut all = Vec::new();
    for estimator in Estimator::ALL {
        for resolution in [Resolution::Full, Resolution::Half, Resolution::Quarter] {
            all.push(AoOptions {
                estimator,
                resolution,
                history: 8,
                bent_normals: estimator.has_bent_normals(),
                ..AoOptions::default()
            });
        }
    }
    all.push(AoOptions {
        resolution: Resolution::Scaled,
        ..AoOptions::default()
    });
    for options in all {
        let what = format!("{options:?}");
        let mut ao = Ao::new(&ctx.device, options).unwrap_or_else(|e| panic!("{what}: {e}"));
        let params = AoParams {
            radius: 1.2,
            scale: if options.resolution == Resolution::Scaled {
                0.5
            } else {
                1.0
            },
            ..Default::default()
        };
        for _ in 0..2 {
            ctx.run_async(|enc| ao.record(&ctx.device, &ctx.queue, enc, &input, &params))
                .await
                .unwrap_or_else(|e| panic!("{what}: {e}"));
        }
        ctx.wait_async()
            .await
            .unwrap_or_else(|e| panic!("{what}: {e}"));
        let out = ctx.read_f32_async(ao.output().unwrap()).await.unwrap();
        assert!(
            out.iter().all(|a| (0.0..=1.0).contains(a)) && out.iter().any(|&a| a < 0.9),
            "{what}: AO outside [0, 1] or nothing occluded"
        );
    }
}

/// Bad input is refused before any GPU work with the native tests' typed errors.
#[wasm_bindgen_test]
async fn browser_refuses_bad_input_as_natively() {
    let ctx = context().await;
    let tex = ctx.upload_r32("depth", &analytic::scene(W, H), W, H);
    let view = tex.create_view(&Default::default());
    let ao = Ao::new(&ctx.device, AoOptions::default()).unwrap();
    let outside = AoInput {
        viewport: Some(Viewport {
            x: 50,
            y: 0,
            width: W,
            height: H,
        }),
        ..analytic::input(&view, W, H)
    };
    assert!(matches!(
        ao.validate(&outside, &AoParams::default()),
        Err(Error::InvalidViewport(_))
    ));
    let bad_radius = AoParams {
        radius: f32::NAN,
        ..Default::default()
    };
    let inside = AoInput {
        viewport: None,
        ..outside
    };
    assert!(matches!(
        ao.validate(&inside, &bad_radius),
        Err(Error::InvalidSetting {
            field: "radius",
            ..
        })
    ));
    let gtao_with_layer = AoOptions {
        second_layer: true,
        ..AoOptions::default()
    };
    assert!(matches!(
        Ao::new(&ctx.device, gtao_with_layer),
        Err(Error::InvalidSetting {
            field: "second_layer",
            ..
        })
    ));
}

/// Not a test but the browser's frame time (run by `bash scripts/web-test.sh --
/// --include-ignored`, printed on the console): the default frame (GTAO high, 2×2, the
/// spatial denoiser) at 1280×720 on the analytic scene at that size, 3 warm-up frames,
/// then the median of 10, each timed by the browser's clock from recording to the
/// completion of its work. Nothing is asserted on the time.
#[wasm_bindgen_test]
#[ignore = "a timing for BENCHMARKS.md, not a test: run with --include-ignored"]
async fn default_frame_time_at_720p() {
    let ctx = context().await;
    let (w, h) = (1280u32, 720u32);
    let depth = analytic::scene(w, h);
    let tex = ctx.upload_r32("depth", &depth, w, h);
    let view = tex.create_view(&Default::default());
    let mut ao = Ao::new(&ctx.device, AoOptions::default()).unwrap();
    let input = analytic::input(&view, w, h);
    let params = AoParams {
        radius: 1.2,
        ..Default::default()
    };
    let mut times = Vec::new();
    for k in 0..13 {
        let t = js_sys::Date::now();
        ctx.run_async(|enc| ao.record(&ctx.device, &ctx.queue, enc, &input, &params))
            .await
            .unwrap();
        ctx.wait_async().await.unwrap();
        if k >= 3 {
            times.push(js_sys::Date::now() - t);
        }
    }
    times.sort_by(f64::total_cmp);
    web_log(&format!(
        "web frame 1280x720 default: median {:.1} ms (min {:.1}, max {:.1}) over {} frames",
        times[times.len() / 2],
        times[0],
        times[times.len() - 1],
        times.len()
    ));
}
