// One level of the depth pyramid (seed 002, "min/max depth hierarchies"; SAO's depth mips,
// McGuire et al. 2012). Texel t of level L+1 covers texels 2t .. 2t+1 of level L, and the
// last texel of an odd-sized level also covers the orphan column/row 2t+2, so every texel
// of level L is covered exactly once and `clamp(p >> L, size - 1)` finds the texel whose
// footprint holds full-resolution pixel p (sizes are wgpu's mip sizes, max(1, size >> 1)).
// Output vec4(select, min, max, 0):
// - select: SAO's rotated-grid pick, child 2t + ((t.y & 1) ^ 1, (t.x & 1) ^ 1): a real depth
//   (never an average), spread over the 2x2 block from texel to texel;
// - min, max: over the footprint's valid (non-sky) depths; 0 when all of it is sky.
// Composed with a pyramid_from_*.wgsl (@binding(1) and `source_texel`, `source_size`).
// CPU mirror: src/reference.rs, `pyramid`.

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(2) var pyramid_out: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let dst = vec2<i32>(textureDimensions(pyramid_out));
    let t = vec2<i32>(gid.xy);
    if any(t >= dst) {
        return;
    }
    let src = source_size();
    let lo = 2 * t;
    let hi = min(select(lo + 1, src - 1, t == dst - 1), src - 1);
    let pick = min(lo + vec2<i32>((t.y & 1) ^ 1, (t.x & 1) ^ 1), src - 1);
    var mn = 3.4e38;
    var mx = 0.0;
    for (var y = lo.y; y <= hi.y; y++) {
        for (var x = lo.x; x <= hi.x; x++) {
            let s = source_texel(vec2<i32>(x, y));
            if s.z > 0.0 {
                mn = min(mn, s.y);
                mx = max(mx, s.z);
            }
        }
    }
    if mx <= 0.0 {
        mn = 0.0;
    }
    textureStore(pyramid_out, t, vec4<f32>(source_texel(pick).x, mn, mx, 0.0));
}
