// Bilinear upsampling: the baseline; blends across depth edges (and with sky).
fn upsample(pos: vec3<f32>, centre: vec4<f32>, fp: Footprint) -> f32 {
    return dot(fp.w, fp.ao);
}
