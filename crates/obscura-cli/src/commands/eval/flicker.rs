//! Flicker on a moving camera: the orbit's last two frames compared where the same surface
//! is seen in both, after reprojecting the frame before the last, less what the truth itself
//! changes between those frames (its view-dependent sampling of the same surfaces).

use glam::Vec3;
use obscura_scene::Camera;

/// Relative depth difference within which a reprojected pixel is the same surface.
const SAME_SURFACE: f32 = 0.01;

/// Pairs `(p, q)`: pixel `p` of the frame seen by `current` (linear view depth
/// `depth_current`, 0 on sky; only where `mask` holds) and the pixel `q` of the frame
/// before, seen by `previous` (`depth_previous`), nearest to where `p`'s surface point falls
/// there, when that pixel sees the same surface (its depth within [`SAME_SURFACE`]).
pub(super) fn reproject(
    (current, previous): (&Camera, &Camera),
    (depth_current, depth_previous): (&[f32], &[f32]),
    mask: &[bool],
    (w, h): (u32, u32),
) -> Vec<(usize, usize)> {
    let aspect = w as f32 / h as f32;
    let proj_prev = previous.projection_matrix(aspect);
    let to_previous = previous.view_matrix() * current.view_matrix().inverse();
    let mut pairs = Vec::new();
    for (p, (&d, &m)) in depth_current.iter().zip(mask).enumerate() {
        if !m || d <= 0.0 {
            continue;
        }
        let ndc = [
            ((p as u32 % w) as f32 + 0.5) / w as f32 * 2.0 - 1.0,
            1.0 - ((p as u32 / w) as f32 + 0.5) / h as f32 * 2.0,
        ];
        let view = view_position(current, aspect, ndc, d);
        let moved = to_previous * view.extend(1.0);
        let clip = proj_prev * moved;
        if clip.w <= 0.0 {
            continue;
        }
        let (x, y) = (clip.x / clip.w, clip.y / clip.w);
        let qx = ((x + 1.0) * 0.5 * w as f32).floor();
        let qy = ((1.0 - y) * 0.5 * h as f32).floor();
        if qx < 0.0 || qy < 0.0 || qx >= w as f32 || qy >= h as f32 {
            continue;
        }
        let q = qy as usize * w as usize + qx as usize;
        let (seen, expected) = (depth_previous[q], -moved.z);
        if seen > 0.0 && (seen - expected).abs() <= SAME_SURFACE * expected {
            pairs.push((p, q));
        }
    }
    pairs
}

/// The view-space point at normalized device coordinates `ndc` and linear depth `d`
/// (obscura's `Projection::ndc_to_view_scale`).
fn view_position(cam: &Camera, aspect: f32, ndc: [f32; 2], d: f32) -> Vec3 {
    let p = cam.obscura_projection(aspect);
    let [sx, sy] = p.ndc_to_view_scale();
    let k = if p.is_perspective() { d } else { 1.0 };
    Vec3::new(ndc[0] * sx * k, ndc[1] * sy * k, -d)
}

/// Mean over `pairs` of |(AO(p) − AO'(q)) − (T(p) − T'(q))|: how much the estimate changes
/// between two frames of a moving camera beyond the truth's own change. 0 without pairs.
pub(super) fn moving_flicker(
    pairs: &[(usize, usize)],
    (ao, ao_before): (&[f32], &[f32]),
    (truth, truth_before): (&[f32], &[f32]),
) -> f32 {
    if pairs.is_empty() {
        return 0.0;
    }
    let sum: f64 = pairs
        .iter()
        .map(|&(p, q)| ((ao[p] - ao_before[q]) - (truth[p] - truth_before[q])).abs() as f64)
        .sum();
    (sum / pairs.len() as f64) as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use obscura_scene::CameraProjection;

    /// A camera orbiting a plane facing it: every pixel of the current frame whose point the
    /// previous frame sees is paired with the pixel that sees it (checked by projecting the
    /// plane point back), and the same camera pairs each pixel with itself.
    #[test]
    fn reprojection_pairs_the_same_surface_point() {
        let cam = Camera {
            eye: Vec3::new(0.0, 0.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            projection: CameraProjection::Perspective { fov_y_deg: 50.0 },
            near: 0.1,
            far: 100.0,
        };
        let (w, h) = (32u32, 20u32);
        // Depth of the plane z = 0 seen by `c`: ray through each pixel centre.
        let depth_of = |c: &Camera| -> Vec<f32> {
            let proj = c.projection_matrix(w as f32 / h as f32);
            let inv = (proj * c.view_matrix()).inverse();
            (0..w * h)
                .map(|p| {
                    let nx = ((p % w) as f32 + 0.5) / w as f32 * 2.0 - 1.0;
                    let ny = 1.0 - ((p / w) as f32 + 0.5) / h as f32 * 2.0;
                    let a = inv.project_point3(Vec3::new(nx, ny, 1.0));
                    let b = inv.project_point3(Vec3::new(nx, ny, 0.5));
                    let t = a.z / (a.z - b.z);
                    let hit = a + (b - a) * t;
                    -(c.view_matrix().transform_point3(hit)).z
                })
                .collect()
        };
        let same = depth_of(&cam);
        let mask = vec![true; (w * h) as usize];
        let pairs = reproject((&cam, &cam), (&same, &same), &mask, (w, h));
        assert_eq!(pairs.len(), (w * h) as usize);
        assert!(pairs.iter().all(|(p, q)| p == q));
        let before = cam.orbit(-3.0);
        let prev = depth_of(&before);
        let pairs = reproject((&cam, &before), (&same, &prev), &mask, (w, h));
        assert!(pairs.len() > (w * h) as usize * 3 / 4, "{}", pairs.len());
        assert!(pairs.iter().any(|(p, q)| p != q));
        // Each pair's pixels see nearly the same world point: within a pixel's footprint.
        let world = |c: &Camera, d: &[f32], p: usize| {
            let ndc = [
                ((p as u32 % w) as f32 + 0.5) / w as f32 * 2.0 - 1.0,
                1.0 - ((p as u32 / w) as f32 + 0.5) / h as f32 * 2.0,
            ];
            let v = view_position(c, w as f32 / h as f32, ndc, d[p]);
            c.view_matrix().inverse().transform_point3(v)
        };
        let pixel = 2.0 * 5.0 * (25f32).to_radians().tan() / h as f32;
        for &(p, q) in &pairs {
            let gap = world(&cam, &same, p).distance(world(&before, &prev, q));
            assert!(
                gap < 1.5 * pixel,
                "{p} {q}: {gap} against a pixel of {pixel}"
            );
        }
    }

    /// The figure is 0 when the estimate changes as the truth does, and the mean of the
    /// excess otherwise.
    #[test]
    fn flicker_counts_only_change_beyond_the_truths() {
        let pairs = [(0, 1), (1, 0)];
        let truth = [0.5, 0.7];
        let follows = [0.4, 0.6];
        let none = moving_flicker(&pairs, (&follows, &follows), (&truth, &truth));
        assert!(none < 1e-6, "{none}");
        let jumps = [0.5, 0.5];
        let f = moving_flicker(&pairs, (&jumps, &[0.3, 0.3]), (&truth, &truth));
        // Pair (0, 1): (0.5 − 0.3) − (0.5 − 0.7) = 0.4; pair (1, 0): 0.2 − 0.2 = 0.
        assert!((f - 0.2).abs() < 1e-6, "{f}");
    }
}
