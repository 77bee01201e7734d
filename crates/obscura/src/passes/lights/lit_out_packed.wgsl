// Output of the many-light passes as the packed texel (lit_packed.wgsl, LIT_PACKED_FORMAT),
// for the merge after them.

@group(0) @binding(4) var lit_out: texture_storage_2d<rgba32uint, write>;

// Stores irradiance `e` of pixel `p` with its geometry `g` = vec4(linear depth, normal).
fn store_lit(p: vec2<i32>, g: vec4<f32>, e: vec3<f32>) {
    textureStore(lit_out, p, pack_lit(g, e));
}
