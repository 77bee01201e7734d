//! The estimators' integrals against answers derived from the geometry alone, not from the
//! code under test: the mirrors are line-by-line ports of the shaders, so a mistake in the
//! horizon search, the radius test or the normalisation shared by both would pass every
//! mirror test and fail here.
//!
//! The scenes are seen straight down by an orthographic camera (the view vector is the same
//! at every pixel), as linear depth, with normals reconstructed from it (exact on planes,
//! away from a crease by two pixels). "Occluded" is the ray tracer's definition: a
//! cosine-weighted direction whose ray meets a solid within the radius R. Under Malley's
//! projection, cosine-weighted directions are the unit disk's points (u, v) taken uniformly,
//! ω = (u, v, √(1 − u² − v²)) about the surface normal, so every occluded fraction below is
//! an area of the disk over π.
//!
//! - **Plane**: nothing within R above it: AO = 1 for every estimator.
//! - **90° crease** (a valley of two walls at 45° to the view): a point on one wall at
//!   distance x from the crease sees the other wall as a plane at distance x perpendicular
//!   to its own: the occluded directions are the disk's segment u > a = x / R, so
//!   1 − AO = (acos a − a √(1 − a²)) / π for a < 1, 0 beyond. GTAO's slices contain the
//!   view vector (Jimenez et al. 2016); seen straight down, each slice meets the valley as
//!   two lines at 90° or more, so its two horizons bound the occluded directions exactly
//!   and its slice integral is the cosine-weighted one. GTAO counts a front within R in
//!   full and beyond R in part, up to GTAO_FALLOFF_END × R (a surface seen beyond R
//!   usually has its body within it; these walls have none), among the samples its march
//!   reaches, R on screen, so its answer lies between the closed forms at R and at
//!   GTAO_FALLOFF_END × R. The bitmask's
//!   solids are entered through the wall's front face, so any finite thickness gives the
//!   closed form at R; infinitely thick, it is GTAO.
//!   VO (Loos & Sloan 2010) measures the share of a sphere of radius R about the point
//!   that lies under the surface, by chords along the view axis: its own wall fills half,
//!   and the other wall cuts off a cap of height R − x, which the first halves, so
//!   AO = 2(1 − share) = 1 − cap / sphere = 1 − h²(3R − h)/(4R³), h = R − x (its area
//!   integral's brute force is the same line integral). VAO's sphere of radius R/2 sits R/2
//!   along the normal, which is parallel to the other wall, so it too is cut at distance x:
//!   the same with R/2. HBAO (Bavoil et al. 2008) and SAO (McGuire et al. 2012) are
//!   defined by their sums, not by a visibility: their references are those sums'
//!   integrals evaluated on the exact surface by fine quadrature (HBAO: per direction,
//!   each rise of the elevation above the tangent plane over the running horizon,
//!   weighted by 1 − r²/R²; SAO: the mean of max(0, v·n − |v| sin β)/(v·v + 0.01R²) over
//!   the screen disk, times 2R).
//! - **A plank over a floor** (the bitmask's thickness): the floor seen beside a raised
//!   half-plane H above it. The bitmask takes the plank as a slab of the prior's depth T
//!   under its top, each pixel's solid clipped to R; a direction is occluded when its ray
//!   enters that slab within R. Its share of the disk is integrated here by quadrature of
//!   that definition (checked against the crease's closed form, the same geometry when the
//!   slab is a block and its top out of reach).

use super::{lock, run_linear};
use glam::Vec3;
use obscura::constants::GTAO_FALLOFF_END;
use obscura::{reference, AoOptions, AoParams, Estimator, Projection};
use std::f32::consts::{PI, SQRT_2, TAU};

/// Image size, pixel size (view units) and the AO radius: R = 32 px.
const W: u32 = 192;
const H: u32 = 128;
const PX: f32 = 1.0 / 32.0;
const R: f32 = 1.0;
/// Depth of the valley's crease and of the floor, view units.
const D0: f32 = 5.0;

fn ortho() -> Projection {
    Projection::Orthographic {
        half_width: W as f32 * PX / 2.0,
        half_height: H as f32 * PX / 2.0,
        near: 0.1,
        far: 100.0,
    }
}

/// View x of column `x`'s pixel centre.
fn view_x(x: u32) -> f32 {
    (x as f32 + 0.5 - W as f32 / 2.0) * PX
}

/// 1 − AO of a point at distance a·R from a perpendicular plane (a ≥ 0).
fn crease_occlusion(a: f32) -> f32 {
    if a >= 1.0 {
        0.0
    } else {
        (a.acos() - a * (1.0 - a * a).sqrt()) / PI
    }
}

/// 1 − AO of a floor point s (view units) from the edge of a plank whose top is h above
/// the floor and whose slab reaches `depth` below its top (infinite: a block), by a
/// midpoint quadrature of the disk on an n × n grid (error below 1e-3 at n = 800).
fn plank_occlusion(s: f32, h: f32, depth: f32, n: usize) -> f32 {
    let bottom = (h - depth).max(0.0);
    let mut hit = 0usize;
    let mut inside = 0usize;
    for i in 0..n {
        let u = -1.0 + (i as f32 + 0.5) * 2.0 / n as f32;
        for j in 0..n {
            let v = -1.0 + (j as f32 + 0.5) * 2.0 / n as f32;
            let r2 = u * u + v * v;
            if r2 >= 1.0 {
                continue;
            }
            inside += 1;
            let w = (1.0 - r2).sqrt();
            if u <= 0.0 {
                continue;
            }
            // Inside the slab while x > 0 and bottom ≤ z ≤ h: from the later of crossing
            // x = 0 and z = bottom, until z = h.
            let enter = (s / u).max(bottom / w);
            if enter <= h / w && enter <= R {
                hit += 1;
            }
        }
    }
    hit as f32 / inside as f32
}

/// The AO of `depth` on the GPU and in the CPU mirror, with `options` and `params`.
fn ao_both(depth: &[f32], options: AoOptions, params: &AoParams) -> (Vec<f32>, Vec<f32>) {
    let r = run_linear(depth, W, H, ortho(), options, params);
    let cpu = reference::ao(&r.frame, &options, &r.prepared);
    (r.ao, cpu)
}

/// The worst difference from `expected` over the middle row's columns that `keep` selects,
/// with the column where it is.
fn worst(ao: &[f32], keep: impl Fn(u32) -> Option<f32>) -> (f32, u32) {
    let y = H / 2;
    (0..W)
        .filter_map(|x| keep(x).map(|e| ((ao[(y * W + x) as usize] - e).abs(), x)))
        .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a })
}

fn params() -> AoParams {
    AoParams {
        radius: R,
        ..Default::default()
    }
}

/// Tolerance of the 64 × 64 integral against its reference. Two errors of the estimator's
/// own, both from samples snapping to pixel centres: the farthest sample counted lies up to
/// a pixel short of R (1/32 of it on screen, √2 that along a 45° wall: 0.044 R), and since
/// d(1 − AO)/dR = 2a√(1 − a²)/(πR) ≤ 1/(πR) that moves the occluded share by at most
/// 0.014; and a sample off its slice's plane, on a surface turned 45° from the view, reads
/// a horizon a little above the tangent plane (0.009 of occlusion measured on the open
/// wall beyond R). 0.025 holds both; the 64 slices' quadrature adds under 0.001.
const INTEGRAL_TOL: f32 = 0.025;

/// The bitmask rounds each horizon to one of its sectors' edges (up to half a sector of a
/// slice a side), an error of either sign that averages out over slices at different
/// angles; measured within GTAO's bound, so the same tolerance.
const BITMASK_TOL: f32 = INTEGRAL_TOL;

/// Tolerance of the sum estimators' 64 × 64 brute force against their integrals: 4096
/// samples of the disk (VO, VAO, SAO) or along 64 directions (HBAO) of a smooth
/// integrand; their snapping to pixel centres moves no sample off a plane, since each
/// reads the surface where it lands. Measured within 0.003.
const SUM_TOL: f32 = 0.01;

#[test]
fn a_plane_seen_straight_down_is_unoccluded_for_every_estimator() {
    let _g = lock();
    let depth = vec![D0; (W * H) as usize];
    for e in Estimator::ALL {
        let options = AoOptions::screen_reference(e);
        let (gpu, cpu) = ao_both(&depth, options, &params());
        // Away from the image's edges by R, where every estimator has its whole disk.
        let inner = |x: u32| (40..W - 40).contains(&x).then_some(1.0);
        for (which, ao) in [("gpu", &gpu), ("mirror", &cpu)] {
            let (d, x) = worst(ao, inner);
            assert!(
                d <= 1e-3,
                "{e:?} {which}: a plane reads {} at column {x}",
                1.0 - d
            );
        }
    }
}

/// The valley: depth D0 − |x|.
fn valley() -> Vec<f32> {
    (0..W * H).map(|i| D0 - view_x(i % W).abs()).collect()
}

/// Columns two pixels or more from the crease and within 1.2 R of it, with their closed
/// form (the distance along the wall is √2 |x|).
fn valley_expected(x: u32) -> Option<f32> {
    valley_expected_within(x, R)
}

/// The same for occluders counted within `radius`.
fn valley_expected_within(x: u32, radius: f32) -> Option<f32> {
    let vx = view_x(x).abs();
    (2.0 * PX..=1.2 * R)
        .contains(&vx)
        .then(|| 1.0 - crease_occlusion(SQRT_2 * vx / radius))
}

/// GTAO's horizons take fronts within R in full and beyond it in part, up to
/// GTAO_FALLOFF_END radii (constants.rs), among the samples its march reaches, R on
/// screen. The walls, surfaces of the ground, have no body behind their faces for that
/// falloff to find, so its integral lies between the closed form at R (every counted front
/// within R) and at GTAO_FALLOFF_END × R (every front within that counted in full): `ao`'s
/// value clamped to that range, for `worst`.
fn valley_bracket(ao: &[f32], x: u32) -> Option<f32> {
    let lo = valley_expected_within(x, GTAO_FALLOFF_END * R)?;
    let hi = valley_expected_within(x, R)?;
    Some(ao[((H / 2) * W + x) as usize].clamp(lo, hi))
}

#[test]
fn gtao_meets_the_crease_closed_form() {
    let _g = lock();
    let (gpu, cpu) = ao_both(
        &valley(),
        AoOptions::screen_reference(Estimator::Gtao),
        &params(),
    );
    for (which, ao) in [("gpu", &gpu), ("mirror", &cpu)] {
        let (d, x) = worst(ao, |x| valley_bracket(ao, x));
        assert!(
            d <= INTEGRAL_TOL,
            "GTAO {which}: {d} outside the closed forms at R and {GTAO_FALLOFF_END} R at column {x} \
             (x = {}; AO {})",
            view_x(x),
            ao[((H / 2) * W + x) as usize],
        );
    }
    // Not a tolerance wide enough for anything: the crease darkens to about half.
    let near = valley_expected(W / 2 + 2).unwrap();
    assert!(near < 0.6, "the closed form near the crease: {near}");
}

#[test]
fn the_bitmask_meets_the_crease_closed_form_at_any_thickness() {
    let _g = lock();
    for thickness in [0.25, 1.0, f32::INFINITY] {
        let p = AoParams {
            thickness,
            ..params()
        };
        let options = AoOptions::screen_reference(Estimator::Bitmask);
        let (gpu, cpu) = ao_both(&valley(), options, &p);
        // Infinitely thick, the bitmask is GTAO, with its falloff beyond R.
        for (which, ao) in [("gpu", &gpu), ("mirror", &cpu)] {
            let (d, x) = if thickness.is_finite() {
                worst(ao, valley_expected)
            } else {
                worst(ao, |x| valley_bracket(ao, x))
            };
            assert!(
                d <= BITMASK_TOL,
                "bitmask (thickness {thickness}) {which}: {d} from the closed form at x = {}",
                view_x(x)
            );
        }
    }
}

/// The plank: the floor at D0 for x < 0, the plank's top `h` nearer for x ≥ 0.
fn plank(h: f32) -> Vec<f32> {
    (0..W * H)
        .map(|i| if view_x(i % W) < 0.0 { D0 } else { D0 - h })
        .collect()
}

#[test]
fn the_bitmask_lets_light_under_a_thin_plank_as_its_slab_does() {
    let _g = lock();
    let h = 0.5 * R;
    // Floor columns two pixels or more from the edge and within R of it.
    let floor = |x: u32| {
        let s = -view_x(x);
        (2.0 * PX..=R).contains(&s).then_some(s)
    };
    // The prior's slab under the plank's top: thinner than the plank's height, and as deep
    // as the floor (the same as a block). An infinite prior is GTAO's model instead (its
    // horizons see the plank's top alone, and a top edge beyond R hides a side face within
    // it), and so is not this slab.
    let mut means = Vec::new();
    for thickness in [0.25, 1.0] {
        let p = AoParams {
            thickness,
            ..params()
        };
        let options = AoOptions::screen_reference(Estimator::Bitmask);
        let (gpu, cpu) = ao_both(&plank(h), options, &p);
        let slab = thickness * R;
        let expected = |x: u32| floor(x).map(|s| 1.0 - plank_occlusion(s, h, slab, 800));
        for (which, ao) in [("gpu", &gpu), ("mirror", &cpu)] {
            let (d, x) = worst(ao, expected);
            assert!(
                d <= BITMASK_TOL,
                "bitmask (thickness {thickness}) {which}: {d} from the slab's integral at s = {}",
                -view_x(x)
            );
        }
        let row: Vec<f32> = (0..W)
            .filter_map(|x| floor(x).map(|_| gpu[((H / 2) * W + x) as usize]))
            .collect();
        means.push(row.iter().sum::<f32>() / row.len() as f32);
    }
    // Not a tolerance wide enough for anything: the thin slab lets light in under the
    // plank that the deep one stops.
    assert!(
        means[0] > means[1] + 0.01,
        "mean floor AO: thin slab {}, deep slab {}",
        means[0],
        means[1]
    );
}

#[test]
fn the_quadrature_meets_the_crease_closed_form() {
    // The plank with an infinitely deep slab and its top out of reach is the crease's
    // geometry for the floor point: one check of the quadrature against the closed form.
    for s in [0.1, 0.3, 0.5, 0.8] {
        let q = plank_occlusion(s, 100.0, f32::INFINITY, 800);
        let c = crease_occlusion(s / R);
        assert!(
            (q - c).abs() < 2e-3,
            "s = {s}: quadrature {q}, closed form {c}"
        );
    }
}

/// The share of a sphere of radius `r` beyond a plane `s` from its centre: a cap of height
/// h = r − s, h²(3r − h)/(4r³) of the sphere.
fn cap_share(s: f32, r: f32) -> f32 {
    let h = (r - s).clamp(0.0, 2.0 * r);
    h * h * (3.0 * r - h) / (4.0 * r * r * r)
}

/// The valley's surface point at view (x, y), and the left wall's normal (toward the
/// crease and the camera).
fn valley_point(x: f32, y: f32) -> Vec3 {
    Vec3::new(x, y, -(D0 - x.abs()))
}
const LEFT_NORMAL: Vec3 = Vec3::new(
    std::f32::consts::FRAC_1_SQRT_2,
    0.0,
    std::f32::consts::FRAC_1_SQRT_2,
);

/// HBAO's integral at view x0 < 0 on the valley's left wall: per direction, the elevations
/// of the surface above the tangent plane along the march out to R (2000 steps), each rise
/// above the running horizon (from the bias) weighted by 1 − r²/R²; AO = 1 − the mean over
/// 720 directions / (1 − sin bias).
fn hbao_valley(x0: f32, sin_bias: f32) -> f32 {
    let (dirs, steps) = (720, 2000);
    let p = valley_point(x0, 0.0);
    let mut sum = 0.0;
    for i in 0..dirs {
        let (sa, ca) = ((i as f32 + 0.5) / dirs as f32 * TAU).sin_cos();
        let (mut h, mut occlusion) = (sin_bias, 0.0);
        for k in 1..=steps {
            let t = k as f32 / steps as f32 * R;
            let v = valley_point(x0 + t * ca, t * sa) - p;
            let r2 = v.length_squared() / (R * R);
            if r2 >= 1.0 {
                break;
            }
            let e = LEFT_NORMAL.dot(v) / v.length();
            if e > h {
                occlusion += (e - h) * (1.0 - r2);
                h = e;
            }
        }
        sum += occlusion;
    }
    1.0 - sum / dirs as f32 / (1.0 - sin_bias)
}

/// SAO's integral at view x0 < 0 on the valley's left wall: 1 − 2R times the mean over the
/// screen disk of radius R (radius uniform, 400 × 720 samples, as SAO's spiral spaces them)
/// of max(0, v·n − |v| sin β)/(v·v + 0.01R²), samples beyond R counting 0.
fn sao_valley(x0: f32, sin_bias: f32) -> f32 {
    let (radii, angles) = (400, 720);
    let p = valley_point(x0, 0.0);
    let mut sum = 0.0;
    for i in 0..radii {
        let t = (i as f32 + 0.5) / radii as f32 * R;
        for j in 0..angles {
            let (sa, ca) = ((j as f32 + 0.5) / angles as f32 * TAU).sin_cos();
            let v = valley_point(x0 + t * ca, t * sa) - p;
            let vv = v.length_squared();
            if vv >= R * R {
                continue;
            }
            sum += (LEFT_NORMAL.dot(v) - vv.sqrt() * sin_bias).max(0.0) / (vv + 0.01 * R * R);
        }
    }
    1.0 - 2.0 * R * sum / (radii * angles) as f32
}

#[test]
fn the_other_estimators_meet_their_crease_integrals() {
    let _g = lock();
    let p = params();
    let sin_bias = p.bias_angle_deg.to_radians().sin();
    // Left-wall columns two pixels or more from the crease and within 1.2 R of it; the
    // references are slow to integrate, so every fourth column.
    let columns: Vec<u32> = (0..W / 2)
        .filter(|&x| valley_expected(x).is_some())
        .step_by(4)
        .collect();
    type Reference = Box<dyn Fn(f32) -> f32>;
    let cases: [(Estimator, Reference); 5] = [
        (
            Estimator::Vo,
            Box::new(|x: f32| 1.0 - cap_share(SQRT_2 * x.abs(), R)),
        ),
        (
            Estimator::VoArea,
            Box::new(|x: f32| 1.0 - cap_share(SQRT_2 * x.abs(), R)),
        ),
        (
            Estimator::Vao,
            Box::new(|x: f32| 1.0 - cap_share(SQRT_2 * x.abs(), R / 2.0)),
        ),
        (
            Estimator::Hbao,
            Box::new(move |x: f32| hbao_valley(x, sin_bias)),
        ),
        (
            Estimator::Sao,
            Box::new(move |x: f32| sao_valley(x, sin_bias)),
        ),
    ];
    for (e, reference) in cases {
        let (gpu, cpu) = ao_both(&valley(), AoOptions::screen_reference(e), &p);
        let expected: Vec<(u32, f32)> =
            columns.iter().map(|&x| (x, reference(view_x(x)))).collect();
        for (which, ao) in [("gpu", &gpu), ("mirror", &cpu)] {
            let (d, x, want) = expected
                .iter()
                .map(|&(x, want)| ((ao[((H / 2) * W + x) as usize] - want).abs(), x, want))
                .fold((0.0, 0, 0.0), |a, b| if b.0 > a.0 { b } else { a });
            assert!(
                d <= SUM_TOL,
                "{e:?} {which}: {d} from its reference {want} at x = {}",
                view_x(x)
            );
        }
    }
}
