// The temporal pass's AO alone, through output.wgsl's store (the frame's output, or the
// upsampler's input).
@group(0) @binding(5) var ao_out: texture_storage_2d<r32float, write>;

fn store_temporal(p: vec2<i32>, ao: f32, centre: vec4<f32>) {
    store_output(p, ao);
}
