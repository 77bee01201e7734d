// Nearest-depth upsampling (seed 004): the AO of the footprint texel whose depth is closest
// to this pixel's. No blending: blocky on surfaces, no bleeding across edges.
fn upsample_weights(pos: vec3<f32>, centre: vec4<f32>, fp: Footprint) -> vec4<f32> {
    return nearest_weights(fp, centre.x);
}
