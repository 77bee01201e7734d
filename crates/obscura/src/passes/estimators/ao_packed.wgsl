// The AO packed beside its pixel's geometry for the spatial denoiser (AO_PACKED_FORMAT):
// vec4(linear depth, normal x, normal y, ±(1 + AO)), the sign the normal's z's, whose
// magnitude follows from the unit length. A tap of the denoiser is then one fetch where
// it was two (the prepared value and the AO), and a fetch costs as much as some forty
// operations on a CPU adapter (BENCHMARKS.md). Written by ao_store_packed.wgsl and
// temporal/temporal_out_packed.wgsl, read by denoise/denoise.wgsl; a storage layout only,
// so the CPU mirror of the denoiser (src/reference.rs, `denoise`) reads the prepared values
// and the AO as they are.

fn pack_ao(prepared: vec4<f32>, ao: f32) -> vec4<f32> {
    return vec4<f32>(prepared.xyz, select(1.0 + ao, -1.0 - ao, prepared.w < 0.0));
}

// The prepared value vec4(depth, normal) of a packed texel; its AO is abs(t.w) - 1.
fn unpack_prepared(t: vec4<f32>) -> vec4<f32> {
    let nz = sqrt(max(1.0 - t.y * t.y - t.z * t.z, 0.0));
    return vec4<f32>(t.xyz, select(nz, -nz, t.w < 0.0));
}
