//! Every shared mesh loads and rasterizes without a wgpu error; the default scene's AO
//! has real occlusion; bad scene files give typed errors. Needs `../shared/scenes`
//! beside the repository (as on every developer machine and in CI) and fails without it.

use obscura::{
    Ao, AoInput, AoMode, AoOptions, AoParams, Denoise, Estimator, GpuContext, NormalEncoding,
    Preset,
};
use obscura_scene::gbuffer::MSAA_SAMPLES;
use obscura_scene::{
    default_scene, Camera, CameraProjection, GBufferRenderer, Mesh, MsaaDepth, SceneError,
    DEPTH_CONVENTION, SKY_DEPTH,
};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};

mod loading;
mod msaa;
mod raster;

fn ctx() -> &'static GpuContext {
    static CTX: OnceLock<GpuContext> = OnceLock::new();
    CTX.get_or_init(|| GpuContext::new().unwrap_or_else(|e| panic!("needs a Vulkan adapter: {e}")))
}

fn lock() -> std::sync::MutexGuard<'static, ()> {
    static LOCK: Mutex<()> = Mutex::new(());
    LOCK.lock().unwrap_or_else(|p| p.into_inner())
}

fn shared_scenes() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes");
    assert!(
        dir.is_dir(),
        "shared scenes not found at {} (clone the repo beside shared/)",
        dir.display()
    );
    dir
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("obscura-scene-test-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Renders `mesh` and computes AO in the default mode; returns (depth, ao) read back.
fn render(mesh: &Mesh, cam: &Camera, w: u32, h: u32, radius: f32) -> (Vec<f32>, Vec<f32>) {
    render_with(mesh, cam, w, h, radius, AoOptions::default())
}

fn render_with(
    mesh: &Mesh,
    cam: &Camera,
    w: u32,
    h: u32,
    radius: f32,
    options: AoOptions,
) -> (Vec<f32>, Vec<f32>) {
    let c = ctx();
    let raster = GBufferRenderer::new(&c.device);
    let gm = raster.upload(c, mesh).unwrap();
    let g = raster.render(c, &gm, cam, w, h).unwrap();
    let mut ao = Ao::new(&c.device, options).unwrap();
    let input = AoInput {
        depth: &g.depth_view,
        convention: DEPTH_CONVENTION,
        projection: cam.obscura_projection(w as f32 / h as f32),
        normals: Some((&g.normals_view, NormalEncoding::ViewSigned)),
        viewport: None,
        guard_band: 0,
        second_layer: None,
        output: None,
    };
    let params = AoParams {
        radius,
        ..Default::default()
    };
    c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &params))
        .unwrap();
    (
        c.read_f32(&g.depth).unwrap(),
        c.read_f32(ao.output().unwrap()).unwrap(),
    )
}

fn rmse(a: &[f32], b: &[f32]) -> f32 {
    (a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f32>() / a.len() as f32).sqrt()
}
