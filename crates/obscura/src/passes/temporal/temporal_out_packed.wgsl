// The temporal pass's AO packed beside the pixel's geometry (estimators/ao_packed.wgsl) for
// the spatial denoiser that follows.
@group(0) @binding(5) var ao_out: texture_storage_2d<rgba32float, write>;

fn store_temporal(p: vec2<i32>, ao: f32, centre: vec4<f32>) {
    textureStore(ao_out, p, pack_ao(centre, ao));
}
