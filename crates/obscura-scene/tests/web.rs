//! The built-in courtyard in a browser against the same view natively: rasterized by
//! obscura-scene and shaded by obscura's default AO on WebGPU in headless Chromium, and on
//! lavapipe by `obscura render` (scripts/web-test.sh renders it first and hands it over in
//! `OBSCURA_WEB_NATIVE`; build.rs). docs/guide/web.md.
#![cfg(target_arch = "wasm32")]

use obscura::{AdapterChoice, Ao, AoOptions, AoParams, GpuContext};
use obscura_scene::{default_scene, GBufferRenderer};
use wasm_bindgen_test::{wasm_bindgen_test, wasm_bindgen_test_configure};

wasm_bindgen_test_configure!(run_in_browser);

/// The native render's size (scripts/web-test.sh).
const W: u32 = 160;
const H: u32 = 100;

const NATIVE: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/native_courtyard.npy"));

/// The values of a little-endian float32 `.npy` of `n` values.
fn npy_values(bytes: &[u8], n: usize) -> Vec<f32> {
    assert!(
        bytes.len() > 10 && bytes.starts_with(b"\x93NUMPY"),
        "no native AO: run the browser tests with `bash scripts/web-test.sh`"
    );
    let header = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let data = &bytes[10 + header..];
    assert_eq!(data.len(), 4 * n, "the native AO is not {W}x{H}");
    data.chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

/// The default AO (GTAO high, 2×2, the spatial denoiser) of the default camera at 160×100,
/// radius 3% of the scene's diagonal, G-buffer normals: `obscura render`'s defaults.
/// Tolerance: two rasterizers (SwiftShader's and lavapipe's) may cover a triangle's edge
/// pixels differently (a pixel may then show another surface, and differ by anything) and
/// the denoiser spreads such a difference over a few pixels, so: at least 97% of pixels
/// within 0.01 of native, at most 1% beyond 0.1, and a mean absolute difference under
/// 0.003. (Measured: 98.7% within 0.01, mean 0.0011.)
#[wasm_bindgen_test]
async fn courtyard_ao_matches_native() {
    let native = npy_values(NATIVE, (W * H) as usize);
    let ctx = GpuContext::request(&AdapterChoice::Auto, None)
        .await
        .unwrap();
    let raster = GBufferRenderer::new(&ctx.device);
    let scene = default_scene::mesh();
    let radius = 0.03 * scene.bounds().unwrap().diagonal();
    let mesh = raster.upload(&ctx, &scene).unwrap();
    let cam = default_scene::camera();
    let mut ao = Ao::new(&ctx.device, AoOptions::default()).unwrap();
    let params = AoParams {
        radius,
        ..Default::default()
    };
    let mut gbuffer = None;
    ctx.run_async(|enc| {
        let g = raster
            .record_guarded(&ctx, enc, &mesh, &cam, (W, H), 0)
            .map_err(|e| obscura::Error::Gpu(e.to_string()))?;
        ao.record(
            &ctx.device,
            &ctx.queue,
            enc,
            &g.ao_input(&cam, true),
            &params,
        )?;
        gbuffer = Some(g);
        Ok(())
    })
    .await
    .unwrap();
    let web = ctx.read_f32_async(ao.output().unwrap()).await.unwrap();
    let diffs: Vec<f32> = web
        .iter()
        .zip(&native)
        .map(|(a, b)| (a - b).abs())
        .collect();
    let close = diffs.iter().filter(|d| **d <= 0.01).count();
    let far = diffs.iter().filter(|d| **d > 0.1).count();
    let mean = diffs.iter().sum::<f32>() / diffs.len() as f32;
    let n = diffs.len() as f32;
    wasm_bindgen_test::console_log!(
        "courtyard {W}x{H}: {close}/{n} within 0.01 of native, {far} beyond 0.1, mean |diff| {mean:.5}"
    );
    assert!(
        close as f32 >= 0.97 * n && far as f32 <= 0.01 * n && mean < 0.003,
        "browser against native: {close}/{n} within 0.01, {far} beyond 0.1, mean |diff| {mean}"
    );
    assert!(native.iter().any(|&a| a < 0.7), "the courtyard is occluded");
}
