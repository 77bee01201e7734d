// Deinterleaved AO (seed 000): invocation (x, y, l) handles texel (x, y) of layer l, i.e.
// full-resolution pixel (x*SPLIT + l % SPLIT, y*SPLIT + l / SPLIT). A workgroup stays in one
// layer, so it shares one pattern (no per-pixel randomization), and samples are snapped
// to the SPLIT-pixel lattice so they stay in the same layer, where neighbouring invocations
// fetch neighbouring texels. Composed with an estimator, an ao_store_*.wgsl and an
// ao_bent*.wgsl.

override SPLIT: u32 = 4u;
// 1: skip the guard band beyond GUARD_AO_MARGIN (common.wgsl, `beyond_output`), writing 1.
override SKIP_BAND: u32 = 1u;

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var prepared_in: texture_2d_array<f32>;

var<private> layer: u32;

fn snap_offset(v: vec2<f32>) -> vec2<i32> {
    return vec2<i32>(round(v / f32(SPLIT))) * i32(SPLIT);
}

// The sampling lattice's cell, pixels.
fn lattice_cell() -> f32 {
    return f32(SPLIT);
}

// `q` is always in this invocation's layer (offsets are multiples of SPLIT), q >= 0.
fn sample_depth(q: vec2<i32>) -> f32 {
    return textureLoad(prepared_in, vec2<u32>(q) / SPLIT, layer, 0).x;
}

@compute @workgroup_size(WG_SIZE, WG_SIZE, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    layer = gid.z;
    let corner = vec2<u32>(layer % SPLIT, layer / SPLIT);
    let full = gid.xy * SPLIT + corner;
    if any(full >= frame.size) {
        return;
    }
    if SKIP_BAND != 0u && beyond_output(full) {
        store_ao(full, gid.xy, layer, 1.0);
        store_bent(full);
        return;
    }
    let pattern = frame.patterns[corner.x + PATTERN_DIM * corner.y];
    let centre = textureLoad(prepared_in, gid.xy, layer, 0);
    store_ao(full, gid.xy, layer, estimate(vec2<i32>(full), centre, pattern));
    store_bent(full);
}
