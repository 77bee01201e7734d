//! The ray-traced reference against analytic AO (cosine-weighted, binary visibility
//! within R). Tolerances: max(4 standard errors, the stated geometric error).

use glam::Vec3;
use obscura_eval::{ao_at, bvh::Tri, Bvh, Falloff, PixelSampling, TraceSettings};
use std::f32::consts::PI;

fn quad(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> [Tri; 2] {
    [[a, b, c], [a, c, d]]
}

fn settings(radius: f32) -> TraceSettings {
    TraceSettings {
        radius,
        rays: 4096,
        falloff: Falloff::None,
        sampling: PixelSampling::Centre,
    }
}

const L: f32 = 1000.0;

fn floor() -> [Tri; 2] {
    quad(
        Vec3::new(-L, 0.0, -L),
        Vec3::new(L, 0.0, -L),
        Vec3::new(L, 0.0, L),
        Vec3::new(-L, 0.0, L),
    )
}

#[test]
fn unoccluded_plane_is_one() {
    let bvh = Bvh::new(floor().to_vec());
    for falloff in [Falloff::None, Falloff::Quadratic] {
        let s = TraceSettings {
            falloff,
            ..settings(2.0)
        };
        let (ao, se) = ao_at(&bvh, Vec3::new(0.3, 0.0, -0.2), Vec3::Y, &s, 7);
        assert_eq!((ao, se), (1.0, 0.0));
    }
}

#[test]
fn inner_corner_of_two_planes_matches_closed_form() {
    // Floor y = 0 and a wall x = 0 rising over the floor. At distance d from the wall the
    // occluded directions are those with −ω.x > a = d/R; for cosine-weighted directions ω.x
    // is uniform over the unit disk (Malley), so AO = 1 − (acos a − a·sqrt(1 − a²)) / π.
    let wall = quad(
        Vec3::new(0.0, 0.0, -L),
        Vec3::new(0.0, L, -L),
        Vec3::new(0.0, L, L),
        Vec3::new(0.0, 0.0, L),
    );
    let bvh = Bvh::new([floor(), wall].concat());
    let r = 1.5;
    for a in [0.0005f32, 0.3, 0.7, 0.95] {
        let (ao, se) = ao_at(&bvh, Vec3::new(a * r, 0.0, 0.0), Vec3::Y, &settings(r), 11);
        let expected = 1.0 - (a.acos() - a * (1.0 - a * a).sqrt()) / PI;
        assert!(
            (ao - expected).abs() <= (4.0 * se).max(0.005),
            "a={a}: {ao} vs {expected} (se {se})"
        );
    }
    // At the crease itself the wall hides exactly half of the cosine-weighted hemisphere.
    let (ao, _) = ao_at(&bvh, Vec3::new(1e-5, 0.0, 0.0), Vec3::Y, &settings(r), 3);
    assert!((ao - 0.5).abs() < 0.01, "{ao}");
}

/// A UV sphere of radius `rb` centred at `c`; `lower_only` keeps the bowl below the equator.
fn sphere(c: Vec3, rb: f32, lower_only: bool) -> Vec<Tri> {
    let (rings, segs) = (64, 128);
    let p = |i: u32, j: u32| {
        let th = i as f32 / rings as f32 * PI;
        let ph = j as f32 / segs as f32 * 2.0 * PI;
        c + rb * Vec3::new(th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin())
    };
    let first = if lower_only { rings / 2 } else { 0 };
    (first..rings)
        .flat_map(|i| {
            (0..segs).flat_map(move |j| quad(p(i, j), p(i, j + 1), p(i + 1, j + 1), p(i + 1, j)))
        })
        .collect()
}

#[test]
fn bottom_of_a_bowl_and_inside_a_cavity() {
    let rb = 1.0;
    let bottom = Vec3::new(0.0, 1e-4, 0.0);
    // Open hemispherical bowl: a ray at angle θ from the vertical meets the sphere after
    // 2·Rb·cos θ, below the rim exactly when θ > 45°; rays steeper than 45° leave through
    // the opening. With R ≥ √2·Rb every shallow ray hits: AO = P(θ < 45°) = sin²45° = 1/2
    // for cosine-weighted directions.
    // Geometric error: 64 × 128 facets, about 0.01.
    let bowl = Bvh::new(sphere(Vec3::new(0.0, rb, 0.0), rb, true));
    let (ao, se) = ao_at(&bowl, bottom, Vec3::Y, &settings(1.5 * rb), 5);
    assert!(
        (ao - 0.5).abs() <= (4.0 * se).max(0.015),
        "bowl: {ao} (se {se})"
    );
    // A closed cavity with R ≥ its diameter: every ray hits, fully occluded.
    let cavity = Bvh::new(sphere(Vec3::new(0.0, rb, 0.0), rb, false));
    let (ao, _) = ao_at(&cavity, bottom, Vec3::Y, &settings(2.5 * rb), 5);
    assert_eq!(ao, 0.0);
    // With the quadratic falloff, the same hits occlude less.
    let q = TraceSettings {
        falloff: Falloff::Quadratic,
        ..settings(2.5 * rb)
    };
    let (aq, _) = ao_at(&cavity, bottom, Vec3::Y, &q, 5);
    assert!(aq > 0.2 && aq < 1.0, "{aq}");
}

/// Per-sample references put the primary rays at the 4× MSAA sample positions: a plane
/// whose edge crosses a pixel at 0.2 of its width covers only the sample at x = 0.125.
/// The centre reference sees sky there; the MSAA one sees the plane (depth 5, its mean
/// over the one covered sample) and averages the sky samples in as unoccluded. Pixels
/// wholly on either side agree. A corner then checks that each position's x goes with its
/// own y (a transposed table fails it).
#[test]
fn msaa_references_sample_the_four_standard_positions() {
    use obscura_scene::{Camera, CameraProjection};
    let (w, h) = (8u32, 4u32);
    let cam = Camera {
        eye: Vec3::ZERO,
        target: Vec3::NEG_Z,
        up: Vec3::Y,
        projection: CameraProjection::Orthographic { height: 4.0 },
        near: 0.1,
        far: 100.0,
    };
    let scale = cam
        .obscura_projection(w as f32 / h as f32)
        .ndc_to_view_scale();
    // View x of screen position `px` (pixels from the left).
    let view_x = |px: f32| (px / w as f32 * 2.0 - 1.0) * scale[0];
    let edge = view_x(3.2);
    let plane = quad(
        Vec3::new(-100.0, -100.0, -5.0),
        Vec3::new(edge, -100.0, -5.0),
        Vec3::new(edge, 100.0, -5.0),
        Vec3::new(-100.0, 100.0, -5.0),
    );
    let bvh = Bvh::new(plane.to_vec());
    let run = |sampling| {
        let s = TraceSettings {
            sampling,
            rays: 16,
            ..settings(1.0)
        };
        obscura_eval::trace_view(&bvh, &cam, w, h, &s, &|_, _| {})
    };
    let (centre, msaa) = (run(PixelSampling::Centre), run(PixelSampling::Msaa4));
    for y in 0..h as usize {
        let at = |x: usize| y * w as usize + x;
        for x in 0..3 {
            assert!(
                (centre.depth[at(x)] - 5.0).abs() < 1e-4,
                "{:?}",
                centre.depth
            );
            assert!((msaa.depth[at(x)] - 5.0).abs() < 1e-4, "{:?}", msaa.depth);
            assert_eq!((centre.ao[at(x)], msaa.ao[at(x)]), (1.0, 1.0));
        }
        assert_eq!(centre.depth[at(3)], 0.0, "the centre of pixel 3 sees sky");
        assert!((msaa.depth[at(3)] - 5.0).abs() < 1e-4, "{:?}", msaa.depth);
        assert_eq!(msaa.ao[at(3)], 1.0);
        for x in 4..w as usize {
            assert_eq!((centre.depth[at(x)], msaa.depth[at(x)]), (0.0, 0.0));
        }
    }
    // A corner covering x < 0.45 and y < 0.25 of pixel (3, 1): only the sample at
    // (0.375, 0.125) lies in it (with x and y of the positions swapped, none would).
    let view_y = |py: f32| (1.0 - py / h as f32 * 2.0) * scale[1];
    let (ex, ey) = (view_x(3.45), view_y(1.25));
    let corner = quad(
        Vec3::new(-100.0, ey, -5.0),
        Vec3::new(ex, ey, -5.0),
        Vec3::new(ex, 100.0, -5.0),
        Vec3::new(-100.0, 100.0, -5.0),
    );
    let bvh = Bvh::new(corner.to_vec());
    let s = |sampling| TraceSettings {
        sampling,
        rays: 16,
        ..settings(1.0)
    };
    let trace = |sampling| obscura_eval::trace_view(&bvh, &cam, w, h, &s(sampling), &|_, _| {});
    let (centre, msaa) = (trace(PixelSampling::Centre), trace(PixelSampling::Msaa4));
    let at = w as usize + 3;
    assert_eq!(centre.depth[at], 0.0);
    assert!((msaa.depth[at] - 5.0).abs() < 1e-4, "{:?}", msaa.depth);
    assert_eq!(msaa.depth[at + 1], 0.0);
}

/// The bent normal in the same inner corner (floor y = 0, wall x = 0): the mean of the
/// unoccluded cosine-weighted directions leans from the floor's normal away from the wall
/// (+x) by atan(x / y), for a = d/R < 1 (integrals over the unit hemisphere of ω and of
/// ω·n over the directions that do not reach the wall, −ω.x < a):
///   y = 2π/3 − (π/2)(2/3 − a + a³/3),   x = (2/3)(1 − a²)^{3/2},
/// and has no z component. Tolerance: 1° (4096 rays).
#[test]
fn bent_normal_in_an_inner_corner_matches_closed_form() {
    let wall = quad(
        Vec3::new(0.0, 0.0, -L),
        Vec3::new(0.0, L, -L),
        Vec3::new(0.0, L, L),
        Vec3::new(0.0, 0.0, L),
    );
    let bvh = Bvh::new([floor(), wall].concat());
    let r = 1.5;
    for a in [0.0005f32, 0.3, 0.7, 1.2] {
        let (_, _, b) =
            obscura_eval::ao_bent_at(&bvh, Vec3::new(a * r, 0.0, 0.0), Vec3::Y, &settings(r), 5);
        let b = b.normalize();
        let (y, x) = if a < 1.0 {
            (
                2.0 * PI / 3.0 - PI / 2.0 * (2.0 / 3.0 - a + a * a * a / 3.0),
                2.0 / 3.0 * (1.0 - a * a).powf(1.5),
            )
        } else {
            (1.0, 0.0)
        };
        let (got, want) = (b.x.atan2(b.y).to_degrees(), x.atan2(y).to_degrees());
        assert!(
            (got - want).abs() < 1.0 && b.z.abs() < 0.02,
            "a={a}: {got}° vs {want}°, {b}"
        );
    }
}

/// The SSDO reference at a floor point `a·R` from a red wall (x = 0), lit by a constant
/// sky L = 1. Rays with −ω.x > a hit the wall within R (the corner test's closed form for
/// their cosine-weighted share c), and bring the wall's albedo times its unshadowed
/// irradiance, L; the rest bring L. So radiance = albedo_floor · ((1 − c) + c · red).
/// And on the open floor under a gradient L(d) = m + h·d.y: albedo · (m + ⅔ h).
#[test]
fn ssdo_reference_matches_the_closed_form_beside_a_wall_and_under_a_gradient() {
    use obscura::Environment;
    use obscura_eval::ssdo_at;
    let wall = quad(
        Vec3::new(0.0, 0.0, -L),
        Vec3::new(0.0, L, -L),
        Vec3::new(0.0, L, L),
        Vec3::new(0.0, 0.0, L),
    );
    // Floor white, wall red (the order of the triangles given to the hierarchy).
    let albedo = [[1.0; 3], [1.0; 3], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
    let bvh = Bvh::new([floor(), wall].concat());
    let env = Environment::Constant([1.0; 3]);
    let irradiance = env.irradiance_sh();
    let r = 1.5;
    let floor_albedo = Vec3::new(0.5, 0.6, 0.7);
    for a in [0.0005f32, 0.3, 0.7] {
        let got = ssdo_at(
            &bvh,
            &albedo,
            &env,
            &irradiance,
            Vec3::new(a * r, 0.0, 0.0),
            Vec3::Y,
            floor_albedo,
            &settings(r),
            5,
        );
        let c = (a.acos() - a * (1.0 - a * a).sqrt()) / PI;
        let want = floor_albedo * (Vec3::splat(1.0 - c) + c * Vec3::new(1.0, 0.0, 0.0));
        assert!(
            (got - want).abs().max_element() < 0.01,
            "a={a}: {got} vs {want}"
        );
    }
    let (sky, ground) = (Vec3::new(1.0, 0.8, 0.5), Vec3::new(0.2, 0.1, 0.0));
    let env = Environment::Gradient {
        sky: sky.to_array(),
        ground: ground.to_array(),
    };
    let open = Bvh::new(floor().to_vec());
    let got = ssdo_at(
        &open,
        &albedo,
        &env,
        &env.irradiance_sh(),
        Vec3::new(0.2, 0.0, 0.1),
        Vec3::Y,
        Vec3::ONE,
        &settings(r),
        9,
    );
    let want = (sky + ground) / 2.0 + (sky - ground) / 2.0 * (2.0 / 3.0);
    assert!((got - want).abs().max_element() < 0.01, "{got} vs {want}");
}
