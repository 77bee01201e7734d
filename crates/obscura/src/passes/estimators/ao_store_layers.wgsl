// AO output kept in deinterleaved layers, merged later by interleave.wgsl. `centre`, the
// pixel's prepared value, is ao_store_packed.wgsl's.
@group(0) @binding(2) var ao_out: texture_storage_2d_array<r32float, write>;

fn store_ao(full: vec2<u32>, texel: vec2<u32>, layer: u32, ao: f32, centre: vec4<f32>) {
    textureStore(ao_out, texel, layer, vec4<f32>(ao, 0.0, 0.0, 0.0));
}
