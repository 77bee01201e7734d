// Bent normals beside the AO (AoOptions::bent_normals): the AO pass writes the estimator's
// `bent_normal` (view space, unit; zero on sky) at the full-resolution position of the
// working grid, whatever the layout (the unfused deinterleaved pass too: bent normals skip
// the interleave pass). Composed after an estimator that sets `bent_normal` (gtao.wgsl with
// BENT_NORMALS) and before ao_full.wgsl or ao_layered.wgsl.

@group(0) @binding(4) var bent_out: texture_storage_2d<rgba32float, write>;

var<private> bent_normal: vec3<f32>;

fn store_bent(full: vec2<u32>) {
    textureStore(bent_out, full, vec4<f32>(bent_normal, 0.0));
}
