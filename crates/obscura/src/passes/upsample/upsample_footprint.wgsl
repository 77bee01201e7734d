// The upsamplers' footprint: the 2x2 low-resolution texels around a full-resolution pixel
// (upsample.wgsl at a power-of-two factor, upsample_scaled.wgsl at any scale), and the
// nearest-depth choice among them. Composed before an upsample_*.wgsl weight fragment.

struct Footprint {
    // Bilinear weights, AO, prepared vec4(d, n) and view position of the 4 texels
    // (order: (0,0), (1,0), (0,1), (1,1)) and their texel coordinates.
    w: vec4<f32>,
    ao: vec4<f32>,
    low: array<vec4<f32>, 4>,
    pos: array<vec3<f32>, 4>,
    texel: array<vec2<i32>, 4>,
}

// All the weight on the footprint texel whose depth is closest to `d` (nearest-depth
// upsampling, and the fallback of the others); the bilinear weights if all four are sky.
fn nearest_weights(fp: Footprint, d: f32) -> vec4<f32> {
    let i = nearest_depth(fp, d);
    if i < 0 {
        return fp.w;
    }
    var w = vec4<f32>(0.0);
    w[i] = 1.0;
    return w;
}

// The footprint texel whose depth is closest to `d` (sky texels never win); -1 if all are sky.
fn nearest_depth(fp: Footprint, d: f32) -> i32 {
    var best = -1;
    var best_diff = 3.4e38;
    for (var i = 0; i < 4; i++) {
        if fp.low[i].x > 0.0 && abs(fp.low[i].x - d) < best_diff {
            best = i;
            best_diff = abs(fp.low[i].x - d);
        }
    }
    return best;
}
