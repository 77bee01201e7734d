//! obscura's demo page: the built-in courtyard rasterized in the browser
//! (obscura-scene's G-buffer), its AO computed by obscura on WebGPU, and shown as AO, lit,
//! or AO beside depth and normals, with an orbit camera and the main options. The page is
//! web/index.html; `bash scripts/web-demo.sh` builds and serves it (docs/guide/web.md).
//! Natively this crate is empty.
#![cfg(target_arch = "wasm32")]

use obscura::{
    AdapterChoice, Ao, AoMode, AoOptions, AoParams, CameraMotion, Denoise, Estimator, GpuContext,
    Preset, Resolution,
};
use obscura_scene::{default_scene, Camera, GBufferRenderer, GpuMesh};
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, Ordering};
use std::sync::Arc;
use wasm_bindgen::prelude::*;

/// Turns any error into the exception the page shows.
fn js<E: std::fmt::Display>(e: E) -> JsValue {
    JsValue::from_str(&e.to_string())
}

/// The page's state: device, canvas, scene, camera, options and the AO pipeline.
#[wasm_bindgen]
#[derive(Debug)]
pub struct Demo {
    ctx: GpuContext,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    raster: GBufferRenderer,
    mesh: GpuMesh,
    /// The scene's own camera; the orbit turns around its target.
    base: Camera,
    /// Orbit around the base camera's target: yaw and pitch (radians), distance.
    orbit: (f32, f32, f32),
    previous: Option<Camera>,
    estimator: Estimator,
    preset: Preset,
    options: AoOptions,
    ao: Ao,
    radius: f32,
    present: wgpu::RenderPipeline,
    view: wgpu::Buffer,
    mode: u32,
    /// The guard band rasterized around the view, pixels, and whether a second depth layer
    /// is peeled for the bitmask (AoInput::guard_band, AoInput::second_layer).
    guard: u32,
    second: bool,
    /// The last finished frame's time, ms (recording to completion), as f64 bits; the
    /// frames finished; whether one is in flight (a CPU adapter takes longer than a
    /// display refresh: frames queued faster than they finish would pile up until the
    /// browser's GPU watchdog loses the device).
    last_ms: Arc<AtomicU64>,
    finished: Arc<AtomicU32>,
    in_flight: Arc<AtomicBool>,
}

/// Starts the demo on `canvas`: the browser's WebGPU adapter, the courtyard uploaded, the
/// default options compiled.
#[wasm_bindgen]
pub async fn start(canvas: web_sys::HtmlCanvasElement) -> Result<Demo, JsValue> {
    let ctx = GpuContext::request(&AdapterChoice::Auto, None)
        .await
        .map_err(js)?;
    let (width, height) = (canvas.width().max(1), canvas.height().max(1));
    let surface = ctx
        .instance
        .create_surface(wgpu::SurfaceTarget::Canvas(canvas))
        .map_err(js)?;
    let config = surface
        .get_default_config(&ctx.adapter, width, height)
        .ok_or("the canvas cannot show this adapter's output")?;
    let format = config.format;
    surface.configure(&ctx.device, &config);
    let raster = GBufferRenderer::new(&ctx.device);
    let scene = default_scene::mesh();
    let radius = 0.03 * scene.bounds().ok_or("empty scene")?.diagonal();
    let mesh = raster.upload(&ctx, &scene).map_err(js)?;
    let base = default_scene::camera();
    let options = AoOptions::default();
    let ao = Ao::new(&ctx.device, options).map_err(js)?;
    let module = ctx
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("present"),
            source: wgpu::ShaderSource::Wgsl(include_str!("present.wgsl").into()),
        });
    let present = ctx
        .device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("present"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                buffers: &[],
                compilation_options: Default::default(),
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                targets: &[Some(format.into())],
                compilation_options: Default::default(),
            }),
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            multiview_mask: None,
            cache: None,
        });
    let view = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("present view"),
        size: 32,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    Ok(Demo {
        ctx,
        surface,
        config,
        raster,
        mesh,
        base,
        orbit: orbit_of(&base),
        previous: None,
        estimator: Estimator::Gtao,
        preset: Preset::High,
        options,
        ao,
        radius,
        present,
        view,
        mode: 1,
        guard: 0,
        second: false,
        last_ms: Arc::new(AtomicU64::new(0f64.to_bits())),
        finished: Arc::new(AtomicU32::new(0)),
        in_flight: Arc::new(AtomicBool::new(false)),
    })
}

/// The orbit (yaw, pitch, distance) that gives `camera`'s eye around its target.
fn orbit_of(camera: &Camera) -> (f32, f32, f32) {
    let offset = camera.eye - camera.target;
    (
        offset.x.atan2(offset.z),
        (offset.y / offset.length()).asin(),
        offset.length(),
    )
}

/// Sponza's standard view (obscura-eval's views.rs): eye, target, vertical field of view.
const SPONZA_VIEW: ([f32; 3], [f32; 3], f32) = ([-14.0, 2.0, 0.0], [10.0, 5.0, 0.0], 60.0);

/// `name` among `all`'s names, or the list of names.
fn pick<T: Copy>(all: &[T], name: impl Fn(T) -> &'static str, s: &str) -> Result<T, JsValue> {
    obscura::settings::by_name(all, name, s).map_err(|e| js(format!("`{s}`: {e}")))
}

#[wasm_bindgen]
impl Demo {
    /// The adapter, for the page.
    pub fn adapter(&self) -> String {
        let i = &self.ctx.info;
        let name = if i.name.is_empty() {
            "WebGPU adapter".to_string()
        } else {
            i.name.clone()
        };
        format!("{name} ({:?})", i.device_type)
    }

    /// Sets an option by the page's control name (`estimator`, `preset`, `layout`,
    /// `resolution`, `denoise`, `temporal`, `guard`, `second`, `view`) and recompiles the
    /// AO pipeline. A combination obscura refuses (a second layer without the bitmask, or
    /// below full resolution) leaves the last one running and throws its message.
    pub fn set(&mut self, control: &str, value: &str) -> Result<(), JsValue> {
        let mut o = self.options;
        match control {
            "estimator" => {
                self.estimator = pick(&Estimator::ALL, Estimator::name, value)?;
            }
            "preset" => {
                let names = |p: Preset| match p {
                    Preset::Low => "low",
                    Preset::Medium => "medium",
                    Preset::High => "high",
                    Preset::Ultra => "ultra",
                };
                self.preset = pick(&Preset::ALL, names, value)?;
            }
            "layout" => o.mode = pick(&AoMode::ALL, AoMode::name, value)?,
            "resolution" => o.resolution = pick(&Resolution::ALL, Resolution::name, value)?,
            "denoise" => o.denoise = pick(&Denoise::ALL, Denoise::name, value)?,
            "temporal" => o.history = value.parse().map_err(js)?,
            "guard" => {
                self.guard = value.parse().map_err(js)?;
                self.previous = None;
                return Ok(());
            }
            "second" => o.second_layer = value == "on",
            "view" => {
                self.mode = match value {
                    "ao" => 0,
                    "lit" => 1,
                    "split" => 2,
                    _ => return Err(js(format!("no view `{value}`"))),
                };
                return Ok(());
            }
            _ => return Err(js(format!("no control `{control}`"))),
        }
        o.estimator = self.estimator;
        // The preset's samples for this layout and resolution (`AoOptions::with_preset`).
        let o = o.with_preset(self.preset);
        self.ao = Ao::new(&self.ctx.device, o).map_err(js)?;
        self.options = o;
        self.second = o.second_layer;
        self.previous = None;
        Ok(())
    }

    /// Shows the built-in courtyard.
    pub fn use_courtyard(&mut self) -> Result<(), JsValue> {
        let scene = default_scene::mesh();
        self.switch(&scene, default_scene::camera())
    }

    /// Shows Sponza from the bytes of the shared scene's `.glb` (fetched by the page when
    /// the shared scenes are served beside it), from its standard view.
    pub fn use_sponza(&mut self, glb: &[u8]) -> Result<(), JsValue> {
        let scene = obscura_scene::Mesh::from_glb("sponza_dabrovic.glb", glb).map_err(js)?;
        let (eye, target, fov) = SPONZA_VIEW;
        let mut camera = Camera {
            eye: glam::Vec3::from(eye),
            target: glam::Vec3::from(target),
            up: glam::Vec3::Y,
            projection: obscura_scene::CameraProjection::Perspective { fov_y_deg: fov },
            near: 0.0,
            far: 0.0,
        };
        camera.fit_clip_planes(&scene.bounds().ok_or("empty scene")?);
        self.switch(&scene, camera)
    }

    fn switch(&mut self, scene: &obscura_scene::Mesh, camera: Camera) -> Result<(), JsValue> {
        self.mesh = self.raster.upload(&self.ctx, scene).map_err(js)?;
        self.radius = 0.03 * scene.bounds().ok_or("empty scene")?.diagonal();
        self.base = camera;
        self.orbit = orbit_of(&camera);
        self.previous = None;
        Ok(())
    }

    /// Turns the camera by a drag of `dx`, `dy` pixels.
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        self.orbit.0 -= dx * 0.01;
        self.orbit.1 = (self.orbit.1 + dy * 0.01).clamp(-1.4, 1.4);
    }

    /// Moves the camera toward the target (`delta` < 0) or away, as a wheel does.
    pub fn zoom(&mut self, delta: f32) {
        let base = (self.base.eye - self.base.target).length();
        self.orbit.2 = (self.orbit.2 * (1.0 + delta * 0.001)).clamp(0.2 * base, 4.0 * base);
    }

    fn camera(&self) -> Camera {
        let base = self.base;
        let (yaw, pitch, distance) = self.orbit;
        let dir = glam::Vec3::new(
            yaw.sin() * pitch.cos(),
            pitch.sin(),
            yaw.cos() * pitch.cos(),
        );
        Camera {
            eye: base.target + dir * distance,
            ..base
        }
    }

    /// Frames whose work has finished.
    pub fn frames(&self) -> u32 {
        self.finished.load(Ordering::Relaxed)
    }

    /// The last finished frame's time, ms, from recording to completion (0 before one).
    pub fn last_ms(&self) -> f64 {
        f64::from_bits(self.last_ms.load(Ordering::Relaxed))
    }

    /// Records one frame (G-buffer, AO, display) and presents it, unless the last one is
    /// still in flight (then nothing: call again on the next display refresh).
    pub fn frame(&mut self) -> Result<(), JsValue> {
        self.ctx.take_errors().map_err(js)?;
        if self.in_flight.load(Ordering::Relaxed) {
            return Ok(());
        }
        let (w, h) = (self.config.width, self.config.height);
        let cam = self.camera();
        let motion = match &self.previous {
            Some(p) => cam.motion_since(p),
            None => CameraMotion::Cut,
        };
        self.previous = Some(cam);
        let params = AoParams {
            radius: self.radius,
            motion,
            ..Default::default()
        };
        let start = now();
        let device = &self.ctx.device;
        let mut enc = device.create_command_encoder(&Default::default());
        let g = self
            .raster
            .record_guarded(&self.ctx, &mut enc, &self.mesh, &cam, (w, h), self.guard)
            .map_err(js)?;
        // The second layer, peeled at the thickness prior behind the first.
        let second = if self.second {
            let separation = params.thickness * self.radius;
            let layer = self
                .raster
                .record_peel(&self.ctx, &mut enc, &self.mesh, &cam, &g, separation)
                .map_err(js)?;
            Some(layer)
        } else {
            None
        };
        let input = obscura::AoInput {
            second_layer: second.as_ref().map(|l| &l.view),
            ..g.ao_input(&cam, true)
        };
        self.ao
            .record(device, &self.ctx.queue, &mut enc, &input, &params)
            .map_err(js)?;
        let ao = self.ao.output().ok_or("no AO output")?;
        let ao_view = ao.create_view(&Default::default());
        let view = [
            self.mode,
            w,
            cam.near.to_bits(),
            cam.far.to_bits(),
            self.guard,
            0,
            0,
            0,
        ];
        self.ctx
            .queue
            .write_buffer(&self.view, 0, bytemuck::cast_slice(&view));
        let target = self.surface.get_current_texture();
        let frame = match target {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            _ => return Err(js("the canvas has no texture to draw into this frame")),
        };
        let out = frame.texture.create_view(&Default::default());
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("present"),
            layout: &self.present.get_bind_group_layout(0),
            entries: &[
                texture_entry(0, &ao_view),
                texture_entry(1, &g.normals_view),
                texture_entry(2, &g.depth_view),
                texture_entry(3, &g.albedo_view),
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: self.view.as_entire_binding(),
                },
            ],
        });
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("present"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &out,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                ..Default::default()
            });
            pass.set_pipeline(&self.present);
            pass.set_bind_group(0, &bind, &[]);
            pass.draw(0..3, 0..1);
        }
        self.ctx.queue.submit([enc.finish()]);
        self.ctx.queue.present(frame);
        self.in_flight.store(true, Ordering::Relaxed);
        let (last, finished, in_flight) = (
            self.last_ms.clone(),
            self.finished.clone(),
            self.in_flight.clone(),
        );
        self.ctx.queue.on_submitted_work_done(move || {
            last.store((now() - start).to_bits(), Ordering::Relaxed);
            finished.fetch_add(1, Ordering::Relaxed);
            in_flight.store(false, Ordering::Relaxed);
        });
        Ok(())
    }
}

fn texture_entry(binding: u32, view: &wgpu::TextureView) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: wgpu::BindingResource::TextureView(view),
    }
}

/// The browser's clock, ms.
fn now() -> f64 {
    web_sys::window()
        .and_then(|w| w.performance())
        .map_or_else(js_sys::Date::now, |p| p.now())
}
