// The merge's taps (lights_merge.wgsl) from two textures: geometry from the prepared source
// (prepared_full.wgsl or prepared_layers.wgsl, composed before), irradiance from lit_in
// (LIT_FORMAT). The SSDO bounce is merged so.

@group(0) @binding(2) var lit_in: texture_2d<f32>;

fn merge_tap(q: vec2<i32>) -> MergeTap {
    return MergeTap(prepared_at(q), textureLoad(lit_in, q, 0).xyz);
}
