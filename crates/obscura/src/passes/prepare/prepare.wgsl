// Prepare pass: raw depth -> linear view depth, plus a view-space normal (decoded from the
// caller's normal texture, or reconstructed from depth), packed as vec4(d, n.xyz).
// Sky / missing depth is stored as d = 0. Composed with a depth_input_*.wgsl,
// prepare_input.wgsl, a normals_*.wgsl (`view_normal`: reconstructed or given), then
// surface_plain.wgsl or normals_fit.wgsl (`surface`: vec4(depth, normal)) and a
// prepare_store_*.wgsl (declares @binding(3) and `store_prepared`: full resolution, or
// straight into deinterleaved layers), then prepare_second*.wgsl (`store_second`: the
// second depth layer, or nothing). Separate fragments rather than a branch: an untaken
// uniform branch still cost lavapipe ~1/3 of this pass (BENCHMARKS.md).

@compute @workgroup_size(WG_SIZE, WG_SIZE, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let pixel = pixel_of(gid);
    if any(pixel >= frame.size) {
        return;
    }
    store_second(pixel);
    let p = vec2<i32>(pixel);
    let d = linear_depth_at(p);
    if d <= 0.0 {
        store_prepared(gid, vec4<f32>(0.0, 0.0, 0.0, 1.0));
        return;
    }
    store_prepared(gid, surface(p, d));
}
