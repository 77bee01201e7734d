// Prepared source of the passes after the AO (denoise, temporal) in fused deinterleaved
// modes, which have no full-resolution buffer: pixel q lives in layer (q mod SPLIT),
// texel q / SPLIT (src/layout.rs).
override SPLIT: u32 = 2u;

@group(0) @binding(1) var prepared_in: texture_2d_array<f32>;

fn prepared_at(q: vec2<i32>) -> vec4<f32> {
    let u = vec2<u32>(q);
    return textureLoad(prepared_in, u / SPLIT, layer_of(u, SPLIT), 0);
}
