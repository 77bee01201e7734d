// Depth input bound as a float colour texture (R32Float / R16Float, e.g. linear view depth).
@group(0) @binding(1) var depth_in: texture_2d<f32>;

fn load_raw_depth(p: vec2<i32>) -> f32 {
    return textureLoad(depth_in, p, 0).x;
}
