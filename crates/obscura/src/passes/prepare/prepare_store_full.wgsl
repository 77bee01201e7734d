// Prepare output at full resolution: invocation (x, y) handles pixel (x, y).
@group(0) @binding(3) var prepared_out: texture_storage_2d<rgba32float, write>;

fn pixel_of(gid: vec3<u32>) -> vec2<u32> {
    return gid.xy;
}

fn store_prepared(gid: vec3<u32>, v: vec4<f32>) {
    textureStore(prepared_out, gid.xy, v);
}
