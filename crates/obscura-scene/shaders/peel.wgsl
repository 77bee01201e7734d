// Depth peeling for obscura's second depth layer (AoOptions::second_layer; Mara, McGuire,
// Nowrouzezahrai & Luebke 2016, "Deep G-Buffers", which peel with a minimum separation):
// composed after gbuffer.wgsl (its camera and vertex stage). A front face's fragment
// survives only at least `separation` (linear view depth) behind the first layer's depth
// at its pixel; the depth test then keeps the nearest survivor. Back faces are culled by
// the pipeline. Where the first layer is sky nothing survives.

struct Peel {
    // The first layer's linearisation (obscura's `Linearize` of reversed-Z, the G-buffer's):
    // d = 1 / (a z + b) when reciprocal != 0, else a z + b.
    a: f32,
    b: f32,
    reciprocal: u32,
    separation: f32,
}

@group(0) @binding(1) var first_depth: texture_depth_2d;
@group(0) @binding(2) var<uniform> peel: Peel;

@fragment
fn fs_peel(in: VsOut) {
    let z = textureLoad(first_depth, vec2<i32>(in.clip.xy), 0);
    // Reversed-Z: the sky is cleared to 0.
    if z <= 0.0 {
        discard;
    }
    var first = peel.a * z + peel.b;
    if peel.reciprocal != 0u {
        first = 1.0 / first;
    }
    if -in.view_pos.z < first + peel.separation {
        discard;
    }
}
