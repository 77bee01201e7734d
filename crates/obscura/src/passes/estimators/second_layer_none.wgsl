// The AO pass without a second depth layer (second_layer.wgsl's interface): one layer.

// Depth layers a sample reads.
const DEPTH_LAYERS: u32 = 1u;

fn sample_second(q: vec2<i32>) -> f32 {
    return 0.0;
}
