//! Python bindings: numpy depth maps in, numpy AO out, through the library's one depth-map
//! path (`obscura::depth_map`), the same rules and messages as `obscura render --depth`.

use ::obscura::depth_map::{self, DepthMap, Framed, Intrinsics};
use ::obscura::{AoOptions, AoParams, Denoise, Estimator, GpuContext, Preset, Resolution};
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
    estimator: &str,
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
    let estimator = named("estimator", &Estimator::ALL, Estimator::name, estimator)?;
    let preset = named("preset", &Preset::ALL, preset_name, preset)?;
    let o = AoOptions {
        resolution: named("resolution", &Resolution::ALL, Resolution::name, resolution)?,
        denoise: named("denoise", &Denoise::ALL, Denoise::name, denoise)?,
        // As the CLI: a history only when frames accumulate (16 frames at most).
        history: if frames > 1 { 16 } else { 0 },
        ..AoOptions::preset(estimator, preset)
    };
    o.validate().map_err(to_py)?;
    Ok(o)
}

/// A 2-D numpy array of an accepted dtype as row-major f32 values, its size, and whether
/// it was stored as integers.
fn depth_values(py: Python<'_>, depth: &Bound<'_, PyAny>) -> PyResult<(u32, u32, Vec<f32>, bool)> {
    let np = py.import("numpy")?;
    if !depth.is_instance(&np.getattr("ndarray")?)? {
        return Err(value_error(format!(
            "depth must be a numpy array, got {}",
            depth.get_type().name()?
        )));
    }
    let shape: Vec<usize> = depth.getattr("shape")?.extract()?;
    let [h, w] = shape[..] else {
        return Err(value_error(format!(
            "depth has shape {shape:?}; a depth map is 2-D (height, width)"
        )));
    };
    let dtype = depth.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    let size: usize = dtype.getattr("itemsize")?.extract()?;
    let integer = match (kind.as_str(), size) {
        ("f", 2 | 4 | 8) => false,
        ("u", 2) => true,
        _ => {
            return Err(value_error(format!(
                "depth dtype {} is not supported (float64, float32, float16 or uint16)",
                dtype.str()?
            )))
        }
    };
    // Any order or strides: numpy makes a C-ordered float32 copy (exact for uint16).
    let c = np.call_method1("ascontiguousarray", (depth, "float32"))?;
    let a: PyReadonlyArray2<f32> = c.extract()?;
    let values = a
        .as_slice()
        .map_err(|e| value_error(format!("depth: {e}")))?
        .to_vec();
    Ok((w as u32, h as u32, values, integer))
}

/// (height, width, 3 or 4) view-space normals in `frame` as obscura's RGBA rows, as
/// `render --normals-file` reads them (`depth_map::view_normals`).
fn normal_values(
    py: Python<'_>,
    normals: &Bound<'_, PyAny>,
    w: u32,
    h: u32,
    frame: &str,
) -> PyResult<Vec<[f32; 4]>> {
    let frame = match frame {
        "opencv" => depth_map::NormalsFrame::OpenCv,
        "opengl" => depth_map::NormalsFrame::OpenGl,
        other => {
            return Err(value_error(format!(
                "normals_frame `{other}`: expected opencv or opengl"
            )))
        }
    };
    let np = py.import("numpy")?;
    if !normals.is_instance(&np.getattr("ndarray")?)? {
        return Err(value_error(format!(
            "normals must be a numpy array, got {}",
            normals.get_type().name()?
        )));
    }
    let shape: Vec<usize> = normals.getattr("shape")?.extract()?;
    let [nh, nw, channels @ (3 | 4)] = shape[..] else {
        return Err(value_error(format!(
            "normals have shape {shape:?}; normals are (height, width, 3) or (height, width, 4)"
        )));
    };
    if (nw as u32, nh as u32) != (w, h) {
        return Err(value_error(format!(
            "the normals are {nw}x{nh} but the depth map is {w}x{h}"
        )));
    }
    let kind: String = normals.getattr("dtype")?.getattr("kind")?.extract()?;
    if kind != "f" {
        return Err(value_error("normals must be float (float16/32/64)".into()));
    }
    let c = np.call_method1("ascontiguousarray", (normals, "float32"))?;
    let a: PyReadonlyArray3<f32> = c.extract()?;
    let values = a
        .as_slice()
        .map_err(|e| value_error(format!("normals: {e}")))?;
    let (normals, away) = depth_map::view_normals(values, channels, frame).map_err(to_py)?;
    if let Some(w) = depth_map::normals_warning(away) {
        let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
        py.import("warnings")?
            .call_method1("warn", (format!("{w} (normals_frame)"), category, 1))?;
    }
    Ok(normals)
}

/// `depth_noise` as the library's model name: None = "auto", a string, or (C, L, Q).
fn noise_spec(depth_noise: Option<&Bound<'_, PyAny>>) -> PyResult<String> {
    let Some(n) = depth_noise else {
        return Ok("auto".into());
    };
    if let Ok(s) = n.extract::<String>() {
        return Ok(s);
    }
    let v: Vec<f32> = n.extract().map_err(|_| {
        value_error("depth_noise: expected \"auto\", \"none\", \"kinect\" or (C, L, Q)".into())
    })?;
    if let Some(bad) = v.iter().find(|x| !x.is_finite()) {
        return Err(value_error(format!(
            "depth_noise contains {bad}; every value must be finite"
        )));
    }
    Ok(v.iter().map(f32::to_string).collect::<Vec<_>>().join(","))
}

/// Everything about one map that needs the GIL: the map framed, its normals, parameters.
struct Job {
    framed: Framed,
    normals: Option<Vec<[f32; 4]>>,
    params: AoParams,
}

#[allow(clippy::too_many_arguments)]
fn job(
    py: Python<'_>,
    depth: &Bound<'_, PyAny>,
    (fx, fy, cx, cy): (f32, f32, f32, f32),
    radius: Option<f32>,
    normals: Option<&Bound<'_, PyAny>>,
    normals_frame: &str,
    depth_scale: Option<f32>,
    depth_noise: Option<&Bound<'_, PyAny>>,
    thickness: Option<f32>,
) -> PyResult<Job> {
    let (w, h, values, integer) = depth_values(py, depth)?;
    if let Some(s) = depth_scale {
        if !(s.is_finite() && s > 0.0) {
            return Err(value_error(format!(
                "depth_scale {s} must be finite and > 0"
            )));
        }
    }
    // The scale applies to integer maps (millimetres by default); floats are scene units
    // unless a scale is given.
    let map = if integer {
        DepthMap::from_integer(w, h, values, depth_scale.unwrap_or(0.001))
    } else {
        let s = depth_scale.unwrap_or(1.0);
        DepthMap::from_float(w, h, values.into_iter().map(|d| d * s).collect())
    }
    .map_err(to_py)?;
    let k = Intrinsics {
        fx,
        fy,
        cx,
        cy,
        width: w,
        height: h,
    };
    let framed = map.frame(&k).map_err(to_py)?;
    let normals = match normals {
        Some(n) => Some(
            framed
                .pad(&normal_values(py, n, w, h, normals_frame)?)
                .map_err(to_py)?,
        ),
        None => None,
    };
    let (depth_noise, _) =
        depth_map::noise_model(&noise_spec(depth_noise)?, &framed).map_err(to_py)?;
    let radius = framed.radius(radius).map_err(to_py)?;
    let params = AoParams {
        radius,
        depth_noise,
        thickness: thickness.unwrap_or(obscura::DEFAULT_THICKNESS),
        ..Default::default()
    };
    params.validate().map_err(to_py)?;
    Ok(Job {
        framed,
        normals,
        params,
    })
}

/// Renders AO of depth maps with one device and passes compiled once: create it once and
/// call `render` for each map (a loop over thousands of maps pays the set-up once).
///
/// Args:
///     estimator: "gtao" (default), "hbao", "vo", "vao", "sao", "vo-area" or "bitmask"
///         (its thickness prior: `render`'s `thickness`).
///     preset: "low", "medium", "high" (default) or "ultra": 8, 16, 32 or 96 samples per pixel.
///     resolution: "full" (default), "half" or "quarter".
///     denoise: "spatial" (default), "none", "box" or "tent".
///     frames: frames of a still camera accumulated per map (1 = one frame).
///
/// Threads may share one renderer: calls are serialized inside it (one device runs one
/// map at a time), and the GIL is released while a map is on the device, so the other
/// threads meanwhile read their files and prepare their arrays.
///
/// Raises:
///     ValueError: a bad choice. DeviceError: no adapter could be opened.
#[pyclass(module = "obscura")]
struct Renderer {
    ctx: GpuContext,
    /// The passes and textures, one map at a time: `render` takes `&self`, so threads that
    /// share the renderer wait here (with the GIL released) instead of failing to borrow it.
    inner: Mutex<depth_map::Renderer>,
    frames: u32,
}

#[pymethods]
impl Renderer {
    #[new]
    #[pyo3(signature = (*, estimator="gtao", preset="high", resolution="full", denoise="spatial", frames=1))]
    fn new(
        py: Python<'_>,
        estimator: &str,
        preset: &str,
        resolution: &str,
        denoise: &str,
        frames: i64,
    ) -> PyResult<Self> {
        let o = options(estimator, preset, resolution, denoise, frames)?;
        let frames = frames as u32; // checked: 1..=MAX_FRAMES
        py.detach(|| {
            let ctx = GpuContext::new()?;
            let inner = Mutex::new(depth_map::Renderer::new(&ctx, o)?);
            Ok(Renderer { ctx, inner, frames })
        })
        .map_err(to_py)
    }

    /// The adapter this renderer runs on, e.g. "llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan, Cpu, ...)".
    #[getter]
    fn adapter(&self) -> String {
        self.ctx.describe()
    }

    /// Ambient occlusion of one depth map; see `obscura.ambient_occlusion` for the arguments.
    #[pyo3(signature = (depth, *, fx, fy, cx, cy, radius=None, normals=None, normals_frame="opencv", depth_scale=None, depth_noise=None, thickness=None))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
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
    ) -> PyResult<Bound<'py, PyAny>> {
        let job = job(
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
        self.run(py, &job)
    }
}

impl Renderer {
    /// The AO of a prepared job as a (height, width) float32 array; the GIL is released
    /// while the device works.
    fn run<'py>(&self, py: Python<'py>, job: &Job) -> PyResult<Bound<'py, PyAny>> {
        let frames = self.frames;
        let ao = py.detach(|| {
            // Poisoned only if a render panicked; its textures may be half-written.
            let mut inner = self.inner.lock().map_err(|_| {
                DeviceError::new_err(
                    "an earlier render on this Renderer panicked: create a new one",
                )
            })?;
            inner
                .render(
                    &self.ctx,
                    &job.framed,
                    job.normals.as_deref(),
                    &job.params,
                    frames,
                )
                .map_err(to_py)
        })?;
        let (w, h) = (job.framed.width as usize, job.framed.height as usize);
        Ok(PyArray1::from_vec(py, ao).reshape([h, w])?.into_any())
    }
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
#[pyo3(signature = (depth, *, fx, fy, cx, cy, radius=None, normals=None, normals_frame="opencv", depth_scale=None, depth_noise=None, thickness=None, estimator="gtao", preset="high", resolution="full", denoise="spatial", frames=1))]
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
    estimator: &str,
    preset: &str,
    resolution: &str,
    denoise: &str,
    frames: i64,
) -> PyResult<Bound<'py, PyAny>> {
    // Input first, so bad input is a ValueError even without a device.
    options(estimator, preset, resolution, denoise, frames)?;
    let job = job(
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
    Renderer::new(py, estimator, preset, resolution, denoise, frames)?.run(py, &job)
}

#[pymodule]
#[pyo3(name = "obscura")]
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
    m.add_class::<Renderer>()?;
    m.add("DeviceError", m.py().get_type::<DeviceError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
