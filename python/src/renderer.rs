//! `Renderer`: one device and its AO objects for many maps, from threads, batches and Dask.

use super::*;

/// Renders AO of depth maps with one device and passes compiled once: create it once and
/// call `render` for each map (a loop over thousands of maps pays the set-up once).
///
/// Args:
///     estimator: "bitmask" (None, the default: the library's estimator for depth maps,
///         more accurate than GTAO from depth alone at about 1.35x its time; its thickness
///         prior: `render`'s `thickness`), "gtao", "hbao", "vo", "vao", "sao" or "vo-area".
///     preset: "low", "medium", "high" (default) or "ultra": 8, 16, 32 or 96 samples per pixel
///         (high with GTAO or the bitmask at full resolution: 36, three slices of six steps
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
pub(crate) struct Renderer {
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
    pub(crate) fn new(
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

/// `e` naming map `i`, when it is about the input (a `ValueError`).
pub(crate) fn of_map(py: Python<'_>, i: usize, e: PyErr) -> PyErr {
    if e.is_instance_of::<PyValueError>(py) {
        value_error(format!("map {i}: {}", e.value(py)))
    } else {
        e
    }
}

impl Renderer {
    /// The device's passes, one map at a time. Poisoned only if a render panicked; its
    /// textures may then be half-written.
    pub(crate) fn lock(&self) -> PyResult<std::sync::MutexGuard<'_, depth_map::Renderer>> {
        self.inner.lock().map_err(|_| {
            DeviceError::new_err("an earlier render on this Renderer panicked: create a new one")
        })
    }

    /// The AO of a prepared map, row-major (call without the GIL).
    pub(crate) fn render_job(
        &self,
        inner: &mut depth_map::Renderer,
        job: &Job,
    ) -> PyResult<Vec<f32>> {
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
