// Helpers shared by every pass. Each pass binds `frame: FrameUniforms` at
// @group(0) @binding(0); the struct and constants above come from Rust (src/shader.rs).
// The CPU mirror of these functions is src/reference.rs.

const TAU: f32 = 6.283185307179586;

// True for +-inf and NaN. A bit test, because `x != x` may be folded away by a driver.
fn is_nonfinite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) == 0x7f800000u;
}

// Linear view depth of a raw depth value, or 0.0 for sky / missing depth (never a near
// occluder): the far plane, and raw values outside [0, 1] (in front of the near plane).
// See src/input.rs, `Linearize::apply`.
fn linearize_depth(z: f32) -> f32 {
    if is_nonfinite(z) {
        return 0.0;
    }
    if (frame.sky_test == 0u && (z >= 1.0 || z < 0.0)) || (frame.sky_test == 1u && (z <= 0.0 || z > 1.0)) {
        return 0.0;
    }
    var d = frame.lin_a * z + frame.lin_b;
    if frame.lin_reciprocal != 0u {
        d = 1.0 / d;
    }
    if is_nonfinite(d) || d <= 0.0 {
        return 0.0;
    }
    return d;
}

// View-space position of pixel-space point `p` (viewport-local; pixel centres at +0.5)
// at linear depth `d`. View space: x right, y up, camera looking down -z.
fn view_position(p: vec2<f32>, d: f32) -> vec3<f32> {
    return view_position_scaled(p, d, frame.ndc_to_view, frame.inv_size);
}

// d(view_position(p, 1).xy)/dp: view_position is linear in p (ndc spans 2 over the size, y
// flips), so a pixel offset moves its xy at depth 1 by this per pixel.
fn view_xy_per_pixel() -> vec2<f32> {
    return vec2<f32>(2.0, -2.0) * frame.inv_size * frame.ndc_to_view;
}

// `view_position` with another projection's `ndc_to_view` on another grid's `inv_size` (the
// previous frame's).
fn view_position_scaled(p: vec2<f32>, d: f32, ndc_to_view: vec2<f32>, inv_size: vec2<f32>) -> vec3<f32> {
    let ndc = vec2<f32>(p.x * inv_size.x * 2.0 - 1.0, 1.0 - p.y * inv_size.y * 2.0);
    var xy = ndc * ndc_to_view;
    if frame.perspective != 0u {
        xy = xy * d;
    }
    return vec3<f32>(xy, -d);
}

// Prepared value `v` = vec4(linear depth, normal), seen at pixel-space point `seen_at`, moved
// along its own tangent plane to the ray through pixel-space point `centre` (the depth
// rules' and the rescale pass's recentring: positions are rebuilt at texel centres
// downstream). Kept as is on grazing surfaces (|n . ray| < 0.2) and where the move would
// exceed 10% of the depth. Mirror: src/reference.rs, `recentred_to`.
fn recentred_to(seen_at: vec2<f32>, centre: vec2<f32>, v: vec4<f32>) -> vec4<f32> {
    let p = view_position(seen_at, v.x);
    let n = v.yzw;
    var d = v.x;
    if frame.perspective != 0u {
        // The ray through the centre at depth 1 is r; the plane n.(X - p) = 0 meets it at d r.
        let r = view_position(centre, 1.0);
        let nr = dot(n, r);
        if abs(nr) >= 0.2 * length(r) {
            d = dot(n, p) / nr;
        }
    } else if abs(n.z) >= 0.2 {
        let q = view_position(centre, v.x);
        d = v.x + dot(n.xy, q.xy - p.xy) / n.z;
    }
    if !(d > 0.0) || abs(d - v.x) > 0.1 * v.x {
        return v;
    }
    return vec4<f32>(d, n);
}

// Depth noise σ at linear depth `d` (AoParams::depth_noise; 0 for rendered depth).
fn depth_sigma(d: f32) -> f32 {
    return max(frame.noise.x + (frame.noise.y + frame.noise.z * d) * d, 0.0);
}

// Tangent-plane tolerance of the depth-aware passes at linear depth `d`: PLANE_TOLERANCE of
// the depth, and at least NOISE_TOLERANCE_SIGMAS σ of the depth noise. Mirror:
// `FrameUniforms::plane_tolerance`.
fn plane_tolerance(d: f32) -> f32 {
    return max(PLANE_TOLERANCE * d, NOISE_TOLERANCE_SIGMAS * depth_sigma(d));
}

// The depth terraces' step at linear depth `d` (DepthNoise::step; 0 for rendered depth).
// Mirror: `FrameUniforms::depth_step`.
fn depth_step(d: f32) -> f32 {
    return max(frame.noise_step.x, frame.noise_step.y * d * d);
}

// Where the estimators measure occluders from: the surface point of pixel-space `p` at
// depth `d`, raised NOISE_OFFSET_SIGMAS σ along its normal `n`, so depth noise within that
// of the tangent plane is not occlusion. The surface itself for rendered depth.
// Mirror: `FrameUniforms::estimator_origin`.
fn estimator_origin(p: vec2<f32>, d: f32, n: vec3<f32>) -> vec3<f32> {
    return view_position(p, d) + n * (NOISE_OFFSET_SIGMAS * depth_sigma(d));
}

// Deinterleaved layer of full-resolution pixel `p` for an n x n split (src/layout.rs).
fn layer_of(p: vec2<u32>, n: u32) -> u32 {
    return p.x % n + n * (p.y % n);
}

// The AO radius projected to the screen, in pixels, for a surface at linear depth `d`
// (clamped to max_radius_px). Mirror: `FrameUniforms::radius_px`.
fn radius_px(d: f32) -> f32 {
    var r = frame.radius * frame.radius_to_px;
    if frame.perspective != 0u {
        r = r / d;
    }
    return min(r, frame.max_radius_px);
}

// Ray-march step, in pixels: the radius split into `steps + 1` parts (HBAO+'s spacing), so
// the march, one pixel out plus an offset in [0, 1) steps, never samples the outer
// 1 / (steps + 1) of the radius. Stretching the steps to reach it raised GTAO's error
// against ray-traced AO (4 × 4: 0.0622 → 0.0654; docs/sample-reuse.md): the nearer, denser
// samples find more of the horizon. Mirror: `FrameUniforms::step_px`.
fn march_step_px(d: f32, steps: u32) -> f32 {
    return radius_px(d) / f32(steps + 1u);
}

// Where step s of `steps` lands along a direction (GTAO, bitmask), pixels from the centre,
// with j the pattern's offset, e the march exponent (the estimator's MARCH_EXPONENT override,
// so this branch is resolved when the pipeline compiles) and `cell` the sampling lattice's
// cell (1, or N for the N x N layers): e = 1 is the even march 1 + (s + j) step_px of every
// release; above 1 the steps crowd toward the centre, where contact shadows a few pixels wide
// are (XeGTAO's "sample distribution power"), from one lattice cell out:
// cell + (1 + step_px steps - cell) ((s + j) / steps)^e, so that short steps do not round
// onto the centre of a coarser lattice. Mirror: `estimators::march_ray`.
fn march_ray(s: u32, steps: u32, j: f32, step_px: f32, cell: f32, e: f32) -> f32 {
    let n = f32(steps);
    if e == 1.0 {
        return 1.0 + (f32(s) + j) * step_px;
    }
    return cell + (1.0 + step_px * n - cell) * march_power((f32(s) + j) / n, e);
}

// t^e for t in [0, 1]. The exponents 1.25, 1.5 and 2 by square roots and a product: the
// same powers, where a CPU adapter (lavapipe) evaluates pow as exp2 and log2 polynomials,
// once per step of every slice (docs/patterns.md). Mirror: `estimators::march_power`.
fn march_power(t: f32, e: f32) -> f32 {
    if e == 1.25 {
        return t * sqrt(sqrt(t));
    }
    if e == 1.5 {
        return t * sqrt(t);
    }
    if e == 2.0 {
        return t * t;
    }
    return pow(t, e);
}

// Whether working-grid pixel `p` (centred at full-resolution (p + 0.5) · inv_scale) lies
// more than GUARD_AO_MARGIN working texels outside the output, in a guard band where no
// later pass reads its AO (AoInput::guard_band; never without a band: the output then
// starts at 0 and spans the grid).
fn beyond_output(p: vec2<u32>) -> bool {
    let f = (vec2<f32>(p) + 0.5) * frame.inv_scale;
    let m = f32(GUARD_AO_MARGIN) * frame.inv_scale;
    let lo = vec2<f32>(frame.output_offset) - m;
    let hi = vec2<f32>(frame.output_offset + frame.output_size) + m;
    return any(f < lo) || any(f > hi);
}
