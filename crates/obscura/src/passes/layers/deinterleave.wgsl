// Split pass (unfused mode): full-resolution prepared buffer -> SPLIT x SPLIT layers.
// Composed with prepare_store_layers.wgsl (binding 3, `store_prepared`).

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var prepared_in: texture_2d<f32>;

// Dispatched over layer texels (x, y, layer), like the fused split.
@compute @workgroup_size(WG_SIZE, WG_SIZE, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let pixel = pixel_of(gid);
    if any(pixel >= frame.size) {
        return;
    }
    store_prepared(gid, textureLoad(prepared_in, pixel, 0));
}
