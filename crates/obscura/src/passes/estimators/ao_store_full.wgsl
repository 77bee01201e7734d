// AO output at full resolution (for the deinterleaved pass: the merge fused into it),
// through output.wgsl's store. `centre`, the pixel's prepared value, is ao_store_packed.wgsl's.
@group(0) @binding(2) var ao_out: texture_storage_2d<r32float, write>;

fn store_ao(full: vec2<u32>, texel: vec2<u32>, layer: u32, ao: f32, centre: vec4<f32>) {
    store_output(vec2<i32>(full), ao);
}
