// prepare_down.wgsl's full-resolution output: linear depth only (every upsampler but the
// bilateral one); the picked child's normal is built afterwards, for it alone.
const CHILD_NORMALS: bool = false;
@group(0) @binding(4) var full_out: texture_storage_2d<r32float, write>;

fn store_child(c: vec2<i32>, d: f32) -> vec4<f32> {
    textureStore(full_out, c, vec4<f32>(d, 0.0, 0.0, 0.0));
    return vec4<f32>(d, 0.0, 0.0, 1.0);
}
