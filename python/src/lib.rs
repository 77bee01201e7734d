//! Python bindings: numpy depth maps in, numpy AO out, through the library's one depth-map
//! path (`obscura::depth_map`), the same rules and messages as `obscura render --depth`.

mod input;
mod job;
mod renderer;

use input::*;
use job::*;
use renderer::*;

use ::obscura::depth_map::{self, DepthMap, Framed, Intrinsics};
use ::obscura::{
    AoOptions, AoParams, Denoise, Estimator, GpuContext, Preset, Resolution, DEPTH_MAP_ESTIMATOR,
};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use std::sync::Mutex;

pyo3::create_exception!(
    obscura,
    DeviceError,
    PyRuntimeError,
    "No usable GPU or software adapter, or the device failed (out of memory, lost)."
);

/// A library error as the Python exception a caller can catch: bad input is a
/// `ValueError`, device trouble a `DeviceError`.
fn to_py(e: ::obscura::Error) -> PyErr {
    use ::obscura::Error as E;
    match e {
        E::NoAdapter(_)
        | E::DeviceCreation { .. }
        | E::Gpu(_)
        | E::OutOfMemory(_)
        | E::DeviceLost(_) => DeviceError::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    }
}

fn value_error(message: String) -> PyErr {
    PyValueError::new_err(message)
}

/// One of `names` (the library's names for its choices), or a `ValueError` listing them.
fn named<T: Copy>(what: &str, all: &[T], name: impl Fn(T) -> &'static str, s: &str) -> PyResult<T> {
    ::obscura::settings::by_name(all, name, s)
        .map_err(|e| value_error(format!("{what} `{s}`: {e}")))
}

fn preset_name(p: Preset) -> &'static str {
    match p {
        Preset::Low => "low",
        Preset::Medium => "medium",
        Preset::High => "high",
        _ => "ultra",
    }
}

/// The most frames `render --frames` accumulates.
const MAX_FRAMES: i64 = 100_000;

/// The options `render --depth` uses for the same choices.
fn options(
    estimator: Option<&str>,
    preset: &str,
    resolution: &str,
    denoise: &str,
    frames: i64,
) -> PyResult<AoOptions> {
    if !(1..=MAX_FRAMES).contains(&frames) {
        return Err(value_error(format!(
            "frames = {frames} must be in 1..={MAX_FRAMES}"
        )));
    }
    // Depth maps take the library's estimator for them unless one is named.
    let estimator = match estimator {
        Some(e) => named("estimator", &Estimator::ALL, Estimator::name, e)?,
        None => DEPTH_MAP_ESTIMATOR,
    };
    let preset = named("preset", &Preset::ALL, preset_name, preset)?;
    // The preset's samples at this resolution (`AoOptions::with_preset`).
    let o = AoOptions {
        estimator,
        resolution: named("resolution", &Resolution::ALL, Resolution::name, resolution)?,
        denoise: named("denoise", &Denoise::ALL, Denoise::name, denoise)?,
        // As the CLI: a history only when frames accumulate (16 frames at most).
        history: if frames > 1 { 16 } else { 0 },
        ..AoOptions::default()
    }
    .with_preset(preset);
    o.validate().map_err(to_py)?;
    Ok(o)
}

/// Ambient occlusion of a depth map: a float32 (height, width) array, 1 = unoccluded.
///
/// Args:
///     depth: (height, width) numpy array, float16/32/64 in scene units or uint16 in
///         depth units (times depth_scale); 0, NaN and inf are missing. Any order or strides.
///     fx, fy, cx, cy: pinhole intrinsics in pixels (OpenCV convention: pixel centres at
///         integer coordinates).
///     radius: AO radius in scene units; default 3% of the scene's extent.
///     normals: optional (height, width, 3 or 4) float view-space normals in `normals_frame`
///         ("opencv": x right, y down, z into the scene; "opengl": y up, z towards the viewer).
///     depth_scale: scene units per depth unit; default 0.001 for uint16 (millimetres to
///         metres), none for floats (scene units already); a scale given applies to both.
///     depth_noise: "auto" (default: estimated from the map), "none", "kinect", or
///         (C, L, Q) for sigma(z) = C + L z + Q z^2 in scene units.
///     thickness: the bitmask estimator's thickness prior, times the radius (> 0, or
///         float("inf") for GTAO's infinitely thick surfaces); default the library's (1).
///         A depth map shows only the front of each object: this assumes every object is
///         that deep behind each pixel, along its ray (docs/thickness.md). Other estimators
///         ignore it.
///     estimator, preset, resolution, denoise, frames: as `Renderer`.
///
/// Creates a device and compiles the passes on every call: use `Renderer` in loops.
///
/// Raises:
///     ValueError: bad input (the library's messages, as `obscura render --depth` prints them).
///     DeviceError: no adapter could be opened, or the device failed.
#[pyfunction]
#[pyo3(signature = (depth, *, fx, fy, cx, cy, radius=None, normals=None, normals_frame="opencv", depth_scale=None, depth_noise=None, thickness=None, estimator=None, preset="high", resolution="full", denoise="spatial", frames=1))]
#[allow(clippy::too_many_arguments)]
fn ambient_occlusion<'py>(
    py: Python<'py>,
    depth: &Bound<'py, PyAny>,
    fx: f32,
    fy: f32,
    cx: f32,
    cy: f32,
    radius: Option<f32>,
    normals: Option<&Bound<'py, PyAny>>,
    normals_frame: &str,
    depth_scale: Option<f32>,
    depth_noise: Option<&Bound<'py, PyAny>>,
    thickness: Option<f32>,
    estimator: Option<&str>,
    preset: &str,
    resolution: &str,
    denoise: &str,
    frames: i64,
) -> PyResult<Bound<'py, PyAny>> {
    // Input first, so bad input is a ValueError even without a device.
    options(estimator, preset, resolution, denoise, frames)?;
    let raw = raw(
        py,
        depth,
        (fx, fy, cx, cy),
        radius,
        normals,
        normals_frame,
        depth_scale,
        depth_noise,
        thickness,
    )?;
    let (w, h) = (raw.width as usize, raw.height as usize);
    let job = py.detach(|| raw.prepare())?;
    let r = Renderer::new(py, estimator, preset, resolution, denoise, frames)?;
    let ao = py.detach(|| r.render_job(&mut *r.lock()?, &job))?;
    Ok(PyArray1::from_vec(py, ao).reshape([h, w])?.into_any())
}

/// Checks settings that many maps will share, before any map is read or device opened:
/// the renderer's options (as `Renderer`), the intrinsics (with the maps' `width` and
/// `height` when known; else what needs no size), and the shared `render` parameters.
/// `obscura.dask.ao_files` calls it before it starts a cluster.
///
/// Raises:
///     ValueError: the first bad setting, with the message `render` would give.
#[pyfunction]
#[pyo3(signature = (*, fx, fy, cx, cy, width=None, height=None, radius=None, depth_scale=None, depth_noise=None, thickness=None, estimator=None, preset="high", resolution="full", denoise="spatial", frames=1))]
#[allow(clippy::too_many_arguments)]
fn check_settings(
    fx: f32,
    fy: f32,
    cx: f32,
    cy: f32,
    width: Option<u32>,
    height: Option<u32>,
    radius: Option<f32>,
    depth_scale: Option<f32>,
    depth_noise: Option<&Bound<'_, PyAny>>,
    thickness: Option<f32>,
    estimator: Option<&str>,
    preset: &str,
    resolution: &str,
    denoise: &str,
    frames: i64,
) -> PyResult<()> {
    options(estimator, preset, resolution, denoise, frames)?;
    check_intrinsics((fx, fy, cx, cy), width.zip(height))?;
    check_shared(depth_scale, depth_noise, thickness, radius).map(|_| ())
}

/// Writes an AO image (a 2-D float array, 1 = unoccluded) to `path` by its extension, as
/// `obscura render --out` does: `.npy` float32, `.exr` float32 (the value in R, G and B),
/// `.png` 16-bit grey (round(ao · 65535)). Values must lie in [0, 1]. Atomic: the file is written
/// beside its name and renamed, so a file that exists is complete.
///
/// Raises:
///     ValueError: not a 2-D float32 array, or another extension. OSError: the write failed.
#[pyfunction]
fn save_ao(py: Python<'_>, path: std::path::PathBuf, ao: &Bound<'_, PyAny>) -> PyResult<()> {
    let a: PyReadonlyArray2<f32> = ao
        .extract()
        .map_err(|_| value_error("ao must be a 2-D float32 numpy array".into()))?;
    let view = a.as_array();
    let (h, w) = view.dim();
    if h == 0 || w == 0 {
        return Err(value_error(format!(
            "ao has shape ({h}, {w}); an AO image has at least one pixel"
        )));
    }
    // Row-major whatever the array's order or strides.
    let values = view.iter().copied().collect::<Vec<f32>>();
    // AO is a fraction: NaN, infinities or values outside [0, 1] are a bug upstream, and
    // a PNG would hide them (clamped, NaN as 0: fully occluded).
    if let Some(i) = values.iter().position(|v| !(0.0..=1.0).contains(v)) {
        let bad = values.iter().filter(|v| !(0.0..=1.0).contains(*v)).count();
        return Err(value_error(format!(
            "ao holds {bad} value(s) outside [0, 1] (the first, {}, at row {}, column {}); \
             AO is 1 where unoccluded and 0 where fully occluded",
            values[i],
            i / w,
            i % w
        )));
    }
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    if !matches!(ext.as_str(), "npy" | "exr" | "png") {
        return Err(value_error(format!(
            "{}: expected .npy, .exr or .png",
            path.display()
        )));
    }
    let (w, h) = (w as u32, h as u32);
    py.detach(|| {
        let mut name = path.file_name().unwrap_or_default().to_os_string();
        name.push(".partial");
        let tmp = path.with_file_name(name);
        let encoded = |bytes: &[u8], color, format| {
            image::save_buffer_with_format(&tmp, bytes, w, h, color, format)
                .map_err(|e| e.to_string())
        };
        let written = match ext.as_str() {
            "npy" => std::fs::write(&tmp, depth_map::npy_f32(&values, &[h, w]))
                .map_err(|e| e.to_string()),
            "exr" => {
                let rgb: Vec<u8> = values
                    .iter()
                    .flat_map(|&v| [v; 3])
                    .flat_map(f32::to_ne_bytes)
                    .collect();
                encoded(
                    &rgb,
                    image::ExtendedColorType::Rgb32F,
                    image::ImageFormat::OpenExr,
                )
            }
            _ => {
                let grey: Vec<u8> = values
                    .iter()
                    .flat_map(|v| ((v * 65535.0).round() as u16).to_ne_bytes())
                    .collect();
                encoded(
                    &grey,
                    image::ExtendedColorType::L16,
                    image::ImageFormat::Png,
                )
            }
        }
        .and_then(|()| std::fs::rename(&tmp, &path).map_err(|e| e.to_string()));
        written.map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            pyo3::exceptions::PyOSError::new_err(format!("cannot write {}: {e}", path.display()))
        })
    })
}

#[pymodule]
#[pyo3(name = "_obscura")]
fn obscura_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // As the CLI: no device-select chatter on stderr ("error: XDG_RUNTIME_DIR is invalid")
    // on headless machines, unless OBSCURA_DEVICE_SELECT is set. Through os.environ, so
    // Python sees it too.
    if ::obscura::context::quiet_device_select() {
        m.py()
            .import("os")?
            .getattr("environ")?
            .set_item("NODEVICE_SELECT", "1")?;
    }
    m.add_function(wrap_pyfunction!(ambient_occlusion, m)?)?;
    m.add_function(wrap_pyfunction!(save_ao, m)?)?;
    m.add_function(wrap_pyfunction!(check_settings, m)?)?;
    m.add_class::<Renderer>()?;
    m.add("DeviceError", m.py().get_type::<DeviceError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
