// The 2x2 -> 1 depth rules of seed 004, shared by downsample.wgsl and prepare_down.wgsl.
// Low-resolution texel t stands for children 2t + (i & 1, i >> 1), i = 0..3, of the level
// above; the rule picks one child (depths are never averaged: an average is a surface that
// is not there) and the caller copies that child's depth and normal as a pair.
// RULE: 0 max, 1 min, 2 checkerboard (min where t.x + t.y is even, else max),
// 3 most representative (drop the child farthest from the centroid of those left until two
// remain, keep the one closer to the centroid of the last three).
// CPU mirror: src/reference.rs, `downsample`.

override RULE: u32 = 3u;
// The pass makes prepared level LEVEL from level LEVEL - 1 (0 = full resolution).
override LEVEL: u32 = 1u;
override RECENTRE: bool = true;

fn child_offset(i: u32) -> vec2<i32> {
    return vec2<i32>(i32(i & 1u), i32(i >> 1u));
}

// The child `RULE` picks among the `count` >= 1 alive ones (depths in `depth`).
fn pick_child(t: vec2<i32>, depth: array<f32, 4>, alive_in: array<bool, 4>, count: u32) -> u32 {
    var alive = alive_in;
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
            anchor += select(0.0, depth[i], alive[i]);
        }
        anchor = anchor / f32(count);
        for (var left = count; left > 2u; left--) {
            var sum = 0.0;
            for (var i = 0u; i < 4u; i++) {
                sum += select(0.0, depth[i], alive[i]);
            }
            let centroid = sum / f32(left);
            anchor = centroid;
            var worst = 0u;
            var worst_dist = -1.0;
            for (var i = 0u; i < 4u; i++) {
                if alive[i] && abs(depth[i] - centroid) > worst_dist {
                    worst = i;
                    worst_dist = abs(depth[i] - centroid);
                }
            }
            alive[worst] = false;
        }
        var best_dist = 3.4e38;
        for (var i = 0u; i < 4u; i++) {
            if alive[i] && abs(depth[i] - anchor) < best_dist {
                pick = i;
                best_dist = abs(depth[i] - anchor);
            }
        }
    } else {
        var best = select(3.4e38, -1.0, rule == 0u);
        for (var i = 0u; i < 4u; i++) {
            if alive[i] && ((rule == 0u && depth[i] > best) || (rule == 1u && depth[i] < best)) {
                best = depth[i];
                pick = i;
            }
        }
    }
    return pick;
}

// RECENTRE: the pick's depth moved along its own tangent plane to the ray through the
// centre of texel t (positions are rebuilt at texel centres downstream); common.wgsl,
// `recentred_to`.
fn recentred(t: vec2<i32>, pick: u32, v: vec4<f32>) -> vec4<f32> {
    if !RECENTRE {
        return v;
    }
    // Full-resolution pixels per source texel (2^(LEVEL-1)) and per destination texel.
    let s = f32(1u << (LEVEL - 1u));
    let child = vec2<f32>(2 * t + child_offset(pick));
    return recentred_to((child + 0.5) * s, (vec2<f32>(t) + 0.5) * 2.0 * s, v);
}
