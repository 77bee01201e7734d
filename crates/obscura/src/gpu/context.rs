//! A headless GPU context: instance, adapter choice, device and queue, plus checked
//! submission and texture read-back for tools and tests.
//!
//! Adapter choice: a hardware adapter is preferred; Mesa's lavapipe (a CPU Vulkan driver)
//! is the fallback. `OBSCURA_ADAPTER=cpu|gpu|<name substring>` forces a choice.
//!
//! On the web (wasm32, WebGPU) nothing may block: [`GpuContext::request`],
//! [`GpuContext::run_async`] and [`GpuContext::read_f32_async`] are the asynchronous
//! forms, and the blocking ones are native only (docs/guide/web.md).

use crate::{Error, Result};
use std::sync::{Arc, Mutex};

/// The environment variable that forces the adapter choice.
pub const ADAPTER_ENV: &str = "OBSCURA_ADAPTER";

/// Set (to anything) to keep Mesa's Vulkan device-select layer, which obscura's front ends
/// (the CLI, the Python package) otherwise turn off with `NODEVICE_SELECT=1`: on a machine
/// without a display server it prints "error: XDG_RUNTIME_DIR is invalid or not set" twice
/// per device, though nothing failed, and obscura chooses its adapter itself
/// ([`ADAPTER_ENV`]).
pub const DEVICE_SELECT_ENV: &str = "OBSCURA_DEVICE_SELECT";

/// Whether a front end should set `NODEVICE_SELECT=1` before its first device: unless the
/// user set `NODEVICE_SELECT` (any value turns the layer off) or [`DEVICE_SELECT_ENV`].
pub fn quiet_device_select() -> bool {
    std::env::var_os("NODEVICE_SELECT").is_none() && std::env::var_os(DEVICE_SELECT_ENV).is_none()
}

/// Which adapter to use.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub enum AdapterChoice {
    /// The best available: discrete GPU, then integrated, virtual, other, then CPU drivers.
    #[default]
    Auto,
    /// A CPU (software) adapter only, e.g. lavapipe.
    Cpu,
    /// A hardware adapter only.
    Gpu,
    /// The first adapter whose name contains this text (case-insensitive).
    Name(String),
}

impl AdapterChoice {
    /// Reads [`ADAPTER_ENV`]; unset or empty means [`AdapterChoice::Auto`].
    pub fn from_env() -> Self {
        match std::env::var(ADAPTER_ENV) {
            Ok(v) => Self::parse(&v),
            Err(_) => AdapterChoice::Auto,
        }
    }

    /// `auto`, `cpu`, `gpu`, or a name substring.
    pub fn parse(s: &str) -> Self {
        match s.trim().to_ascii_lowercase().as_str() {
            "" | "auto" => AdapterChoice::Auto,
            "cpu" => AdapterChoice::Cpu,
            "gpu" => AdapterChoice::Gpu,
            other => AdapterChoice::Name(other.to_string()),
        }
    }

    fn accepts(&self, info: &wgpu::AdapterInfo) -> bool {
        let cpu = info.device_type == wgpu::DeviceType::Cpu;
        match self {
            AdapterChoice::Auto => true,
            AdapterChoice::Cpu => cpu,
            AdapterChoice::Gpu => !cpu,
            AdapterChoice::Name(n) => info.name.to_ascii_lowercase().contains(n.as_str()),
        }
    }
}

/// Native compute APIs only: the GL backend lacks storage-texture formats obscura needs
/// and, headless, probes for a display server. In a browser: WebGPU.
#[cfg(not(target_arch = "wasm32"))]
const BACKENDS: wgpu::Backends = wgpu::Backends::PRIMARY;
#[cfg(target_arch = "wasm32")]
const BACKENDS: wgpu::Backends = wgpu::Backends::BROWSER_WEBGPU;

/// Preference rank of an adapter: lower is better.
fn rank(info: &wgpu::AdapterInfo) -> (u8, u8) {
    let kind = match info.device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Other => 3,
        wgpu::DeviceType::Cpu => 4,
    };
    // Native compute APIs before GL.
    let backend = match info.backend {
        wgpu::Backend::Vulkan | wgpu::Backend::Metal | wgpu::Backend::Dx12 => 0,
        _ => 1,
    };
    (kind, backend)
}

/// Errors reported asynchronously by wgpu, collected instead of panicking.
#[derive(Debug, Default)]
struct ErrorSink {
    uncaptured: Vec<String>,
    lost: Option<String>,
}

/// Instance, adapter, device and queue.
#[derive(Debug)]
pub struct GpuContext {
    pub instance: wgpu::Instance,
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    /// Name, backend and type of the chosen adapter.
    pub info: wgpu::AdapterInfo,
    sink: Arc<Mutex<ErrorSink>>,
}

impl GpuContext {
    /// Creates a context on the adapter chosen by [`AdapterChoice::from_env`].
    #[cfg(not(target_arch = "wasm32"))]
    pub fn new() -> Result<Self> {
        Self::with_choice(&AdapterChoice::from_env())
    }

    /// Creates a context on the best adapter that `choice` accepts, with every limit the
    /// adapter offers.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn with_choice(choice: &AdapterChoice) -> Result<Self> {
        Self::with_limits(choice, None)
    }

    /// As [`GpuContext::with_choice`], requesting `limits` instead of the adapter's own
    /// (`Some(wgpu::Limits::default())`: WebGPU's default limits, what a browser gives).
    #[cfg(not(target_arch = "wasm32"))]
    pub fn with_limits(choice: &AdapterChoice, limits: Option<wgpu::Limits>) -> Result<Self> {
        pollster::block_on(Self::request(choice, limits))
    }

    /// The adapters `instance` offers: every native one, or the browser's WebGPU adapter.
    #[cfg(not(target_arch = "wasm32"))]
    async fn adapters(instance: &wgpu::Instance) -> Vec<wgpu::Adapter> {
        instance.enumerate_adapters(BACKENDS).await
    }

    #[cfg(target_arch = "wasm32")]
    async fn adapters(instance: &wgpu::Instance) -> Vec<wgpu::Adapter> {
        let options = wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        };
        instance
            .request_adapter(&options)
            .await
            .into_iter()
            .collect()
    }

    /// [`GpuContext::with_limits`] without blocking: the constructor on the web, where the
    /// adapter is the browser's WebGPU adapter (`choice` may still refuse it by kind or
    /// name), and every error goes to the device's uncaptured-error handler
    /// ([`GpuContext::take_errors`]) instead of a blocking error scope.
    pub async fn request(choice: &AdapterChoice, limits: Option<wgpu::Limits>) -> Result<Self> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: BACKENDS,
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        let adapters = Self::adapters(&instance).await;
        let names: Vec<String> = adapters
            .iter()
            .map(|a| {
                let i = a.get_info();
                format!("{} ({:?}, {:?})", i.name, i.backend, i.device_type)
            })
            .collect();
        let adapter = adapters
            .into_iter()
            .filter(|a| choice.accepts(&a.get_info()))
            .min_by_key(|a| rank(&a.get_info()))
            .ok_or_else(|| {
                if names.is_empty() && cfg!(target_arch = "wasm32") {
                    Error::NoAdapter(
                        "the browser offers no WebGPU adapter (is WebGPU on? Chromium offers a \
                         CPU adapter only with --enable-unsafe-webgpu)"
                            .into(),
                    )
                } else if names.is_empty() {
                    Error::NoAdapter(
                        "no Vulkan, Metal or DX12 adapter exists on this machine. \
                         Install a GPU driver, or Mesa's software Vulkan driver: \
                         `sudo apt-get install -y mesa-vulkan-drivers` (Debian/Ubuntu)"
                            .into(),
                    )
                } else {
                    Error::NoAdapter(format!(
                        "{ADAPTER_ENV}={choice:?} matches none of the adapters found: {}",
                        names.join("; ")
                    ))
                }
            })?;
        let info = adapter.get_info();
        // Only features that are useful and present: timestamps where the adapter has them.
        let required_features = adapter.features() & wgpu::Features::TIMESTAMP_QUERY;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("obscura"),
                required_features,
                required_limits: limits.unwrap_or_else(|| adapter.limits()),
                ..Default::default()
            })
            .await
            .map_err(|e| Error::DeviceCreation {
                adapter: info.name.clone(),
                reason: e.to_string(),
            })?;
        let sink = Arc::new(Mutex::new(ErrorSink::default()));
        let s = sink.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut s) = s.lock() {
                s.uncaptured.push(e.to_string());
            }
        }));
        let s = sink.clone();
        device.set_device_lost_callback(move |reason, msg| {
            if let Ok(mut s) = s.lock() {
                s.lost = Some(format!("{reason:?}: {msg}"));
            }
        });
        Ok(Self {
            instance,
            adapter,
            device,
            queue,
            info,
            sink,
        })
    }

    /// One line describing the adapter, for logs.
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {:?}, driver {} {})",
            self.info.name,
            self.info.backend,
            self.info.device_type,
            self.info.driver,
            self.info.driver_info
        )
    }

    /// True when the device can write timestamps (real GPUs; on lavapipe they do not
    /// bracket dispatches, so obscura times with the wall clock there).
    pub fn has_timestamps(&self) -> bool {
        self.device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY)
            && self.info.device_type != wgpu::DeviceType::Cpu
    }

    /// Returns and clears errors wgpu reported outside an error scope, or a lost device.
    pub fn take_errors(&self) -> Result<()> {
        let mut s = self
            .sink
            .lock()
            .map_err(|_| Error::Gpu("error sink poisoned".into()))?;
        if let Some(lost) = &s.lost {
            return Err(Error::DeviceLost(lost.clone()));
        }
        if !s.uncaptured.is_empty() {
            let all = std::mem::take(&mut s.uncaptured).join("\n");
            return Err(Error::Gpu(all));
        }
        Ok(())
    }

    /// Runs `record` inside validation and out-of-memory error scopes, submits, waits for
    /// the GPU, and turns any wgpu error into [`Error::Gpu`], [`Error::OutOfMemory`] or
    /// [`Error::DeviceLost`].
    #[cfg(not(target_arch = "wasm32"))]
    pub fn run<T>(&self, record: impl FnOnce(&mut wgpu::CommandEncoder) -> Result<T>) -> Result<T> {
        let (value, index) = pollster::block_on(self.submit_checked(record))?;
        self.wait(index)?;
        self.take_errors()?;
        Ok(value)
    }

    /// [`GpuContext::run`] without blocking: records inside the error scopes, submits, and
    /// awaits the scopes (not the GPU work: a later [`GpuContext::read_f32_async`] waits
    /// for it, as submissions finish in order).
    pub async fn run_async<T>(
        &self,
        record: impl FnOnce(&mut wgpu::CommandEncoder) -> Result<T>,
    ) -> Result<T> {
        let (value, _) = self.submit_checked(record).await?;
        self.take_errors()?;
        Ok(value)
    }

    /// Records `record` inside validation and out-of-memory error scopes and submits it;
    /// the scopes' errors (wgpu-core reports recording and submission errors synchronously,
    /// so natively they resolve at once) come back before anyone waits on a submission
    /// that may not exist.
    async fn submit_checked<T>(
        &self,
        record: impl FnOnce(&mut wgpu::CommandEncoder) -> Result<T>,
    ) -> Result<(T, wgpu::SubmissionIndex)> {
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("obscura"),
            });
        let value = record(&mut encoder);
        let index = self.queue.submit([encoder.finish()]);
        let v_err = validation.pop().await;
        let o_err = oom.pop().await;
        if let Some(e) = o_err.or(v_err) {
            self.take_errors()?;
            return Err(e.into());
        }
        Ok((value?, index))
    }

    /// Blocks until submission `index` has finished.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn wait(&self, index: wgpu::SubmissionIndex) -> Result<()> {
        self.device
            .poll(wgpu::PollType::Wait {
                submission_index: Some(index),
                timeout: None,
            })
            .map(|_| ())
            .map_err(|e| Error::DeviceLost(e.to_string()))
    }

    /// Reads a whole 2D texture or texture array (mip 0, every layer, layer-major) back as
    /// tightly packed bytes.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn read_texture(&self, texture: &wgpu::Texture) -> Result<Vec<u8>> {
        self.read_texture_mip(texture, 0)
    }

    /// As [`GpuContext::read_texture`], for mip level `mip`.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn read_texture_mip(&self, texture: &wgpu::Texture, mip: u32) -> Result<Vec<u8>> {
        let copy = self.copy_out(texture, mip)?;
        self.run(|enc| {
            copy.record(enc, texture);
            Ok(())
        })?;
        Ok(copy.unpad(&self.map_read(&copy.buffer)?))
    }

    /// [`GpuContext::read_texture`] without blocking (mip 0).
    pub async fn read_texture_async(&self, texture: &wgpu::Texture) -> Result<Vec<u8>> {
        let copy = self.copy_out(texture, 0)?;
        self.run_async(|enc| {
            copy.record(enc, texture);
            Ok(())
        })
        .await?;
        Ok(copy.unpad(&self.map_read_async(&copy.buffer).await?))
    }

    /// [`GpuContext::read_f32`] without blocking.
    pub async fn read_f32_async(&self, texture: &wgpu::Texture) -> Result<Vec<f32>> {
        Ok(bytemuck::pod_collect_to_vec(
            &self.read_texture_async(texture).await?,
        ))
    }

    /// [`GpuContext::map_read`] without blocking: resolves when the buffer is mapped (on
    /// the web, once the browser has run the work before it; natively it must be polled).
    pub async fn map_read_async(&self, buffer: &wgpu::Buffer) -> Result<Vec<u8>> {
        let slice = buffer.slice(..);
        let mapped = Signal::default();
        let done = mapped.clone();
        slice.map_async(wgpu::MapMode::Read, move |r| done.set(r));
        mapped
            .await
            .ok_or_else(|| Error::Gpu("buffer mapping lost".into()))?
            .map_err(|e| Error::Gpu(e.to_string()))?;
        let data = super::compat::mapped_bytes(&slice)?;
        buffer.unmap();
        Ok(data)
    }

    /// Resolves when the work submitted so far has finished (on the web; natively the
    /// device must be polled for it to resolve).
    pub async fn wait_async(&self) -> Result<()> {
        let finished = Signal::default();
        let done = finished.clone();
        self.queue.on_submitted_work_done(move || done.set(()));
        finished
            .await
            .ok_or_else(|| Error::Gpu("submitted-work callback lost".into()))?;
        self.take_errors()
    }

    /// The read-back buffer of `texture`'s mip `mip` and how to copy into it.
    fn copy_out(&self, texture: &wgpu::Texture, mip: u32) -> Result<CopyOut> {
        let format = texture.format();
        let bpp = format
            .block_copy_size(Some(wgpu::TextureAspect::All))
            .or_else(|| format.block_copy_size(Some(wgpu::TextureAspect::DepthOnly)))
            .ok_or(Error::UnsupportedFormat {
                what: "read-back",
                format,
                expected: "a single-aspect colour or depth format",
            })?;
        if mip >= texture.mip_level_count() {
            return Err(Error::Gpu(format!(
                "mip {mip} of a texture with {} levels",
                texture.mip_level_count()
            )));
        }
        let size = texture.size().mip_level_size(mip, texture.dimension());
        let (w, h) = (size.width, size.height);
        let rows = h * texture.depth_or_array_layers();
        let row = w * bpp;
        let padded =
            row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("obscura read-back"),
            size: padded as u64 * rows as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        Ok(CopyOut {
            buffer,
            mip,
            size,
            padded,
            row,
            rows,
        })
    }

    /// Maps a `MAP_READ` buffer whose writes were submitted, and copies its contents out.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn map_read(&self, buffer: &wgpu::Buffer) -> Result<Vec<u8>> {
        let slice = buffer.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| Error::DeviceLost(e.to_string()))?;
        rx.recv()
            .map_err(|e| Error::Gpu(e.to_string()))?
            .map_err(|e| Error::Gpu(e.to_string()))?;
        let data = super::compat::mapped_bytes(&slice)?;
        buffer.unmap();
        Ok(data)
    }

    /// An `R32Float` texture holding `data` (row-major, `width` × `height`), readable by
    /// shaders (`TEXTURE_BINDING`): linear depth from the CPU, for [`crate::AoInput`].
    pub fn upload_r32(&self, label: &str, data: &[f32], width: u32, height: u32) -> wgpu::Texture {
        self.upload(
            label,
            bytemuck::cast_slice(data),
            width,
            height,
            wgpu::TextureFormat::R32Float,
        )
    }

    /// An `Rgba32Float` texture holding `data` (row-major, `width` × `height`), readable by
    /// shaders: normals from the CPU ([`crate::NormalEncoding::ViewSigned`]).
    pub fn upload_rgba32(
        &self,
        label: &str,
        data: &[[f32; 4]],
        width: u32,
        height: u32,
    ) -> wgpu::Texture {
        self.upload(
            label,
            bytemuck::cast_slice(data),
            width,
            height,
            wgpu::TextureFormat::Rgba32Float,
        )
    }

    /// A `format` texture holding `bytes` (tightly packed rows, `width` × `height`),
    /// readable by shaders (`TEXTURE_BINDING`).
    pub fn upload(
        &self,
        label: &str,
        bytes: &[u8],
        width: u32,
        height: u32,
        format: wgpu::TextureFormat,
    ) -> wgpu::Texture {
        let tex = self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        self.write(&tex, bytes);
        tex
    }

    /// Replaces the whole of mip 0 of `tex` with `bytes` (tightly packed rows).
    pub fn write(&self, tex: &wgpu::Texture, bytes: &[u8]) {
        let texel = tex.format().block_copy_size(None).unwrap_or(4);
        self.queue.write_texture(
            tex.as_image_copy(),
            bytes,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(texel * tex.width()),
                rows_per_image: Some(tex.height()),
            },
            tex.size(),
        );
    }

    /// Reads an `R32Float`/`Depth32Float` texture as `f32`s, or `Rgba32Float` as 4 per texel.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn read_f32(&self, texture: &wgpu::Texture) -> Result<Vec<f32>> {
        Ok(bytemuck::pod_collect_to_vec(&self.read_texture(texture)?))
    }
}

/// A texture mip's copy into a read-back buffer, rows padded to wgpu's alignment.
struct CopyOut {
    buffer: wgpu::Buffer,
    mip: u32,
    size: wgpu::Extent3d,
    padded: u32,
    row: u32,
    rows: u32,
}

impl CopyOut {
    fn record(&self, enc: &mut wgpu::CommandEncoder, texture: &wgpu::Texture) {
        enc.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture,
                mip_level: self.mip,
                origin: wgpu::Origin3d::ZERO,
                aspect: if texture.format().is_depth_stencil_format() {
                    wgpu::TextureAspect::DepthOnly
                } else {
                    wgpu::TextureAspect::All
                },
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &self.buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.padded),
                    rows_per_image: Some(self.size.height),
                },
            },
            self.size,
        );
    }

    /// The mapped bytes without the row padding.
    fn unpad(&self, data: &[u8]) -> Vec<u8> {
        let mut out = Vec::with_capacity((self.row * self.rows) as usize);
        for y in 0..self.rows as usize {
            let start = y * self.padded as usize;
            out.extend_from_slice(&data[start..start + self.row as usize]);
        }
        out
    }
}

/// A value a wgpu callback hands over, as a future: the callback fills it and wakes the
/// task (`None`: the state was poisoned).
struct Signal<T>(Arc<Mutex<SignalState<T>>>);

struct SignalState<T> {
    value: Option<T>,
    waker: Option<std::task::Waker>,
}

impl<T> Default for Signal<T> {
    fn default() -> Self {
        Signal(Arc::new(Mutex::new(SignalState {
            value: None,
            waker: None,
        })))
    }
}

impl<T> Clone for Signal<T> {
    fn clone(&self) -> Self {
        Signal(self.0.clone())
    }
}

impl<T> Signal<T> {
    fn set(&self, v: T) {
        if let Ok(mut s) = self.0.lock() {
            s.value = Some(v);
            if let Some(w) = s.waker.take() {
                w.wake();
            }
        }
    }
}

impl<T> std::future::Future for Signal<T> {
    type Output = Option<T>;

    fn poll(
        self: std::pin::Pin<&mut Self>,
        cx: &mut std::task::Context<'_>,
    ) -> std::task::Poll<Option<T>> {
        let Ok(mut s) = self.0.lock() else {
            return std::task::Poll::Ready(None);
        };
        match s.value.take() {
            Some(v) => std::task::Poll::Ready(Some(v)),
            None => {
                s.waker = Some(cx.waker().clone());
                std::task::Poll::Pending
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_adapter_choice() {
        assert_eq!(AdapterChoice::parse(""), AdapterChoice::Auto);
        assert_eq!(AdapterChoice::parse("CPU"), AdapterChoice::Cpu);
        assert_eq!(AdapterChoice::parse(" gpu "), AdapterChoice::Gpu);
        assert_eq!(
            AdapterChoice::parse("llvmpipe"),
            AdapterChoice::Name("llvmpipe".into())
        );
    }
}
