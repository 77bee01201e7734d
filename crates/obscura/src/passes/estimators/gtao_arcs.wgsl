// GTAO's slice geometry and closed-form arcs (Jimenez, Wu, Pesce & Jarabo 2016), shared by
// the AO estimator (gtao.wgsl) and the directional-occlusion bounce (ssdo_bounce.wgsl).
// CPU mirror: src/reference.rs (`fast_acos`, `gtao_falloff`, `gtao_side`, `gtao_bent`,
// `gtao_slice`).

const PI: f32 = 3.141592653589793;
const HALF_PI: f32 = 1.5707963267948966;

// acos with |error| <= 1e-4 rad on [-1, 1]: a square root and a cubic (Abramowitz & Stegun
// 1964, 4.4.45: |error| <= 5e-5 on [0, 1]; acos(-x) = pi - acos(x)), cheaper than the
// driver's acos. Mirror: `reference::fast_acos`, whose bound a test checks.
fn fast_acos(x: f32) -> f32 {
    let a = abs(x);
    let r = sqrt(1.0 - a) * (ACOS_POLY[0] + a * (ACOS_POLY[1] + a * (ACOS_POLY[2] + a * ACOS_POLY[3])));
    return select(r, PI - r, x < 0.0);
}

// A front's weight as a horizon at squared distance `r2` (radii²) from the centre: 1 within
// R, falling linearly in r² to 0 at GTAO_FALLOFF_END radii (constants.rs); the horizon is
// mixed toward the tangent plane's by it. Mirror: `reference::gtao_falloff`.
fn gtao_falloff(r2: f32) -> f32 {
    let end2 = GTAO_FALLOFF_END * GTAO_FALLOFF_END;
    return clamp((end2 - r2) * (1.0 / (end2 - 1.0)), 0.0, 1.0);
}

// One side's cosine-weighted visible arc (Jimenez et al., eq. 10): from the normal's angle
// n to the horizon h = s * acos(c) (s = +1 or -1, the side), h clamped to the normal's
// hemisphere. cos(2h - n) comes from the double-angle formulas, or is -cos(n) where the
// clamp holds (h = n +- pi/2), so the slice needs no trigonometric call.
fn gtao_side(c: f32, s: f32, n: f32, cos_n: f32, sin_n: f32) -> f32 {
    let t = s * fast_acos(c) - n;
    let h = n + clamp(t, -HALF_PI, HALF_PI);
    let sin_h = s * sqrt(max(1.0 - c * c, 0.0));
    let cos_2h_n = select((2.0 * c * c - 1.0) * cos_n + 2.0 * sin_h * c * sin_n, -cos_n, abs(t) > HALF_PI);
    return (cos_n + 2.0 * h * sin_n - cos_2h_n) * 0.25;
}

// One side's share of the slice's bent normal (Jimenez et al. 2016, sec. 5: the cosine-
// weighted mean of the unoccluded directions): the integral from 0 to the horizon h of
// (sin t, cos t) sin t cos(t - n) dt, in (ortho, V) coordinates, with the measure |sin t|
// of eq. 10 taken signed as there (the side's sign comes from the direction of
// integration). Closed form from cos h and sin h, so no trigonometric call:
//   ortho: cos n sin³h / 3 + sin n (2/3 - cos h + cos³h / 3)
//   V:     cos n (1 - cos³h) / 3 + sin n sin³h / 3
// h as in gtao_side: s * acos(c), clamped to n +- pi/2 (where cos h, sin h follow from n).
fn gtao_bent(c: f32, s: f32, n: f32, cos_n: f32, sin_n: f32) -> vec2<f32> {
    let t = s * fast_acos(c) - n;
    var ch = c;
    var sh = s * sqrt(max(1.0 - c * c, 0.0));
    if t > HALF_PI {
        ch = -sin_n;
        sh = cos_n;
    } else if t < -HALF_PI {
        ch = sin_n;
        sh = -cos_n;
    }
    let sh3 = sh * sh * sh;
    let ch3 = ch * ch * ch;
    return vec2<f32>(
        cos_n * sh3 + sin_n * (2.0 - 3.0 * ch + ch3),
        cos_n * (1.0 - ch3) + sin_n * sh3,
    ) / 3.0;
}

// One screen-space slice through the view vector `v` along screen direction `dir`
// (pixels, y down) for a surface with normal `normal`.
struct GtaoSlice {
    // Normal of the slice plane, and the unit direction in it orthogonal to V.
    axis: vec3<f32>,
    ortho: vec3<f32>,
    // d(azimuth)/d(screen angle): slices are spaced evenly on screen, which is not even
    // in azimuth around V off the image centre; this weight makes an unoccluded surface
    // integrate to exactly 1.
    weight: f32,
    // The normal projected into the slice plane: its length, and its signed angle n from
    // V (positive toward `ortho`) with cos n and sin n.
    proj_len: f32,
    n: f32,
    cos_n: f32,
    sin_n: f32,
}

fn gtao_slice(dir: vec2<f32>, v: vec3<f32>, normal: vec3<f32>) -> GtaoSlice {
    var s: GtaoSlice;
    // The slice plane holds V and the screen direction (y flips from pixels to view).
    let dir3 = vec3<f32>(dir.x, -dir.y, 0.0);
    let ortho = dir3 - dot(dir3, v) * v;
    s.axis = normalize(cross(ortho, v));
    s.ortho = normalize(ortho);
    // d(ortho)/d(angle), from d(dir3)/d(angle) = (-dir.y, -dir.x, 0).
    let ddir3 = vec3<f32>(-dir.y, -dir.x, 0.0);
    let dortho = ddir3 - dot(ddir3, v) * v;
    s.weight = abs(dot(dortho, s.axis)) / length(ortho);
    let proj_n = normal - s.axis * dot(normal, s.axis);
    s.proj_len = length(proj_n);
    s.cos_n = clamp(dot(proj_n, v) / max(s.proj_len, 1e-30), -1.0, 1.0);
    let sgn = sign(dot(ortho, proj_n));
    s.n = sgn * fast_acos(s.cos_n);
    s.sin_n = sgn * sqrt(1.0 - s.cos_n * s.cos_n);
    return s;
}
