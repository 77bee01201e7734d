// Upsampling low-resolution AO to full resolution (seeds 002 and 004). Full-resolution pixel
// p reads the 2x2 low-resolution texels around it (the bilinear footprint): low texel x has
// its centre at full-resolution x * F + F / 2 (F = frame.up_factor), the mapping the AO pass
// used (FrameUniforms::at_factor), so odd sizes neither shift nor crop. Composed with an
// upsample_*.wgsl defining `upsample(p, centre, fp)`. Sky pixels get 1.

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var prepared_in: texture_2d<f32>;
@group(0) @binding(2) var ao_low: texture_2d<f32>;
@group(0) @binding(3) var prepared_low: texture_2d<f32>;
@group(0) @binding(4) var ao_out: texture_storage_2d<r32float, write>;

struct Footprint {
    // Bilinear weights, AO, prepared vec4(d, n) and view position of the 4 texels
    // (order: (0,0), (1,0), (0,1), (1,1)) and their texel coordinates.
    w: vec4<f32>,
    ao: vec4<f32>,
    low: array<vec4<f32>, 4>,
    pos: array<vec3<f32>, 4>,
    texel: array<vec2<i32>, 4>,
}

fn footprint(p: vec2<i32>) -> Footprint {
    let f = f32(frame.up_factor);
    let size = vec2<i32>(textureDimensions(ao_low));
    let u = (vec2<f32>(p) + 0.5) / f - 0.5;
    let base = vec2<i32>(floor(u));
    let t = u - floor(u);
    var fp: Footprint;
    fp.w = vec4<f32>((1.0 - t.x) * (1.0 - t.y), t.x * (1.0 - t.y), (1.0 - t.x) * t.y, t.x * t.y);
    for (var i = 0u; i < 4u; i++) {
        let q = clamp(base + vec2<i32>(i32(i & 1u), i32(i >> 1u)), vec2<i32>(0), size - 1);
        fp.texel[i] = q;
        fp.ao[i] = textureLoad(ao_low, q, 0).x;
        fp.low[i] = textureLoad(prepared_low, q, 0);
        fp.pos[i] = view_position((vec2<f32>(q) + 0.5) * f, fp.low[i].x);
    }
    return fp;
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

// Distance of `q` from the plane through `c` with normal `n`, relative to the depth `d`.
fn plane_distance(q: vec3<f32>, c: vec3<f32>, n: vec3<f32>, d: f32) -> f32 {
    return abs(dot(q - c, n)) / d;
}

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if any(gid.xy >= frame.size) {
        return;
    }
    let p = vec2<i32>(gid.xy);
    let centre = textureLoad(prepared_in, p, 0);
    var ao = 1.0;
    if centre.x > 0.0 {
        ao = upsample(p, centre, footprint(p));
    }
    textureStore(ao_out, p, vec4<f32>(ao, 0.0, 0.0, 0.0));
}
