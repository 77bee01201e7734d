// Nearest-depth upsampling (seed 004): the AO of the footprint texel whose depth is closest
// to this pixel's. No blending: blocky on surfaces, no bleeding across edges.
fn upsample(pos: vec3<f32>, centre: vec4<f32>, fp: Footprint) -> f32 {
    let i = nearest_depth(fp, centre.x);
    if i < 0 {
        return dot(fp.w, fp.ao);
    }
    return fp.ao[i];
}
