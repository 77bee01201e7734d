// Bent normals through the temporal pass (AoOptions::bent_normals with a history): the
// bent-normal history is read with the AO history's reprojection weights (the same texels
// kept, the same bilinear weights), turned from last frame's view space into this one's,
// and blended with this frame's bent normal by the AO's weight, then renormalised. It is not
// clamped to the neighbourhood: a direction has no min/max, and the texels that could ghost
// are the ones the depth and normal tests already reject. Composed before temporal.wgsl.

@group(0) @binding(6) var bent_in: texture_2d<f32>;
@group(0) @binding(7) var bent_history_in: texture_2d<f32>;
@group(0) @binding(8) var bent_history_out: texture_storage_2d<rgba32float, write>;
@group(0) @binding(9) var bent_out: texture_storage_2d<rgba32float, write>;

var<private> bent_sum: vec3<f32>;

fn bent_history_tap(t: vec2<i32>, w: f32) {
    bent_sum += w * textureLoad(bent_history_in, t, 0).xyz;
}

// `kept`: the AO history was used, `current_weight` its blend weight of this frame.
fn bent_finish(p: vec2<i32>, kept: bool, current_weight: f32) {
    var b = textureLoad(bent_in, p, 0).xyz;
    if kept && dot(bent_sum, bent_sum) > 1e-12 {
        // v * M = transpose(M) v: last frame's view space back to this frame's.
        let r = mat3x3<f32>(
            frame.prev_from_view[0].xyz,
            frame.prev_from_view[1].xyz,
            frame.prev_from_view[2].xyz,
        );
        let m = mix(normalize(bent_sum) * r, b, current_weight);
        if dot(m, m) > 1e-12 {
            b = normalize(m);
        }
    }
    textureStore(bent_history_out, p, vec4<f32>(b, 0.0));
    textureStore(bent_out, p, vec4<f32>(b, 0.0));
}
