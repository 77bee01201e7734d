// Pyramid source: the previous pyramid level (a one-mip view).
@group(0) @binding(1) var pyramid_in: texture_2d<f32>;

fn source_size() -> vec2<i32> {
    return vec2<i32>(textureDimensions(pyramid_in));
}

fn source_texel(p: vec2<i32>) -> vec3<f32> {
    return textureLoad(pyramid_in, p, 0).xyz;
}
