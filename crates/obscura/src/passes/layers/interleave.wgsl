// Merge pass (unfused mode): SPLIT x SPLIT AO layers -> full resolution.
// Composed with ao_store_full.wgsl (binding 2, `store_ao`).

override SPLIT: u32 = 4u;

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var ao_layers: texture_2d_array<f32>;

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if any(gid.xy >= frame.size) {
        return;
    }
    let layer = layer_of(gid.xy, SPLIT);
    let texel = gid.xy / SPLIT;
    store_ao(gid.xy, texel, layer, textureLoad(ao_layers, texel, layer, 0).x, vec4<f32>(0.0));
}
