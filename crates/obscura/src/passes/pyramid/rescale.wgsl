// The prepared buffer at any working scale s in [1/4, 1] (Resolution::Scaled; seed 002:
// Yang, Sander & Lawrence's geometry-aware framebuffer level of detail, whose resolution
// changes every frame). Working texel q stands for the full-resolution pixels whose centres
// it covers, p + 0.5 in [q / s, (q + 1) / s). Of those among the 2 x 2 nearest its centre
// c = (q + 0.5) / s (all of them for s >= 1/2), the depth rule RULE picks one
// (downsample_rule.wgsl, `pick_child`: a real depth and normal of one surface, never an
// average, as seed 004's rules), moved along its own tangent plane to the ray through c
// (RECENTRE) so positions rebuilt at texel centres lie on the surface. At s = 1/2 these are
// the 2 x 2 children of half resolution; at s = 1 the one pixel, unmoved: the identity.
// Without a surface among them, the pixel nearest c. Composed after downsample_rule.wgsl;
// bound with the working frame (FrameUniforms::at_scale). CPU mirror: src/reference.rs,
// `rescale`.

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var full_in: texture_2d<f32>;
@group(0) @binding(2) var work_out: texture_storage_2d<rgba32float, write>;

// Candidate i of the working texel of this invocation (the global `texel`): the prepared
// value of pixel `first + child_offset(i)`, or vec4(0) (no surface) where that pixel is
// outside the image or its centre maps to another texel.
var<private> texel: vec2<u32>;

fn candidate(first: vec2<i32>, last: vec2<i32>, i: u32) -> vec4<f32> {
    let u = first + child_offset(i);
    let p = clamp(u, vec2<i32>(0), last);
    let v = textureLoad(full_in, p, 0);
    let member = all(u == p) && all(vec2<u32>((vec2<f32>(p) + 0.5) * frame.scale) == texel);
    return select(vec4<f32>(0.0), v, member);
}

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if any(gid.xy >= frame.size) {
        return;
    }
    texel = gid.xy;
    let q = vec2<f32>(gid.xy) + 0.5;
    let c = q * frame.inv_scale;
    let last = vec2<i32>(frame.full_size) - 1;
    let first = vec2<i32>(floor(c - 0.5));
    // Candidate i: pixel `first + child_offset(i)`, kept if it is in the image, its centre
    // maps into this texel (each pixel belongs to exactly one texel) and it is not sky.
    var pick = 4u;
    var out = vec4<f32>(0.0);
    if RULE == 3u {
        var v: array<vec4<f32>, 4>;
        var alive: array<bool, 4>;
        var depth: array<f32, 4>;
        var count = 0u;
        for (var i = 0u; i < 4u; i++) {
            v[i] = candidate(first, last, i);
            alive[i] = v[i].x > 0.0;
            depth[i] = select(0.0, v[i].x, alive[i]);
            count += u32(alive[i]);
        }
        if count > 0u {
            pick = pick_child(vec2<i32>(gid.xy), depth, alive, count);
            out = v[pick];
        }
    } else {
        // Max, min or checkerboard as pick_child decides them (the first of equal depths
        // wins), without its arrays: CPU drivers keep indexed arrays in memory.
        let max_rule = RULE == 0u || (RULE == 2u && ((gid.x + gid.y) & 1u) == 1u);
        for (var i = 0u; i < 4u; i++) {
            let v = candidate(first, last, i);
            let better = pick == 4u || select((v.x < out.x), (v.x > out.x), max_rule);
            let take = v.x > 0.0 && better;
            out = select(out, v, take);
            pick = select(pick, i, take);
        }
    }
    if pick == 4u {
        // No surface among them: the pixel nearest the centre, as it is.
        textureStore(work_out, gid.xy, textureLoad(full_in, min(vec2<i32>(c), last), 0));
        return;
    }
    if RECENTRE {
        // This grid's pixel coordinates: full-resolution x maps to x * scale.
        let p = first + child_offset(pick);
        out = recentred_to((vec2<f32>(p) + 0.5) * frame.scale, q, out);
    }
    textureStore(work_out, gid.xy, out);
}
