//! numpy input: dtypes, empty and mismatched arrays, depth and normal values, the
//! depth-noise model, per-map parameters.

use super::*;

/// Whether a depth dtype is accepted (float16/32/64 or uint16), and whether it holds
/// integers (stored units, times the depth scale).
pub(crate) fn check_dtype(dtype: &Bound<'_, PyAny>) -> PyResult<bool> {
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
pub(crate) type Shared<'a, 'py> = (
    Option<&'a Bound<'py, PyAny>>,
    Option<f32>,
    Option<&'a Bound<'py, PyAny>>,
    Option<f32>,
);

/// An empty `render_many` checks what it was given as a full one would before its first
/// map: the stack's dtype, each intrinsic given as one number (all four, with the stack's
/// size when it has one, as `Intrinsics::validate`), and the shared parameters.
pub(crate) fn check_empty(
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
pub(crate) fn depth_values(
    py: Python<'_>,
    depth: &Bound<'_, PyAny>,
) -> PyResult<(u32, u32, Vec<f32>, bool)> {
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
pub(crate) fn normal_values(
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
pub(crate) fn noise_spec(depth_noise: Option<&Bound<'_, PyAny>>) -> PyResult<String> {
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

/// `v` for each of `n` maps: one number for all, or a sequence of `n` numbers.
pub(crate) fn each(name: &str, v: &Bound<'_, PyAny>, n: usize) -> PyResult<Vec<f32>> {
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
