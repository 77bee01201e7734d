// Pyramid source: level 0 read from the SPLIT x SPLIT deinterleaved prepared layers.
override SPLIT: u32 = 2u;

@group(0) @binding(1) var pyramid_in: texture_2d_array<f32>;

fn source_size() -> vec2<i32> {
    return vec2<i32>(frame.size);
}

fn source_texel(p: vec2<i32>) -> vec3<f32> {
    let q = vec2<u32>(p);
    return vec3<f32>(textureLoad(pyramid_in, q / SPLIT, layer_of(q, SPLIT), 0).x);
}
