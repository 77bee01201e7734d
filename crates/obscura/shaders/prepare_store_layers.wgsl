// Prepare output written straight into SPLIT x SPLIT deinterleaved layers (the split fused
// into the prepare pass: no full-resolution intermediate). Layout: src/layout.rs.
override SPLIT: u32 = 4u;
@group(0) @binding(3) var prepared_out: texture_storage_2d_array<rgba32float, write>;

fn store_prepared(p: vec2<u32>, v: vec4<f32>) {
    textureStore(prepared_out, p / SPLIT, layer_of(p, SPLIT), v);
}
