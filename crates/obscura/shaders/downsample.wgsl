// Depth downsampling, 2x2 -> 1 (seed 004): low-resolution texel t is one of the prepared
// texels 2t + (0..1, 0..1) of the level above, chosen by RULE, with that texel's normal
// (the value is copied whole: depth and normal stay a real pair, never an average).
// Children outside the source (odd sizes: dst = ceil(src / 2)) and sky children are skipped.
// RULE: 0 max, 1 min, 2 checkerboard (min where t.x + t.y is even, else max),
// 3 most representative (drop the child farthest from the centroid of those left until two
// remain, keep the one closer to the centroid of the last three). CPU mirror: src/reference.rs, `downsample`.

override RULE: u32 = 3u;
// This pass makes prepared level LEVEL from level LEVEL - 1 (0 = full resolution).
override LEVEL: u32 = 1u;
override RECENTRE: bool = true;

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var src: texture_2d<f32>;
@group(0) @binding(2) var dst: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let t = vec2<i32>(gid.xy);
    if any(t >= vec2<i32>(textureDimensions(dst))) {
        return;
    }
    let size = vec2<i32>(textureDimensions(src));
    var v: array<vec4<f32>, 4>;
    var alive: array<bool, 4>;
    var count = 0u;
    for (var i = 0u; i < 4u; i++) {
        let c = 2 * t + vec2<i32>(i32(i & 1u), i32(i >> 1u));
        alive[i] = false;
        if all(c < size) {
            v[i] = textureLoad(src, c, 0);
            alive[i] = v[i].x > 0.0;
        }
        count += u32(alive[i]);
    }
    if count == 0u {
        textureStore(dst, t, vec4<f32>(0.0, 0.0, 0.0, 1.0));
        return;
    }
    var rule = RULE;
    if rule == 2u {
        rule = select(1u, 0u, ((t.x + t.y) & 1) == 1);
    }
    var pick = 0u;
    if rule == 3u {
        // Drop the farthest from the centroid of the depths left until two remain, then
        // keep the one closer to the last centroid (of the last three; with only two valid
        // children their midpoint, a tie: the earlier).
        var anchor = 0.0;
        for (var i = 0u; i < 4u; i++) {
            anchor += select(0.0, v[i].x, alive[i]);
        }
        anchor = anchor / f32(count);
        for (var left = count; left > 2u; left--) {
            var sum = 0.0;
            for (var i = 0u; i < 4u; i++) {
                sum += select(0.0, v[i].x, alive[i]);
            }
            let centroid = sum / f32(left);
            anchor = centroid;
            var worst = 0u;
            var worst_dist = -1.0;
            for (var i = 0u; i < 4u; i++) {
                if alive[i] && abs(v[i].x - centroid) > worst_dist {
                    worst = i;
                    worst_dist = abs(v[i].x - centroid);
                }
            }
            alive[worst] = false;
        }
        var best_dist = 3.4e38;
        for (var i = 0u; i < 4u; i++) {
            if alive[i] && abs(v[i].x - anchor) < best_dist {
                pick = i;
                best_dist = abs(v[i].x - anchor);
            }
        }
    } else {
        var best = select(3.4e38, -1.0, rule == 0u);
        for (var i = 0u; i < 4u; i++) {
            if alive[i] && ((rule == 0u && v[i].x > best) || (rule == 1u && v[i].x < best)) {
                best = v[i].x;
                pick = i;
            }
        }
    }
    textureStore(dst, t, recentred(t, pick, v[pick]));
}

// RECENTRE: the pick's depth moved along its own tangent plane to the ray through the
// centre of texel t (positions are rebuilt at texel centres downstream). Kept as picked on
// grazing surfaces (|n . ray| < 0.2) and where the move would exceed 10% of the depth.
fn recentred(t: vec2<i32>, pick: u32, v: vec4<f32>) -> vec4<f32> {
    if !RECENTRE {
        return v;
    }
    // Full-resolution pixels per source texel (2^(LEVEL-1)) and per destination texel.
    let s = f32(1u << (LEVEL - 1u));
    let child = vec2<f32>(2 * t + vec2<i32>(i32(pick & 1u), i32(pick >> 1u)));
    let p = view_position((child + 0.5) * s, v.x);
    let centre = (vec2<f32>(t) + 0.5) * 2.0 * s;
    let n = v.yzw;
    var d = v.x;
    if frame.perspective != 0u {
        // The ray through the centre at depth 1 is r; the plane n.(X - p) = 0 meets it at d r.
        let r = view_position(centre, 1.0);
        let nr = dot(n, r);
        if abs(nr) >= 0.2 * length(r) {
            d = dot(n, p) / nr;
        }
    } else if abs(n.z) >= 0.2 {
        let q = view_position(centre, v.x);
        d = v.x + dot(n.xy, q.xy - p.xy) / n.z;
    }
    if !(d > 0.0) || abs(d - v.x) > 0.1 * v.x {
        return v;
    }
    return vec4<f32>(d, n);
}
