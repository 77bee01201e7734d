// Normals reconstructed from depth (composed into prepare.wgsl).

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

fn view_normal(p: vec2<i32>, c: vec3<f32>, dc: f32) -> vec3<f32> {
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
