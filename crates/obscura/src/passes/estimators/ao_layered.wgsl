// Deinterleaved AO (seed 000): invocation (x, y, l) handles texel (x, y) of layer l, i.e.
// full-resolution pixel (x*SPLIT + l % SPLIT, y*SPLIT + l / SPLIT). A workgroup stays in one
// layer, so its pixels share one pattern, turned a little per pixel (`pixel_pattern`).
// Samples beyond NEAR_FIELD_CELLS lattice cells are snapped to the SPLIT-pixel lattice so
// they stay in the same layer, where neighbouring invocations fetch neighbouring texels;
// nearer ones are taken at full resolution from the layer that holds them
// (constants.rs, NEAR_FIELD_CELLS). Composed with an estimator, an ao_store_*.wgsl and an
// ao_bent*.wgsl.

override SPLIT: u32 = 4u;
// The rotation sector of the patterns (jitter.rs, `rotation_sector`); 0: every pixel of a
// layer takes its layer's pattern as it is (no jitter).
override PATTERN_SECTOR: f32 = 0.0;
// 1: skip the guard band beyond GUARD_AO_MARGIN (common.wgsl, `beyond_output`), writing 1.
override SKIP_BAND: u32 = 1u;

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var prepared_in: texture_2d_array<f32>;

var<private> layer: u32;

// An offset in pixels as a whole-pixel offset: rounded to the pixel in the near field, to
// the layer's lattice beyond it.
fn snap_offset(v: vec2<f32>) -> vec2<i32> {
    let near = f32(NEAR_FIELD_CELLS * SPLIT);
    if dot(v, v) < near * near {
        return vec2<i32>(round(v));
    }
    return vec2<i32>(round(v / f32(SPLIT))) * i32(SPLIT);
}

// The first step's distance: one pixel, as at full resolution (the near field is).
fn lattice_cell() -> f32 {
    return 1.0;
}

// Depth of full-resolution pixel `q` (q >= 0), from the layer that holds it.
fn sample_depth(q: vec2<i32>) -> f32 {
    let u = vec2<u32>(q);
    return textureLoad(prepared_in, u / SPLIT, (u.x % SPLIT) + SPLIT * (u.y % SPLIT), 0).x;
}

// Interleaved gradient noise (constants.rs, IGN_WEIGHTS) at pixel `q` and at `q` shifted:
// two values in [0, 1) that differ widely between neighbours. `q` is the pixel of the AO's
// grid, so a guard band is the crop of the widened frame. CPU mirror: jitter.rs,
// `pixel_noise`.
fn pixel_noise(q: vec2<i32>) -> vec2<f32> {
    let a = vec2<f32>(q);
    let b = a + IGN_SHIFT;
    return vec2<f32>(
        fract(IGN_WEIGHTS.z * fract(IGN_WEIGHTS.x * a.x + IGN_WEIGHTS.y * a.y)),
        fract(IGN_WEIGHTS.z * fract(IGN_WEIGHTS.x * b.x + IGN_WEIGHTS.y * b.y)),
    );
}

// The layer's pattern turned within its stratum of the sector (1/SPLIT² of it) and its ray
// offset moved within its 1/SPLIT² of a step, per pixel: nearby directions in a layer
// without one set of directions over the whole layer, whose streaks the denoiser cannot
// remove. CPU mirror: jitter.rs, `pixel_pattern`.
fn pixel_pattern(base: vec4<f32>, q: vec2<i32>) -> vec4<f32> {
    if PATTERN_SECTOR == 0.0 {
        return base;
    }
    let u = pixel_noise(q);
    let share = 1.0 / f32(SPLIT * SPLIT);
    let half = 0.5 / f32(PATTERN_COUNT);
    let turn = (u.x * share - half) * PATTERN_SECTOR;
    let c = cos(turn);
    let s = sin(turn);
    let o = base.z + u.y * share - half;
    return vec4<f32>(base.x * c - base.y * s, base.y * c + base.x * s, o - floor(o), base.w);
}

@compute @workgroup_size(WG_SIZE, WG_SIZE, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    layer = gid.z;
    let corner = vec2<u32>(layer % SPLIT, layer / SPLIT);
    let full = gid.xy * SPLIT + corner;
    if any(full >= frame.size) {
        return;
    }
    let centre = textureLoad(prepared_in, gid.xy, layer, 0);
    if SKIP_BAND != 0u && beyond_output(full) {
        store_ao(full, gid.xy, layer, 1.0, centre);
        store_bent(full);
        return;
    }
    let pattern = pixel_pattern(frame.patterns[corner.x + PATTERN_DIM * corner.y], vec2<i32>(full));
    store_ao(full, gid.xy, layer, estimate(vec2<i32>(full), centre, pattern), centre);
    store_bent(full);
}
