// The denoiser's taps from the AO pass's packed output (estimators/ao_packed.wgsl): the
// AO and the prepared value vec4(depth, normal) in one fetch a tap.

@group(0) @binding(2) var ao_in: texture_2d<f32>;

fn denoise_tap(q: vec2<i32>) -> DenoiseTap {
    let t = textureLoad(ao_in, q, 0);
    return DenoiseTap(unpack_prepared(t), abs(t.w) - 1.0);
}
