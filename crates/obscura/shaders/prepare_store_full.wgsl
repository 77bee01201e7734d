// Prepare output at full resolution.
@group(0) @binding(3) var prepared_out: texture_storage_2d<rgba32float, write>;

fn store_prepared(p: vec2<u32>, v: vec4<f32>) {
    textureStore(prepared_out, p, v);
}
