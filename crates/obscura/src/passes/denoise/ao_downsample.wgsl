// AO downsample filters of seed 003, 2x (dst = ceil(src / 2)). The tap offsets and weights
// are compile-time constants (TENT_SPACING, TENT_WEIGHTS from Rust; the 9-tap loop unrolls),
// not computed per pixel (the seed moves them from the pixel to the vertex shader for the
// same reason). CPU mirror: src/reference.rs, `ao_downsample`.
// - box (TENT = false): the mean of the 4 children 2t + (0..1, 0..1);
// - tent (TENT = true): 9 taps at offsets (-2, 0, 2) around the corner 2t + 1 shared by the
//   children, each tap the mean of the 2x2 texels around its point, weights 1-2-1 x 1-2-1 /
//   16: a 6x6 tent footprint.
// Texels outside the source are left out and the weights renormalized.

override TENT: bool = false;

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var ao_in: texture_2d<f32>;
@group(0) @binding(2) var ao_out: texture_storage_2d<r32float, write>;

// Sum and count of the source texels in [lo, lo + 1]^2.
fn block(lo: vec2<i32>) -> vec2<f32> {
    let size = vec2<i32>(textureDimensions(ao_in));
    var acc = vec2<f32>(0.0);
    for (var i = 0; i < 4; i++) {
        let q = lo + vec2<i32>(i & 1, i >> 1u);
        if all(q >= vec2<i32>(0)) && all(q < size) {
            acc += vec2<f32>(textureLoad(ao_in, q, 0).x, 1.0);
        }
    }
    return acc;
}

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let t = vec2<i32>(gid.xy);
    if any(t >= vec2<i32>(textureDimensions(ao_out))) {
        return;
    }
    var ao = 0.0;
    if TENT {
        var sum = 0.0;
        var total = 0.0;
        for (var i = 0; i < 9; i++) {
            let tap = vec2<i32>(i % 3, i / 3);
            let b = block(2 * t + (tap - 1) * TENT_SPACING);
            let w = TENT_WEIGHTS[tap.x] * TENT_WEIGHTS[tap.y];
            if b.y > 0.0 {
                sum += w * b.x / b.y;
                total += w;
            }
        }
        ao = sum / total;
    } else {
        let b = block(2 * t);
        ao = b.x / b.y;
    }
    textureStore(ao_out, t, vec4<f32>(ao, 0.0, 0.0, 0.0));
}
