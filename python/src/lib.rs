//! Python bindings: numpy depth maps in, numpy AO out, through the library's one depth-map
//! path (`obscura::depth_map`), the same rules and messages as `obscura render --depth`.

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

/// Whether a depth dtype is accepted (float16/32/64 or uint16), and whether it holds
/// integers (stored units, times the depth scale).
fn check_dtype(dtype: &Bound<'_, PyAny>) -> PyResult<bool> {
    let kind: String = dtype.getattr("kind")?.extract()?;
    let size: usize = dtype.getattr("itemsize")?.extract()?;
    match (kind.as_str(), size) {
        ("f", 2 | 4 | 8) => Ok(false),
        ("u", 2) => Ok(true),
        _ => Err(value_error(format!(
            "depth dtype {} is not supported (float64, float32, float16 or uint16)",
            dtype.str()?
        ))),
    }
}

/// The arguments every map of a call shares: radius, depth scale, noise and thickness.
type Shared<'a, 'py> = (
    Option<&'a Bound<'py, PyAny>>,
    Option<f32>,
    Option<&'a Bound<'py, PyAny>>,
    Option<f32>,
);

/// An empty `render_many` checks what it was given as a full one would before its first
/// map: the stack's dtype, each intrinsic given as one number (all four, with the stack's
/// size when it has one, as `Intrinsics::validate`), and the shared parameters.
fn check_empty(
    maps: &Bound<'_, PyAny>,
    stacked: bool,
    intrinsics: [&Bound<'_, PyAny>; 4],
    (radius, depth_scale, depth_noise, thickness): Shared<'_, '_>,
) -> PyResult<()> {
    let size = if stacked {
        check_dtype(&maps.getattr("dtype")?)?;
        let shape: Vec<usize> = maps.getattr("shape")?.extract()?;
        (shape[1] > 0 && shape[2] > 0).then(|| (shape[2] as u32, shape[1] as u32))
    } else {
        None
    };
    let mut k = [None; 4];
    for (i, (name, v)) in ["fx", "fy", "cx", "cy"]
        .into_iter()
        .zip(intrinsics)
        .enumerate()
    {
        k[i] = v.extract::<f32>().ok();
        if k[i].is_none() {
            each(name, v, 0)?; // a sequence: it must be empty too
        }
    }
    let at = |i: usize, fallback: f32| k[i].unwrap_or(fallback);
    // The numbers given, each against its own rule (a sequence's place takes a harmless
    // stand-in); all four given: the whole check.
    let size = if k.iter().all(Option::is_some) {
        size
    } else {
        None
    };
    check_intrinsics((at(0, 1.0), at(1, 1.0), at(2, 0.0), at(3, 0.0)), size)?;
    let radius = match radius.map(|r| (r, r.extract::<f32>())) {
        Some((_, Ok(x))) => Some(x),
        Some((r, Err(_))) => {
            each("radius", r, 0)?;
            None
        }
        None => None,
    };
    check_shared(depth_scale, depth_noise, thickness, radius).map(|_| ())
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
    let integer = check_dtype(&depth.getattr("dtype")?)?;
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

/// One map's arguments copied out of Python (the part that needs the GIL).
struct Raw {
    width: u32,
    height: u32,
    values: Vec<f32>,
    integer: bool,
    intrinsics: (f32, f32, f32, f32),
    /// View-space normals, unpadded (`depth_map::view_normals`).
    normals: Option<Vec<[f32; 4]>>,
    radius: Option<f32>,
    depth_scale: Option<f32>,
    noise: String,
    thickness: Option<f32>,
}

/// A map ready for the device: framed, its normals padded, its parameters.
struct Job {
    framed: Framed,
    normals: Option<Vec<[f32; 4]>>,
    params: AoParams,
}

/// The parameters every map of a call shares, checked before any map is read: the depth
/// scale, the noise model's name or numbers, the thickness prior and a given radius.
fn check_shared(
    depth_scale: Option<f32>,
    depth_noise: Option<&Bound<'_, PyAny>>,
    thickness: Option<f32>,
    radius: Option<f32>,
) -> PyResult<String> {
    if let Some(s) = depth_scale {
        if !(s.is_finite() && s > 0.0) {
            return Err(value_error(format!(
                "depth_scale {s} must be finite and > 0"
            )));
        }
    }
    let noise = noise_spec(depth_noise)?;
    depth_map::NoiseSpec::parse(&noise).map_err(to_py)?;
    let params = AoParams {
        thickness: thickness.unwrap_or(obscura::DEFAULT_THICKNESS),
        radius: radius.unwrap_or(1.0),
        ..Default::default()
    };
    params.validate().map_err(to_py)?;
    Ok(noise)
}

/// Intrinsics checked with the maps' size when it is known, else what needs no size.
fn check_intrinsics(
    (fx, fy, cx, cy): (f32, f32, f32, f32),
    size: Option<(u32, u32)>,
) -> PyResult<()> {
    let (width, height) = size.unwrap_or((1, 1));
    let k = Intrinsics {
        fx,
        fy,
        cx,
        cy,
        width,
        height,
    };
    match size {
        Some(_) => k.validate(),
        None => k.validate_unsized(),
    }
    .map_err(to_py)
}

#[allow(clippy::too_many_arguments)]
fn raw(
    py: Python<'_>,
    depth: &Bound<'_, PyAny>,
    intrinsics: (f32, f32, f32, f32),
    radius: Option<f32>,
    normals: Option<&Bound<'_, PyAny>>,
    normals_frame: &str,
    depth_scale: Option<f32>,
    depth_noise: Option<&Bound<'_, PyAny>>,
    thickness: Option<f32>,
) -> PyResult<Raw> {
    let (width, height, values, integer) = depth_values(py, depth)?;
    let noise = check_shared(depth_scale, depth_noise, thickness, radius)?;
    let normals = match normals {
        Some(n) => Some(normal_values(py, n, width, height, normals_frame)?),
        None => None,
    };
    Ok(Raw {
        width,
        height,
        values,
        integer,
        intrinsics,
        normals,
        radius,
        depth_scale,
        noise,
        thickness,
    })
}

impl Raw {
    /// Frames the map, estimates its noise and checks its parameters: CPU work that needs
    /// no GIL (the noise estimate is tens of milliseconds at 640×480).
    fn prepare(self) -> PyResult<Job> {
        // The scale applies to integer maps (millimetres by default); floats are scene
        // units unless a scale is given.
        let (w, h) = (self.width, self.height);
        let map = if self.integer {
            DepthMap::from_integer(w, h, self.values, self.depth_scale.unwrap_or(0.001))
        } else {
            let s = self.depth_scale.unwrap_or(1.0);
            DepthMap::from_float(w, h, self.values.into_iter().map(|d| d * s).collect())
        }
        .map_err(to_py)?;
        let (fx, fy, cx, cy) = self.intrinsics;
        let k = Intrinsics {
            fx,
            fy,
            cx,
            cy,
            width: w,
            height: h,
        };
        let framed = map.frame(&k).map_err(to_py)?;
        let normals = match self.normals {
            Some(n) => Some(framed.pad(&n).map_err(to_py)?),
            None => None,
        };
        let (depth_noise, _) = depth_map::noise_model(&self.noise, &framed).map_err(to_py)?;
        let radius = framed.radius(self.radius).map_err(to_py)?;
        let params = AoParams {
            radius,
            depth_noise,
            thickness: self.thickness.unwrap_or(obscura::DEFAULT_THICKNESS),
            ..Default::default()
        };
        params.validate().map_err(to_py)?;
        Ok(Job {
            framed,
            normals,
            params,
        })
    }
}

/// Renders AO of depth maps with one device and passes compiled once: create it once and
/// call `render` for each map (a loop over thousands of maps pays the set-up once).
///
/// Args:
///     estimator: "bitmask" (None, the default: the library's estimator for depth maps,
///         more accurate than GTAO from depth alone at about 1.25x its time; its thickness
///         prior: `render`'s `thickness`), "gtao", "hbao", "vo", "vao", "sao" or "vo-area".
///     preset: "low", "medium", "high" (default) or "ultra": 8, 16, 32 or 96 samples per pixel
///         (high with GTAO or the bitmask at full resolution: 30, three slices of five steps
///         crowded toward the centre).
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
    #[pyo3(signature = (*, estimator=None, preset="high", resolution="full", denoise="spatial", frames=1))]
    fn new(
        py: Python<'_>,
        estimator: Option<&str>,
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
        let ao = py.detach(|| {
            let job = raw.prepare()?;
            self.render_job(&mut *self.lock()?, &job)
        })?;
        Ok(PyArray1::from_vec(py, ao).reshape([h, w])?.into_any())
    }

    /// Ambient occlusion of many depth maps: an (N, height, width) array in, an (N, height,
    /// width) float32 array out; a sequence of 2-D arrays in (sizes may differ), a list
    /// out. Each intrinsic and `radius` is one number for every map or a sequence of N;
    /// `normals` is None or N arrays (None among them: that map's from depth); the other arguments are shared (see
    /// `obscura.ambient_occlusion`). The maps are prepared (framed, noise estimated) on a
    /// second thread while the device renders the one before, and rendered grouped by
    /// size, so the textures are made once per size. The GIL is released throughout the
    /// device work. Results equal `render` on each map.
    ///
    /// Raises:
    ///     ValueError: bad input, naming the map ("map 3: ..."); no map's AO is returned.
    #[pyo3(signature = (maps, *, fx, fy, cx, cy, radius=None, normals=None, normals_frame="opencv", depth_scale=None, depth_noise=None, thickness=None))]
    #[allow(clippy::too_many_arguments)]
    fn render_many<'py>(
        &self,
        py: Python<'py>,
        maps: &Bound<'py, PyAny>,
        fx: &Bound<'py, PyAny>,
        fy: &Bound<'py, PyAny>,
        cx: &Bound<'py, PyAny>,
        cy: &Bound<'py, PyAny>,
        radius: Option<&Bound<'py, PyAny>>,
        normals: Option<&Bound<'py, PyAny>>,
        normals_frame: &str,
        depth_scale: Option<f32>,
        depth_noise: Option<&Bound<'py, PyAny>>,
        thickness: Option<f32>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let np = py.import("numpy")?;
        let stacked = maps.is_instance(&np.getattr("ndarray")?)?;
        let items: Vec<Bound<'py, PyAny>> = if stacked {
            let ndim: usize = maps.getattr("ndim")?.extract()?;
            if ndim != 3 {
                return Err(value_error(format!(
                    "maps: a {ndim}-D array; render_many takes (N, height, width) or a \
                     sequence of 2-D maps (one map: render)"
                )));
            }
            maps.try_iter()?.collect::<PyResult<_>>()?
        } else {
            maps.try_iter()
                .map_err(|_| {
                    value_error("maps: expected an (N, height, width) array or a sequence".into())
                })?
                .collect::<PyResult<_>>()?
        };
        let n = items.len();
        if n == 0 {
            let shared = (radius, depth_scale, depth_noise, thickness);
            check_empty(maps, stacked, [fx, fy, cx, cy], shared)?;
        }
        let [fx, fy, cx, cy] =
            [("fx", fx), ("fy", fy), ("cx", cx), ("cy", cy)].map(|(name, v)| each(name, v, n));
        let (fx, fy, cx, cy) = (fx?, fy?, cx?, cy?);
        let radius: Vec<Option<f32>> = match radius {
            None => vec![None; n],
            Some(r) => each("radius", r, n)?.into_iter().map(Some).collect(),
        };
        let normals: Vec<Option<Bound<'py, PyAny>>> = match normals {
            None => vec![None; n],
            Some(list) => {
                let v: Vec<Bound<'py, PyAny>> = list
                    .try_iter()
                    .map_err(|_| value_error("normals: expected N arrays".into()))?
                    .collect::<PyResult<_>>()?;
                if v.len() != n {
                    return Err(value_error(format!(
                        "normals: {} arrays for {n} maps",
                        v.len()
                    )));
                }
                // None for a map: its normals from depth.
                v.into_iter().map(|a| (!a.is_none()).then_some(a)).collect()
            }
        };
        let mut raws = Vec::with_capacity(n);
        for (i, depth) in items.iter().enumerate() {
            let r = raw(
                py,
                depth,
                (fx[i], fy[i], cx[i], cy[i]),
                radius[i],
                normals[i].as_ref(),
                normals_frame,
                depth_scale,
                depth_noise,
                thickness,
            );
            raws.push(r.map_err(|e| of_map(py, i, e))?);
        }
        let sizes: Vec<(usize, usize)> = raws
            .iter()
            .map(|r| (r.height as usize, r.width as usize))
            .collect();
        let aos = py.detach(|| self.render_all(raws))?;
        let arrays = aos
            .into_iter()
            .zip(sizes)
            .map(|(ao, (h, w))| Ok(PyArray1::from_vec(py, ao).reshape([h, w])?.into_any()))
            .collect::<PyResult<Vec<_>>>()?;
        if stacked {
            if arrays.is_empty() {
                let shape: Vec<usize> = maps.getattr("shape")?.extract()?;
                return np.call_method1("zeros", (shape, "float32"));
            }
            return np.call_method1("stack", (arrays,));
        }
        Ok(pyo3::types::PyList::new(py, arrays)?.into_any())
    }
}

/// `v` for each of `n` maps: one number for all, or a sequence of `n` numbers.
fn each(name: &str, v: &Bound<'_, PyAny>, n: usize) -> PyResult<Vec<f32>> {
    if let Ok(x) = v.extract::<f32>() {
        return Ok(vec![x; n]);
    }
    let xs: Vec<f32> = v.extract().map_err(|_| {
        value_error(format!(
            "{name}: expected a number or a sequence of {n} numbers"
        ))
    })?;
    if xs.len() != n {
        return Err(value_error(format!(
            "{name}: {} values for {n} maps",
            xs.len()
        )));
    }
    Ok(xs)
}

/// `e` naming map `i`, when it is about the input (a `ValueError`).
fn of_map(py: Python<'_>, i: usize, e: PyErr) -> PyErr {
    if e.is_instance_of::<PyValueError>(py) {
        value_error(format!("map {i}: {}", e.value(py)))
    } else {
        e
    }
}

impl Renderer {
    /// The device's passes, one map at a time. Poisoned only if a render panicked; its
    /// textures may then be half-written.
    fn lock(&self) -> PyResult<std::sync::MutexGuard<'_, depth_map::Renderer>> {
        self.inner.lock().map_err(|_| {
            DeviceError::new_err("an earlier render on this Renderer panicked: create a new one")
        })
    }

    /// The AO of a prepared map, row-major (call without the GIL).
    fn render_job(&self, inner: &mut depth_map::Renderer, job: &Job) -> PyResult<Vec<f32>> {
        inner
            .render(
                &self.ctx,
                &job.framed,
                job.normals.as_deref(),
                &job.params,
                self.frames,
            )
            .map_err(to_py)
    }

    /// The AO of every map, in order (call without the GIL): a second thread prepares the
    /// maps, grouped by size, while this one renders the map before.
    fn render_all(&self, raws: Vec<Raw>) -> PyResult<Vec<Vec<f32>>> {
        let mut out: Vec<Vec<f32>> = vec![Vec::new(); raws.len()];
        // Each map with its index, grouped by size (a stable sort keeps their order).
        let mut queue: Vec<(usize, Raw)> = raws.into_iter().enumerate().collect();
        queue.sort_by_key(|(_, r)| (r.width, r.height));
        let mut inner = self.lock()?;
        std::thread::scope(|scope| {
            // One map prepared ahead of the device: the channel holds one.
            let (tx, rx) = std::sync::mpsc::sync_channel::<(usize, PyResult<Job>)>(1);
            scope.spawn(move || {
                for (i, raw) in queue {
                    // A closed channel: the device side stopped at an error.
                    if tx.send((i, raw.prepare())).is_err() {
                        break;
                    }
                }
            });
            for (i, job) in rx {
                let job = job.map_err(|e| Python::attach(|py| of_map(py, i, e)))?;
                out[i] = self.render_job(&mut inner, &job)?;
            }
            Ok(out)
        })
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
