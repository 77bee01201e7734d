// Joint bilateral upsampling (Yang et al., "Geometry-Aware Framebuffer Level of Detail",
// EGSR 2008; seed 002): bilinear weight x depth weight x normal weight per footprint texel,
//   depth:  exp(-(distance from this pixel's tangent plane / (PLANE_TOLERANCE x depth))^2),
//   normal: max(n_low . n, 0)^8 (halves at 25 degrees).
// Where every weight vanishes (no texel on this surface), nearest-depth.
fn upsample(p: vec2<i32>, centre: vec4<f32>, fp: Footprint) -> f32 {
    let pos = view_position(vec2<f32>(p) + 0.5, centre.x);
    var sum = 0.0;
    var total = 0.0;
    for (var i = 0u; i < 4u; i++) {
        if fp.low[i].x <= 0.0 {
            continue;
        }
        let z = plane_distance(fp.pos[i], pos, centre.yzw, centre.x) / PLANE_TOLERANCE;
        let c = max(dot(fp.low[i].yzw, centre.yzw), 0.0);
        let c2 = c * c;
        let c4 = c2 * c2;
        let w = fp.w[i] * exp(-z * z) * c4 * c4;
        sum += w * fp.ao[i];
        total += w;
    }
    if total > 1e-4 {
        return sum / total;
    }
    let i = nearest_depth(fp, centre.x);
    if i < 0 {
        return dot(fp.w, fp.ao);
    }
    return fp.ao[i];
}
