// Bilinear upsampling: the baseline; blends across depth edges (and with sky).
fn upsample_weights(pos: vec3<f32>, centre: vec4<f32>, fp: Footprint) -> vec4<f32> {
    return fp.w;
}
