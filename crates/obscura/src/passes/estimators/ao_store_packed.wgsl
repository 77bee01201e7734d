// AO output at full resolution packed beside its pixel's geometry (ao_packed.wgsl), for
// the spatial denoiser that follows.
@group(0) @binding(2) var ao_out: texture_storage_2d<rgba32float, write>;

fn store_ao(full: vec2<u32>, texel: vec2<u32>, layer: u32, ao: f32, centre: vec4<f32>) {
    textureStore(ao_out, vec2<i32>(full), pack_ao(centre, ao));
}
