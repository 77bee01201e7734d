// A pixel's prepared value, vec4(depth, normal), for depth without a noise model: the
// depth as given and `view_normal` (composed after a normals_*.wgsl into the prepare passes).

fn surface(p: vec2<i32>, d: f32) -> vec4<f32> {
    return vec4<f32>(d, view_normal(p, view_position(vec2<f32>(p) + 0.5, d), d));
}
