// The merge of interleaved many-light shading (lights_shade.wgsl), one axis per pass
// (AXIS 0: x, then AXIS 1: y). Pixel class k of the n × n tile shaded lights k, k + n², …
// times n², so each class is a lattice of pixels n apart (a deinterleaved layer, seed
// 000) holding an estimate of the whole sum. Along the axis, the merge interpolates every
// class's lattice at this pixel linearly from its two nearest lattice pixels around it,
// each tap also weighted by geometry (merge.wgsl), and averages the classes; the second
// pass does the same across rows to the first pass's output. Together: each layer
// upsampled bilinearly and geometry-aware (joint bilateral upsampling, Kopf et al. 2007;
// seed 002's geometry-aware upsampling), then the layers averaged (Segovia et al. 2006's
// merge of interleaved sample patterns, made edge-aware per class), in 2 × (2n − 1) taps
// instead of (2n − 1)² (separable, as joint bilateral filters are commonly split; exact
// where the geometric weights are 1). A class none of whose taps lies on this surface (weights below
// LIGHTS_CLASS_MIN_WEIGHT: a feature thinner than the tile) is left out and the others
// averaged, so no class is filled from another surface, as a plain n × n box does at
// every edge; the centre's own class always counts. Irradiance linear across a surface
// comes back exactly, since each class is interpolated at the centre rather than read
// beside it. Taps past the image border are dropped (each class keeps one on the inner
// side where the image spans at least a period). Sky pixels pass through.
// Taps are packed texels (lit_packed.wgsl): geometry and irradiance in one fetch.
// Composed after lit_packed.wgsl, an output (lit_out_packed.wgsl between the axes, else
// lit_out_plain.wgsl) and merge.wgsl. CPU mirror: src/reference.rs, `merge_lights_packed`.

override PERIOD: u32 = 2u;
override AXIS: u32 = 0u;

@group(0) @binding(0) var<uniform> frame: FrameUniforms;

@group(0) @binding(2) var lit_in: texture_2d<u32>;

// What the merge reads of a pixel: vec4(linear depth, view normal) and irradiance.
struct MergeTap {
    geometry: vec4<f32>,
    lit: vec3<f32>,
}

fn merge_tap(q: vec2<i32>) -> MergeTap {
    let t = textureLoad(lit_in, q, 0);
    return MergeTap(unpack_geometry(t), unpack_irradiance(t));
}

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if any(gid.xy >= frame.size) {
        return;
    }
    let p = vec2<i32>(gid.xy);
    let own = merge_tap(p);
    let centre = own.geometry;
    let pos = view_position(vec2<f32>(p) + 0.5, centre.x);
    let n = centre.yzw;
    let inv_tol = 1.0 / plane_tolerance(centre.x);
    let size = vec2<i32>(frame.size);
    let step = select(vec2<i32>(1, 0), vec2<i32>(0, 1), AXIS == 1u);
    let coordinate = dot(p, step);
    let extent = dot(size, step);
    // Sky passes through: its loop has no class to merge. (A bound of 1, not a branch
    // around the loop: lavapipe runs a branch's body for a whole SIMD batch when no lane
    // takes it, but ends a loop once no lane is left in it; on an all-sky frame the merge
    // cost 71 ms at 1280×720 with the branch, BENCHMARKS.md "Many-light shading".)
    let period = select(1, i32(PERIOD), centre.x > 0.0);
    // Class j of the axis (the pixels j before p modulo the period) has its lattice
    // pixels at −j and period − j, with linear weights period − j and j: for j = 0 that
    // is p alone (p's own class, always counted).
    var sum = own.lit;
    var classes = 1.0;
    for (var j = 1; j < period; j++) {
        var total = 0.0;
        var acc = vec3<f32>(0.0);
        for (var t = 0; t < 2; t++) {
            let d = select(-j, period - j, t == 1);
            if coordinate + d < 0 || coordinate + d >= extent {
                continue;
            }
            let q = p + d * step;
            // Sky, or not a depth at all (NaN), is no tap.
            let s = merge_tap(q);
            if !(s.geometry.x > 0.0) {
                continue;
            }
            let w = f32(period - abs(d)) * merge_weight(pos, n, inv_tol, q, s.geometry);
            total += w;
            acc += w * s.lit;
        }
        if total >= LIGHTS_CLASS_MIN_WEIGHT {
            sum += acc / total;
            classes += 1.0;
        }
    }
    store_lit(p, centre, sum / classes);
}
