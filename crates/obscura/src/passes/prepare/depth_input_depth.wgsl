// Depth input bound as a depth texture (Depth32Float, Depth24Plus, Depth16Unorm, ...).
@group(0) @binding(1) var depth_in: texture_depth_2d;

fn load_raw_depth(p: vec2<i32>) -> f32 {
    return textureLoad(depth_in, p, 0);
}
