//! A depth map's frame and settings checked before any GPU work (`Raw`), and the job the
//! renderer runs for it.

use super::*;

/// One map's arguments copied out of Python (the part that needs the GIL).
pub(crate) struct Raw {
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) values: Vec<f32>,
    pub(crate) integer: bool,
    pub(crate) intrinsics: (f32, f32, f32, f32),
    /// View-space normals, unpadded (`depth_map::view_normals`).
    pub(crate) normals: Option<Vec<[f32; 4]>>,
    pub(crate) radius: Option<f32>,
    pub(crate) depth_scale: Option<f32>,
    pub(crate) noise: String,
    pub(crate) thickness: Option<f32>,
}

/// A map ready for the device: framed, its normals padded, its parameters.
pub(crate) struct Job {
    pub(crate) framed: Framed,
    pub(crate) normals: Option<Vec<[f32; 4]>>,
    pub(crate) params: AoParams,
}

/// The parameters every map of a call shares, checked before any map is read: the depth
/// scale, the noise model's name or numbers, the thickness prior and a given radius.
pub(crate) fn check_shared(
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
pub(crate) fn check_intrinsics(
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
pub(crate) fn raw(
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
    pub(crate) fn prepare(self) -> PyResult<Job> {
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
