// The randomized single pass: every full-resolution pixel runs the estimator with the
// pattern of its position in the 4x4 tile, sampling at rounded pixel offsets. Composed
// with an estimator (hbao.wgsl or gtao.wgsl: `estimate`), an ao_store_*.wgsl and an
// ao_bent*.wgsl.

// 1: skip the guard band beyond GUARD_AO_MARGIN (common.wgsl, `beyond_output`), writing 1.
override SKIP_BAND: u32 = 1u;

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var prepared_in: texture_2d<f32>;

fn snap_offset(v: vec2<f32>) -> vec2<i32> {
    return vec2<i32>(round(v));
}

// The sampling lattice's cell, pixels.
fn lattice_cell() -> f32 {
    return 1.0;
}

fn sample_depth(q: vec2<i32>) -> f32 {
    return textureLoad(prepared_in, q, 0).x;
}

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if any(gid.xy >= frame.size) {
        return;
    }
    let p = vec2<i32>(gid.xy);
    let centre = textureLoad(prepared_in, p, 0);
    if SKIP_BAND != 0u && beyond_output(gid.xy) {
        store_ao(gid.xy, gid.xy, 0u, 1.0, centre);
        store_bent(gid.xy);
        return;
    }
    let pattern = frame.patterns[(gid.x % PATTERN_DIM) + PATTERN_DIM * (gid.y % PATTERN_DIM)];
    store_ao(gid.xy, gid.xy, 0u, estimate(p, centre, pattern), centre);
    store_bent(gid.xy);
}
