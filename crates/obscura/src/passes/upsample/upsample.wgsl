// Upsampling low-resolution AO to full resolution (seeds 002 and 004). Full-resolution pixel
// p reads the 2x2 low-resolution texels around it (the bilinear footprint): low texel x has
// its centre at full-resolution x * F + F / 2 (F = UP_FACTOR), the mapping the AO pass used
// (FrameUniforms::at_factor), so odd sizes neither shift nor crop. Composed with an
// upsample_*.wgsl defining `upsample_weights(pos, centre, fp)`, the weights of the four
// footprint texels (summing to 1; centre: this pixel's full-resolution input, .x linear
// depth and, for the bilateral upsampler, .yzw its normal), and an upsample_bent*.wgsl that
// takes bent normals through with the same weights. Sky pixels get 1.
// - One invocation per low texel t writes its F x F full-resolution pixels: their
//   footprints all lie in the 3 x 3 texels around t, each read once (2.25 texel reads per
//   pixel at half resolution instead of 4; 0.56 at quarter).
// - The full-resolution input: the prepared buffer, or what prepare_down.wgsl wrote (linear
//   depth only, unless the upsampler is the bilateral one, whose normal weight needs the
//   pixel's normal). The plane tests of the classified upsampler use the low-resolution
//   texels' own tangent planes, so it needs no full-resolution normal.

override UP_FACTOR: u32 = 2u;

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var full_in: texture_2d<f32>;
@group(0) @binding(2) var ao_low: texture_2d<f32>;
@group(0) @binding(3) var prepared_low: texture_2d<f32>;
@group(0) @binding(4) var ao_out: texture_storage_2d<r32float, write>;

// One low-resolution texel: coordinates (clamped to the texture), AO, prepared vec4(d, n)
// and the view position of its centre.
struct Texel {
    q: vec2<i32>,
    ao: f32,
    low: vec4<f32>,
    pos: vec3<f32>,
}

fn texel(t: vec2<i32>, dx: i32, dy: i32) -> Texel {
    let q = clamp(t + vec2<i32>(dx, dy), vec2<i32>(0), vec2<i32>(textureDimensions(ao_low)) - 1);
    let low = textureLoad(prepared_low, q, 0);
    let pos = view_position((vec2<f32>(q) + 0.5) * f32(UP_FACTOR), low.x);
    return Texel(q, textureLoad(ao_low, q, 0).x, low, pos);
}

// The pixels of quadrant c (0 or 1 per axis) of low texel t's block share one footprint,
// texels (a, b, e, f) in the order (0,0), (1,0), (0,1), (1,1); only the weights differ:
// for pixel p, u = (p + 0.5) / F - 0.5 and the weights are its fractional part.
fn quadrant(t: vec2<i32>, c: vec2<u32>, a: Texel, b: Texel, e: Texel, f: Texel) {
    let half = UP_FACTOR / 2u;
    var fp: Footprint;
    fp.ao = vec4<f32>(a.ao, b.ao, e.ao, f.ao);
    fp.low = array<vec4<f32>, 4>(a.low, b.low, e.low, f.low);
    fp.pos = array<vec3<f32>, 4>(a.pos, b.pos, e.pos, f.pos);
    fp.texel = array<vec2<i32>, 4>(a.q, b.q, e.q, f.q);
    for (var oy = 0u; oy < half; oy++) {
        for (var ox = 0u; ox < half; ox++) {
            let o = c * half + vec2<u32>(ox, oy);
            let p = vec2<u32>(t) * UP_FACTOR + o;
            if any(p >= frame.size) {
                continue;
            }
            let u = (vec2<f32>(o) + 0.5) / f32(UP_FACTOR) - 0.5;
            let w = u - floor(u);
            fp.w = vec4<f32>((1.0 - w.x) * (1.0 - w.y), w.x * (1.0 - w.y), (1.0 - w.x) * w.y, w.x * w.y);
            let pi = vec2<i32>(p);
            let centre = textureLoad(full_in, pi, 0);
            var ao = 1.0;
            var wts = vec4<f32>(0.0);
            if centre.x > 0.0 {
                wts = upsample_weights(view_position(vec2<f32>(pi) + 0.5, centre.x), centre, fp);
                // The weights sum to 1 up to rounding, which must not leave [0, 1].
                ao = clamp(dot(wts, fp.ao), 0.0, 1.0);
            }
            store_output(pi, ao);
            upsample_bent(pi, wts, centre, fp);
        }
    }
}

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let t = vec2<i32>(gid.xy);
    if any(t >= vec2<i32>(textureDimensions(ao_low))) {
        return;
    }
    // The 3 x 3 texels around t, each read once; UP_FACTOR >= 2, so the block has four
    // quadrants, whose footprints' top-left texels are t + (-1 or 0, -1 or 0).
    let n00 = texel(t, -1, -1);
    let n10 = texel(t, 0, -1);
    let n20 = texel(t, 1, -1);
    let n01 = texel(t, -1, 0);
    let n11 = texel(t, 0, 0);
    let n21 = texel(t, 1, 0);
    let n02 = texel(t, -1, 1);
    let n12 = texel(t, 0, 1);
    let n22 = texel(t, 1, 1);
    quadrant(t, vec2<u32>(0u, 0u), n00, n10, n01, n11);
    quadrant(t, vec2<u32>(1u, 0u), n10, n20, n11, n21);
    quadrant(t, vec2<u32>(0u, 1u), n01, n11, n02, n12);
    quadrant(t, vec2<u32>(1u, 1u), n11, n21, n12, n22);
}
