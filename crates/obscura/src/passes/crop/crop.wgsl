// Crop (guard band): the AO of the processed rectangle (the viewport grown by the guard
// band, `frame.size`) → the output, the viewport, at `frame.output_offset` in it.

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var ao_in: texture_2d<f32>;
@group(0) @binding(2) var ao_out: texture_storage_2d<r32float, write>;

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if any(gid.xy >= frame.output_size) {
        return;
    }
    let ao = textureLoad(ao_in, gid.xy + frame.output_offset, 0).x;
    textureStore(ao_out, gid.xy, vec4<f32>(ao, 0.0, 0.0, 0.0));
}
