// Prepare pass: raw depth -> linear view depth, plus a view-space normal (decoded from the
// caller's normal texture, or reconstructed from depth), packed as vec4(d, n.xyz).
// Sky / missing depth is stored as d = 0. Composed with a depth_input_*.wgsl (declares
// @binding(1) and `load_raw_depth`) and a prepare_store_*.wgsl (declares @binding(3) and
// `store_prepared`: full resolution, or straight into deinterleaved layers).

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(2) var normals_in: texture_2d<f32>;

// Linear depth of viewport-local pixel `p`; 0 outside the viewport.
fn linear_depth_at(p: vec2<i32>) -> f32 {
    if any(p < vec2<i32>(0)) || any(p >= vec2<i32>(frame.size)) {
        return 0.0;
    }
    return linearize_depth(load_raw_depth(p + vec2<i32>(frame.viewport_origin)));
}

// Derivative of the view position along `axis`, taken towards the neighbour whose depth
// is closer to the centre's so silhouettes do not smear. When both neighbours are
// missing (sky, invalid depth, outside), the pixels two steps away are tried.
// w = 0 when none exists.
fn axis_derivative(p: vec2<i32>, axis: vec2<i32>, c: vec3<f32>, dc: f32) -> vec4<f32> {
    for (var k = 1; k <= 2; k++) {
        let step = axis * k;
        let dm = linear_depth_at(p - step);
        let dp = linear_depth_at(p + step);
        if dp > 0.0 && (dm <= 0.0 || abs(dp - dc) < abs(dm - dc)) {
            return vec4<f32>(view_position(vec2<f32>(p + step) + 0.5, dp) - c, 1.0);
        }
        if dm > 0.0 {
            return vec4<f32>(c - view_position(vec2<f32>(p - step) + 0.5, dm), 1.0);
        }
    }
    return vec4<f32>(0.0);
}

fn reconstruct_normal(p: vec2<i32>, c: vec3<f32>, dc: f32) -> vec3<f32> {
    let dx = axis_derivative(p, vec2<i32>(1, 0), c, dc);
    let dy = axis_derivative(p, vec2<i32>(0, 1), c, dc);
    let n = cross(dy.xyz, dx.xyz);
    let len2 = dot(n, n);
    if dx.w == 0.0 || dy.w == 0.0 || !(len2 > 0.0) {
        return normalize(-c);
    }
    let nn = n * inverseSqrt(len2);
    return select(nn, -nn, dot(nn, c) > 0.0);
}

fn provided_normal(p: vec2<i32>) -> vec3<f32> {
    var n = textureLoad(normals_in, p + vec2<i32>(frame.viewport_origin), 0).xyz;
    if frame.normals_mode == 2u {
        n = n * 2.0 - 1.0;
    }
    let len2 = dot(n, n);
    if !(len2 > 1e-12) || is_nonfinite(len2) {
        return vec3<f32>(0.0, 0.0, 1.0);
    }
    return n * inverseSqrt(len2);
}

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if any(gid.xy >= frame.size) {
        return;
    }
    let p = vec2<i32>(gid.xy);
    let d = linear_depth_at(p);
    if d <= 0.0 {
        store_prepared(gid.xy, vec4<f32>(0.0, 0.0, 0.0, 1.0));
        return;
    }
    let c = view_position(vec2<f32>(p) + 0.5, d);
    var n: vec3<f32>;
    if frame.normals_mode == 0u {
        n = reconstruct_normal(p, c, d);
    } else {
        n = provided_normal(p);
    }
    store_prepared(gid.xy, vec4<f32>(d, n));
}
