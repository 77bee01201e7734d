// The prepare pass's second depth layer (AoOptions::second_layer): the caller's
// second layer, linearised like the first (common.wgsl, `linearize_depth`; sky and
// missing depth are 0), stored at full resolution over the processed rectangle for the AO
// pass (estimators/second_layer.wgsl). Composed after a second_input_*.wgsl
// (`load_raw_second`, the first layer's binding kind); the empty interface is
// prepare_second_none.wgsl.
@group(0) @binding(6) var second_out: texture_storage_2d<r32float, write>;

fn store_second(pixel: vec2<u32>) {
    let raw = load_raw_second(vec2<i32>(pixel) + vec2<i32>(frame.viewport_origin));
    textureStore(second_out, pixel, vec4<f32>(linearize_depth(raw), 0.0, 0.0, 0.0));
}
