// The second depth layer bound as a depth texture, like depth_input_depth.wgsl.
@group(0) @binding(5) var second_in: texture_depth_2d;

fn load_raw_second(p: vec2<i32>) -> f32 {
    return textureLoad(second_in, p, 0);
}
