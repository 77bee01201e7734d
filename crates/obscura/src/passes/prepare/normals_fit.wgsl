// A pixel's prepared value, vec4(depth, normal), from noisy depth (AoOptions::depth_noise;
// composed after normals_reconstruct.wgsl into the prepare passes): a least-squares plane
// fitted to (2 FIT_RADIUS + 1)^2 depths whose spacing grows with the noise σ(d) relative to
// the pixel's footprint and with the terraces of quantised depth (DepthNoise::step), so
// the normal's error stays below 20° (shader.rs, FIT_*). A plane is linear in pixel
// position in 1/d under perspective (in d under orthographic projection), so that is what
// is fitted, as in plane-fit normal estimation of range images (Hoppe et al. 1992, fitted
// here in image space where the noise is axial). Two fits: the first over the 3 x 3 taps
// nearest the pixel, the second over every tap that agrees with the first within the
// noise and one terrace step, so taps on another surface (across a crease or
// an edge farther than the noise) never tilt the plane. The depth stored is the plane's
// at the pixel: the estimators then read depth averaged over the window. Where too few
// taps agree, the depth as given and the three-pixel reconstruction (normals_reconstruct).
// CPU mirror: reference.rs, `fit_surface`.

const FIT_SIDE: i32 = 2 * FIT_RADIUS + 1;
const FIT_TAPS: i32 = FIT_SIDE * FIT_SIDE;

// The plane f = f0 + a x + b y through weighted taps (x, y in taps from the centre, f minus
// the centre's), from the sums m = [[n, sx, sy], [sx, sxx, sxy], [sy, sxy, syy]] and
// r = (sf, sxf, syf) by Cramer's rule; w = 0 when fewer than `min_taps` taps or taps that
// do not span a plane.
fn solve_plane(m: mat3x3<f32>, r: vec3<f32>, min_taps: f32) -> vec4<f32> {
    let det = determinant(m);
    let n = m[0][0];
    if n < min_taps || !(det > 1e-3 * n * n * n) {
        return vec4<f32>(0.0);
    }
    let f0 = determinant(mat3x3<f32>(r, m[1], m[2])) / det;
    let a = determinant(mat3x3<f32>(m[0], r, m[2])) / det;
    let b = determinant(mat3x3<f32>(m[0], m[1], r)) / det;
    return vec4<f32>(f0, a, b, 1.0);
}

fn surface(p: vec2<i32>, d: f32) -> vec4<f32> {
    let persp = frame.perspective != 0u;
    let sigma = depth_sigma(d);
    // View-space size of one pixel at this depth.
    let footprint = select(1.0, d, persp) / frame.radius_to_px;
    // Normal error: a least-squares slope over (2R+1)^2 taps `stride` pixels apart has
    // standard error σ / (footprint · stride · sqrt(S(R))), S = 6, 50, 196 for R = 1, 2, 3.
    // The smallest window whose error is below FIT_NORMAL_TAN: 3 x 3 taps for σ below
    // ~0.4 footprints, wider taps once 7 x 7 is not enough.
    let need = sigma / (footprint * FIT_NORMAL_TAN);
    var reach = FIT_RADIUS;
    if need * need <= 6.0 {
        reach = 1;
    } else if need * need <= 50.0 {
        reach = 2;
    }
    var stride = i32(clamp(ceil(need / 14.0), 1.0, f32(FIT_MAX_STRIDE)));
    // Terraces: a window inside one terrace of `step` is flat, and its true slope is at
    // most step / (window width); the window reaches at least `need_step` pixels from the
    // centre so that slope stays below FIT_NORMAL_TAN.
    let step = depth_step(d);
    let need_step = step / (2.0 * footprint * FIT_NORMAL_TAN);
    if need_step > f32(reach * stride) {
        reach = FIT_RADIUS;
        stride = max(stride, i32(clamp(ceil(need_step / f32(FIT_RADIUS)), 1.0, f32(FIT_MAX_STRIDE))));
    }
    let fc = select(d, 1.0 / d, persp);
    var f: array<f32, FIT_TAPS>;
    var m = mat3x3<f32>();
    var r = vec3<f32>(0.0);
    for (var k = 0; k < FIT_TAPS; k++) {
        let o = vec2<i32>(k % FIT_SIDE, k / FIT_SIDE) - FIT_RADIUS;
        f[k] = 0.0;
        if any(abs(o) > vec2<i32>(reach)) {
            continue;
        }
        let dq = linear_depth_at(p + o * stride);
        // The fitted quantity, or 0 where the depth is missing or outside the window.
        if dq > 0.0 {
            f[k] = select(dq, 1.0 / dq, persp);
        }
        // First fit: the 3 x 3 taps nearest the centre that lie near its depth.
        let tol = 1.4142135 * FIT_SIGMAS * sigma + step + FIT_SLOPE * footprint * f32(stride);
        if all(abs(o) <= vec2<i32>(1)) && dq > 0.0 && abs(dq - d) <= tol {
            let x = vec3<f32>(1.0, vec2<f32>(o));
            m += mat3x3<f32>(x * x.x, x * x.y, x * x.z);
            r += x * (f[k] - fc);
        }
    }
    let first = solve_plane(m, r, 5.0);
    // Second fit: every tap within FIT_SIGMAS of the first plane's uncertainty there (the
    // tap's own σ and the first plane's prediction error, σ sqrt(1/9 + t^2/6) at t taps
    // out, least squares over 3 x 3: together σ sqrt(1 + t^2 / 6)) and one terrace step.
    m = mat3x3<f32>();
    r = vec3<f32>(0.0);
    for (var k = 0; k < FIT_TAPS; k++) {
        let o = vec2<f32>(vec2<i32>(k % FIT_SIDE, k / FIT_SIDE) - FIT_RADIUS);
        let fp = fc + first.x + first.y * o.x + first.z * o.y;
        let dq = select(f[k], 1.0 / f[k], persp);
        let dp = select(fp, 1.0 / fp, persp);
        let tol = FIT_SIGMAS * depth_sigma(dp) * sqrt(1.0 + dot(o, o) / 6.0) + depth_step(dp);
        if f[k] != 0.0 && dp > 0.0 && abs(dq - dp) <= tol {
            let x = vec3<f32>(1.0, o);
            m += mat3x3<f32>(x * x.x, x * x.y, x * x.z);
            r += x * (f[k] - fc);
        }
    }
    var plane = solve_plane(m, r, 6.0);
    if first.w == 0.0 {
        plane.w = 0.0;
    }
    let f0 = fc + plane.x;
    let dfit = select(f0, 1.0 / f0, persp);
    let k = view_xy_per_pixel();
    let g = plane.yz / (f32(stride) * k);
    // Perspective: 1/d = (n.r)/c for the ray r = view_position(pixel, 1) and a plane n.X = c,
    // so n = (gx, gy, gx rx + gy ry - 1/d). Orthographic: d = c - n.xy X.xy / nz, n = (g, 1).
    let ray = view_position(vec2<f32>(p) + 0.5, 1.0);
    var n = vec3<f32>(g, 1.0);
    if persp {
        n = vec3<f32>(g, dot(g, ray.xy) - f0);
    }
    let len2 = dot(n, n);
    if plane.w != 0.0 && dfit > 0.0 && !is_nonfinite(dfit) && len2 > 0.0 && !is_nonfinite(len2) {
        n = n * inverseSqrt(len2);
        return vec4<f32>(dfit, select(n, -n, persp && dot(n, ray) > 0.0));
    }
    return vec4<f32>(d, view_normal(p, view_position(vec2<f32>(p) + 0.5, d), d));
}
