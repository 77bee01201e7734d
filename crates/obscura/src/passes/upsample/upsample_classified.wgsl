// Classified upsampling (seed 004): the 2x2 footprint is a *surface* when
//  - every low-resolution normal is within 25 degrees of their mean (the seed's normal test),
//  - this pixel lies within plane_tolerance(depth) of every texel's tangent plane (catches
//    parallel surfaces at different depths, whose normals agree), and
//  - no texel's own footprint spans more than DEPTH_RANGE_TOLERANCE of its depth in the
//    min/max depth pyramid (its one depth stands for an edge inside it);
// bilinear on surfaces, nearest-depth on discontinuities.

@group(0) @binding(5) var pyramid: texture_2d<f32>;

const COS_25_DEG: f32 = 0.9063078;

// Distance of this pixel's surface point `pos` from the tangent plane of footprint texel
// `i`: small when the pixel lies on that texel's surface.
fn plane_distance(fp: Footprint, i: u32, pos: vec3<f32>) -> f32 {
    return abs(dot(pos - fp.pos[i], fp.low[i].yzw));
}

fn upsample_weights(pos: vec3<f32>, centre: vec4<f32>, fp: Footprint) -> vec4<f32> {
    let d = centre.x;
    var mean = vec3<f32>(0.0);
    var surface = true;
    // Pyramid level log2(UP_FACTOR) holds each low texel's footprint; its mip is one less.
    let mip = firstTrailingBit(UP_FACTOR) - 1u;
    let psize = max(vec2<i32>(textureDimensions(pyramid)) >> vec2<u32>(mip), vec2<i32>(1));
    for (var i = 0u; i < 4u; i++) {
        let low = fp.low[i];
        if low.x <= 0.0 {
            surface = false;
            continue;
        }
        mean += low.yzw;
        if plane_distance(fp, i, pos) > plane_tolerance(d) {
            surface = false;
        }
        let range = textureLoad(pyramid, min(fp.texel[i], psize - 1), mip).yz;
        if range.y - range.x > DEPTH_RANGE_TOLERANCE * range.x {
            surface = false;
        }
    }
    let m = normalize(mean);
    for (var i = 0u; i < 4u; i++) {
        if dot(fp.low[i].yzw, m) < COS_25_DEG {
            surface = false;
        }
    }
    if surface {
        return fp.w;
    }
    return nearest_weights(fp, d);
}
