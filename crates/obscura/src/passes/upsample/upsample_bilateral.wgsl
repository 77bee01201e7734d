// Joint bilateral upsampling (Yang et al., "Geometry-Aware Framebuffer Level of Detail",
// EGSR 2008; seed 002): bilinear weight x depth weight x normal weight per footprint texel,
//   depth:  exp(-(distance of the texel from this pixel's tangent plane /
//           plane_tolerance(depth))^2),
//   normal: max(n_low . n, 0)^8 (halves at 25 degrees).
// The normal weight is what makes it better than bilinear away from edges too: a low texel
// stands for one child's face, and a pixel on a face turned another way takes its AO from
// texels of its own orientation (mean RMSE against ray-traced AO at half resolution 0.079
// with it, 0.089 without, docs/mixed-resolution.md). Needs the full-resolution normal
// (`centre.yzw`). Where every weight vanishes (no texel on this surface), nearest-depth.
fn upsample_weights(pos: vec3<f32>, centre: vec4<f32>, fp: Footprint) -> vec4<f32> {
    let d = centre.x;
    let n = centre.yzw;
    var w = vec4<f32>(0.0);
    for (var i = 0u; i < 4u; i++) {
        if fp.low[i].x <= 0.0 {
            continue;
        }
        let z = abs(dot(fp.pos[i] - pos, n)) / plane_tolerance(d);
        let c = max(dot(fp.low[i].yzw, n), 0.0);
        let c2 = c * c;
        let c4 = c2 * c2;
        w[i] = fp.w[i] * exp(-z * z) * c4 * c4;
    }
    let total = w.x + w.y + w.z + w.w;
    if total > 1e-4 {
        return w / total;
    }
    return nearest_weights(fp, d);
}
