// Output of the many-light passes as irradiance, vec4(rgb, 1) (LIT_FORMAT).

@group(0) @binding(4) var lit_out: texture_storage_2d<rgba32float, write>;

// Stores irradiance `e` of pixel `p` (geometry `g` is not kept).
fn store_lit(p: vec2<i32>, g: vec4<f32>, e: vec3<f32>) {
    textureStore(lit_out, p, vec4<f32>(e, 1.0));
}
