// The second depth layer bound as a float colour texture, like depth_input_float.wgsl.
@group(0) @binding(5) var second_in: texture_2d<f32>;

fn load_raw_second(p: vec2<i32>) -> f32 {
    return textureLoad(second_in, p, 0).x;
}
