// Prepare output written straight into SPLIT x SPLIT deinterleaved layers (the split fused
// into the prepare pass: no full-resolution intermediate). Invocation (x, y, l) handles
// texel (x, y) of layer l, i.e. pixel (x*SPLIT + l % SPLIT, y*SPLIT + l / SPLIT), so each
// workgroup writes a contiguous block of one layer. Layout: src/layout.rs.
override SPLIT: u32 = 4u;
@group(0) @binding(3) var prepared_out: texture_storage_2d_array<rgba32float, write>;

fn pixel_of(gid: vec3<u32>) -> vec2<u32> {
    return gid.xy * SPLIT + vec2<u32>(gid.z % SPLIT, gid.z / SPLIT);
}

fn store_prepared(gid: vec3<u32>, v: vec4<f32>) {
    textureStore(prepared_out, gid.xy, gid.z, v);
}
