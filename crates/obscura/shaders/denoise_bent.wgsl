// Bent normals through the denoiser (AoOptions::bent_normals): each tap's bent normal takes
// the weight of its AO tap, and the centre gets their weighted mean, renormalised (a mean
// direction, where the AO gets the fitted plane's centre: the fit removes the bias of a
// one-sided kernel on a value, and the bent normal's own unit length is restored anyway).
// Sky pixels pass through. Composed before denoise.wgsl.

@group(0) @binding(4) var bent_in: texture_2d<f32>;
@group(0) @binding(5) var bent_out: texture_storage_2d<rgba32float, write>;

var<private> bent_sum: vec3<f32>;

fn bent_tap(q: vec2<i32>, w: f32) {
    bent_sum += w * textureLoad(bent_in, q, 0).xyz;
}

fn bent_store(p: vec2<i32>, filtered: bool) {
    var b = textureLoad(bent_in, p, 0).xyz;
    if filtered && dot(bent_sum, bent_sum) > 1e-12 {
        b = normalize(bent_sum);
    }
    textureStore(bent_out, p, vec4<f32>(b, 0.0));
}
