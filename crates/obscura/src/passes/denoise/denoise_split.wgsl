// The denoiser's taps from two textures: the prepared source (prepared_full.wgsl or
// prepared_layers.wgsl) and the AO, two fetches a tap. Where the AO pass writes the AO
// packed with its geometry, denoise_packed.wgsl reads it in one.

@group(0) @binding(2) var ao_in: texture_2d<f32>;

fn denoise_tap(q: vec2<i32>) -> DenoiseTap {
    return DenoiseTap(prepared_at(q), textureLoad(ao_in, q, 0).x);
}
