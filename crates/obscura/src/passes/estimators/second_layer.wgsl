// The AO pass's second depth layer (AoOptions::second_layer): linear depth of
// the surface behind pixel q's first, 0 where there is none, written by the prepare pass
// (prepare/prepare_second.wgsl) at full resolution over the processed rectangle. `q` is a
// full-resolution pixel in every layout (the layered passes' samples are pixels too).
// Read by bitmask.wgsl; the empty interface is second_layer_none.wgsl.

// Depth layers a sample reads.
const DEPTH_LAYERS: u32 = 2u;

@group(0) @binding(5) var second_in: texture_2d<f32>;

fn sample_second(q: vec2<i32>) -> f32 {
    return textureLoad(second_in, q, 0).x;
}
