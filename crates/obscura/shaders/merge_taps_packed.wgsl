// The merge's taps (lights_merge.wgsl) from one packed texture (lit_packed.wgsl,
// LIT_PACKED_FORMAT): geometry and irradiance in one fetch.

@group(0) @binding(2) var lit_in: texture_2d<u32>;

fn merge_tap(q: vec2<i32>) -> MergeTap {
    let t = textureLoad(lit_in, q, 0);
    return MergeTap(unpack_geometry(t), unpack_irradiance(t));
}
