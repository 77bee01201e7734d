// Four levels of the depth pyramid in one pass (the most WebGPU's default limit of 4
// storage textures per stage allows): levels 1-4 below the source level `src` (a pyramid
// mip). Each workgroup computes a WG_SIZE^2 (8x8) tile of level 1 from the source, then the
// 4x4, 2x2 and 1x1 tiles of levels 2-4 from the level above, kept in workgroup memory. Values
// and footprints are those of pyramid.wgsl (CPU mirror: src/reference.rs, `pyramid`,
// checked bit for bit): an odd level's last texel also covers the orphan row/column, which
// can lie in the next workgroup's tile; such a child is computed directly from the source
// (`from_source`: the select follows the picks down, min/max span the whole footprint,
// which equals the level-by-level result because min and max are exact).
// Outputs beyond the last mip are bound to 1x1 placeholders and written harmlessly.

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var src: texture_2d<f32>;
@group(0) @binding(2) var out1: texture_storage_2d<rgba32float, write>;
@group(0) @binding(3) var out2: texture_storage_2d<rgba32float, write>;
@group(0) @binding(4) var out3: texture_storage_2d<rgba32float, write>;
@group(0) @binding(5) var out4: texture_storage_2d<rgba32float, write>;

const T1: u32 = WG_SIZE * WG_SIZE;
var<workgroup> tile1: array<vec3<f32>, T1>;
var<workgroup> tile2: array<vec3<f32>, T1 / 4u>;
var<workgroup> tile3: array<vec3<f32>, T1 / 16u>;

// Size of level j (0 = the source), as wgpu sizes mips: max(1, size >> 1) per level.
fn level_size(j: u32) -> vec2<i32> {
    var s = vec2<i32>(textureDimensions(src));
    for (var i = 0u; i < j; i++) {
        s = max(s >> vec2<u32>(1u), vec2<i32>(1));
    }
    return s;
}

// The child texel of level j - 1 whose select value texel t of level j takes (the rotated
// grid of pyramid.wgsl).
fn pick_child(t: vec2<i32>, below: vec2<i32>) -> vec2<i32> {
    return min(2 * t + vec2<i32>((t.y & 1) ^ 1, (t.x & 1) ^ 1), below - 1);
}

// The last child of texel t of level j - 1 (sizes `size` at j, `below` at j - 1): 2t + 1,
// or the orphan 2t + 2 for the last texel of an odd-sized level.
fn last_child(t: vec2<i32>, size: vec2<i32>, below: vec2<i32>) -> vec2<i32> {
    return min(select(2 * t + 1, below - 1, t == size - 1), below - 1);
}

fn accumulate(acc: vec2<f32>, s: vec3<f32>) -> vec2<f32> {
    if s.z > 0.0 {
        return vec2<f32>(min(acc.x, s.y), max(acc.y, s.z));
    }
    return acc;
}

fn finish(select_depth: f32, acc: vec2<f32>) -> vec3<f32> {
    if acc.y <= 0.0 {
        return vec3<f32>(select_depth, 0.0, 0.0);
    }
    return vec3<f32>(select_depth, acc);
}

// Texel t of level j computed from the source alone.
fn from_source(j: u32, t: vec2<i32>) -> vec3<f32> {
    var p = t;
    var lo = t;
    var hi = t;
    for (var i = j; i > 0u; i--) {
        let size = level_size(i);
        let below = level_size(i - 1u);
        p = pick_child(p, below);
        hi = last_child(hi, size, below);
        lo = 2 * lo;
    }
    var acc = vec2<f32>(3.4e38, 0.0);
    for (var y = lo.y; y <= hi.y; y++) {
        for (var x = lo.x; x <= hi.x; x++) {
            acc = accumulate(acc, textureLoad(src, vec2<i32>(x, y), 0).xyz);
        }
    }
    return finish(textureLoad(src, p, 0).x, acc);
}

// Child c of level j - 1 for the workgroup whose level-(j - 1) tile starts at `origin` with
// `extent` texels per axis: from the tile when it holds it, else from the source.
fn child(j: u32, c: vec2<i32>, origin: vec2<i32>, extent: i32) -> vec3<f32> {
    let l = c - origin;
    if all(l < vec2<i32>(extent)) {
        let i = u32(l.y * extent + l.x);
        if j == 2u {
            return tile1[i];
        } else if j == 3u {
            return tile2[i];
        }
        return tile3[i];
    }
    return from_source(j - 1u, c);
}

// Texel t of level j >= 2 from its children in level j - 1.
fn from_children(j: u32, t: vec2<i32>, origin: vec2<i32>, extent: i32) -> vec3<f32> {
    let size = level_size(j);
    let below = level_size(j - 1u);
    let hi = last_child(t, size, below);
    var acc = vec2<f32>(3.4e38, 0.0);
    for (var y = 2 * t.y; y <= hi.y; y++) {
        for (var x = 2 * t.x; x <= hi.x; x++) {
            acc = accumulate(acc, child(j, vec2<i32>(x, y), origin, extent));
        }
    }
    return finish(child(j, pick_child(t, below), origin, extent).x, acc);
}

fn store(j: u32, t: vec2<i32>, v: vec3<f32>) {
    let texel = vec4<f32>(v, 0.0);
    if j == 1u {
        textureStore(out1, t, texel);
    } else if j == 2u {
        textureStore(out2, t, texel);
    } else if j == 3u {
        textureStore(out3, t, texel);
    } else {
        textureStore(out4, t, texel);
    }
}

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
) {
    let l = vec2<i32>(lid.xy);
    // Level 1 from the source.
    let t1 = vec2<i32>(wg.xy) * i32(WG_SIZE) + l;
    var v = vec3<f32>(0.0);
    if all(t1 < level_size(1u)) {
        v = from_source(1u, t1);
        store(1u, t1, v);
    }
    tile1[lid.y * WG_SIZE + lid.x] = v;
    workgroupBarrier();
    // Levels 2-4 from the tile above: extents WG_SIZE / 2, / 4, / 8. Each level reads only
    // the tile of the level above and writes its own, so one barrier per level suffices.
    for (var j = 2u; j <= 4u; j++) {
        let extent = i32(WG_SIZE) >> (j - 1u);
        let t = vec2<i32>(wg.xy) * extent + l;
        if all(l < vec2<i32>(extent)) && all(t < level_size(j)) {
            let w = from_children(j, t, vec2<i32>(wg.xy) * (2 * extent), 2 * extent);
            store(j, t, w);
            let i = u32(l.y * extent + l.x);
            if j == 2u {
                tile2[i] = w;
            } else if j == 3u {
                tile3[i] = w;
            }
        }
        workgroupBarrier();
    }
}
