// Bilinear upsampling: the baseline; blends across depth edges (and with sky).
fn upsample(p: vec2<i32>, centre: vec4<f32>, fp: Footprint) -> f32 {
    return dot(fp.w, fp.ao);
}
