// Prepared source of the passes after the AO (denoise, temporal): the prepared buffer
// vec4(linear depth, view normal) of the working grid, read directly.
@group(0) @binding(1) var prepared_in: texture_2d<f32>;

fn prepared_at(q: vec2<i32>) -> vec4<f32> {
    return textureLoad(prepared_in, q, 0);
}
