// prepare_down.wgsl's full-resolution output: vec4(depth, normal) of every child, as
// prepare.wgsl writes it (the bilateral upsampler weighs by normal agreement).
const CHILD_NORMALS: bool = true;
@group(0) @binding(4) var full_out: texture_storage_2d<rgba32float, write>;

fn store_child(c: vec2<i32>, v: vec4<f32>) {
    textureStore(full_out, c, v);
}
