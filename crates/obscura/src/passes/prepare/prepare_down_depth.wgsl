// prepare_down.wgsl's full-resolution output: linear depth only (every upsampler but the
// bilateral one); without a noise model the picked child's normal is built afterwards, for
// it alone.
const CHILD_NORMALS: bool = false;
@group(0) @binding(4) var full_out: texture_storage_2d<r32float, write>;

fn store_child(c: vec2<i32>, v: vec4<f32>) {
    textureStore(full_out, c, vec4<f32>(v.x, 0.0, 0.0, 0.0));
}
