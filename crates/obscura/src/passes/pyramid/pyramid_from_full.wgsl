// Pyramid source: full-resolution linear depth, .x of the prepared buffer or the linear
// depth of prepare_down.wgsl (level 0 of the pyramid).
@group(0) @binding(1) var pyramid_in: texture_2d<f32>;

fn source_size() -> vec2<i32> {
    return vec2<i32>(frame.size);
}

fn source_texel(p: vec2<i32>) -> vec3<f32> {
    return vec3<f32>(textureLoad(pyramid_in, p, 0).x);
}
