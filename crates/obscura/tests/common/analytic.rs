//! Shared by the native GPU tests (tests/gpu/) and the browser tests (tests/web.rs): the
//! analytic scene (a floor, a back wall and a sphere, ray-cast), its camera and input, and
//! the tolerance of a GPU pass against its CPU mirror.

use obscura::{AoInput, DepthConvention, Projection};

/// The scene's vertical field of view, radians.
pub const FOV_Y: f32 = 1.0;

/// The scene's camera for a `w` × `h` image.
pub fn projection(w: u32, h: u32) -> Projection {
    Projection::Perspective {
        fov_y: FOV_Y,
        aspect: w as f32 / h as f32,
        near: 0.1,
        far: 100.0,
    }
}

/// The scene's linear depth `view` (`w` × `h`) as obscura's whole input: no viewport,
/// band, second layer or output of the caller's.
pub fn input(view: &wgpu::TextureView, w: u32, h: u32) -> AoInput<'_> {
    AoInput {
        depth: view,
        convention: DepthConvention::LinearView,
        projection: projection(w, h),
        normals: None,
        viewport: None,
        guard_band: 0,
        second_layer: None,
        output: None,
    }
}

/// GPU AO against its CPU mirror. Tolerance: 99.5% of pixels within 2e-3, none beyond 0.1.
/// A sample position that lands within float error of a pixel boundary may round to the
/// neighbour on one side.
pub fn assert_matches_mirror(gpu: &[f32], cpu: &[f32], what: &str) {
    assert_eq!(gpu.len(), cpu.len(), "{what}");
    let diffs: Vec<f32> = gpu.iter().zip(cpu).map(|(g, c)| (g - c).abs()).collect();
    let close = diffs.iter().filter(|d| **d <= 2e-3).count();
    let max = diffs.iter().cloned().fold(0.0, f32::max);
    assert!(
        close as f32 >= 0.995 * diffs.len() as f32 && max <= 0.1,
        "{what}: {close}/{} within 2e-3, max diff {max}",
        diffs.len()
    );
}

/// Linear view depth of a floor (y = −1), a back wall (z = −8) and a sphere resting on the
/// floor in front of it, ray-cast through each pixel's centre; 0 where nothing is hit.
pub fn scene(w: u32, h: u32) -> Vec<f32> {
    let t = (0.5 * FOV_Y).tan();
    let aspect = w as f32 / h as f32;
    let (centre, r) = (glam::Vec3::new(0.4, -0.3, -4.0), 0.7f32);
    let mut depth = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let ndc = (
                2.0 * (x as f32 + 0.5) / w as f32 - 1.0,
                1.0 - 2.0 * (y as f32 + 0.5) / h as f32,
            );
            // Direction with view z = −1, so the ray parameter is the linear depth.
            let d = glam::Vec3::new(ndc.0 * t * aspect, ndc.1 * t, -1.0);
            let mut best = f32::INFINITY;
            if d.y < 0.0 {
                best = best.min(-1.0 / d.y);
            }
            best = best.min(8.0);
            // |s d − c|² = r²
            let (a, b, c) = (d.dot(d), -2.0 * d.dot(centre), centre.dot(centre) - r * r);
            let disc = b * b - 4.0 * a * c;
            if disc >= 0.0 {
                let s = (-b - disc.sqrt()) / (2.0 * a);
                if s > 0.0 {
                    best = best.min(s);
                }
            }
            depth.push(if best.is_finite() { best } else { 0.0 });
        }
    }
    depth
}
