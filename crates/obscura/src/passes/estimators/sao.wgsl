// Scalable Ambient Obscurance (McGuire, Mara & Luebke, HPG 2012): the estimator only,
// composed like hbao.wgsl with an entry fragment (`snap_offset`, `sample_depth`).
//
// N = DIRECTIONS * STEPS samples on a spiral: sample i at angle i * golden angle (Vogel's
// spiral instead of the paper's per-N turn table), rotated by the pattern, at screen radius
// alpha_i * r_px with alpha_i = (i + pattern.z) / N. A sample r pixels away reads the depth
// pyramid at level floor(log2(r)) - 3 (the paper's q' = 8 pixels), so far samples fetch
// from small, cache-resident levels: cost no longer grows with the radius.
//
// Obscurance (Alchemy AO, McGuire et al. 2011, the sum SAO evaluates):
//   A = 1 - (2 sigma / N) * sum max(0, v.n - |v| sin_bias) / (v.v + eps),  over |v| < R,
// with sigma = R: samples spaced linearly in radius each stand for an annulus of area
// 2 pi R^2 alpha / N, and that patch seen from the centre occludes about
// (1/pi) cos(theta) area / |v|^2, which sums to the expression above, so it is independent of
// the scene's scale. eps = 0.01 R^2 bounds the weight of samples next to the centre.
// Visibility is cut at R (no falloff), the ray-traced reference's definition.
// CPU mirror: src/reference.rs, `sao_pixel`.

override DIRECTIONS: u32 = 8u;
override STEPS: u32 = 4u;

// The golden angle as a fraction of a turn, (3 - sqrt 5) / 2: angles stay in [0, 2 pi),
// where sin/cos are accurate on every driver.
const GOLDEN_TURN: f32 = 0.3819660112501051;
const LOG2_MIP_STRIDE: i32 = 3;

@group(0) @binding(3) var pyramid: texture_2d<f32>;

// Depth of pixel `q` of this frame's grid, `r_px` pixels from the centre. Pyramid level L
// of the full-resolution buffer is level L - pyramid_offset of this grid (below full
// resolution the pyramid still comes from the full-resolution buffer).
fn sao_depth(q: vec2<i32>, r_px: f32) -> f32 {
    // floor(log2(r)) as the paper's findMSB of the integer radius: exact, no log2 rounding.
    let most = max(i32(textureNumLevels(pyramid)) - i32(frame.pyramid_offset), 0);
    let level = clamp(i32(firstLeadingBit(u32(max(r_px, 1.0)))) - LOG2_MIP_STRIDE, 0, most);
    if level == 0 {
        return sample_depth(q);
    }
    let mip = u32(level) + frame.pyramid_offset - 1u;
    // Mip sizes from the base size (wgpu's rule, max(1, base >> m)): lavapipe answered
    // textureDimensions(t, level) with another level's size.
    let size = max(vec2<i32>(textureDimensions(pyramid)) >> vec2<u32>(mip), vec2<i32>(1));
    return textureLoad(pyramid, min(q >> vec2<u32>(u32(level)), size - 1), mip).x;
}

fn estimate(p: vec2<i32>, centre: vec4<f32>, pattern: vec4<f32>) -> f32 {
    let d = centre.x;
    if d <= 0.0 {
        return 1.0;
    }
    let n = centre.yzw;
    let pos = estimator_origin(vec2<f32>(p) + 0.5, d, centre.yzw);
    let r_px = radius_px(d);
    let r2 = frame.radius * frame.radius;
    let count = DIRECTIONS * STEPS;
    var sum = 0.0;
    for (var i = 0u; i < count; i++) {
        let a = fract(f32(i) * GOLDEN_TURN) * TAU;
        let base = vec2<f32>(cos(a), sin(a));
        let dir = vec2<f32>(base.x * pattern.x - base.y * pattern.y, base.x * pattern.y + base.y * pattern.x);
        let ss_r = (f32(i) + pattern.z) / f32(count) * r_px;
        let q = p + snap_offset(dir * ss_r);
        if any(q < vec2<i32>(0)) || any(q >= vec2<i32>(frame.size)) {
            continue;
        }
        let sd = sao_depth(q, ss_r);
        if sd <= 0.0 {
            continue;
        }
        let v = view_position(vec2<f32>(q) + 0.5, sd) - pos;
        let vv = dot(v, v);
        if vv >= r2 {
            continue;
        }
        sum += max(dot(v, n) - sqrt(vv) * frame.sin_bias, 0.0) / (vv + 0.01 * r2);
    }
    return clamp(1.0 - sum * frame.radius * frame.ao_scale, 0.0, 1.0);
}
