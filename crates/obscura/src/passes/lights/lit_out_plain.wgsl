// Output of the many-light passes as irradiance, vec4(rgb, 1) (LIT_FORMAT).
// With CROPS (the last pass of Lights: the shading at period 1, else the merge along y)
// the pass runs over the processed rectangle, the viewport grown by a guard band
// (crate::AoInput::guard_band), and stores only the viewport's pixels, moved to the
// output's origin, as output.wgsl does for the AO. Without a band the crop keeps every
// pixel where it is.

@group(0) @binding(4) var lit_out: texture_storage_2d<rgba32float, write>;

override CROPS: bool = false;

// Stores irradiance `e` of pixel `p` (geometry `g` is not kept).
fn store_lit(p: vec2<i32>, g: vec4<f32>, e: vec3<f32>) {
    var q = p;
    if CROPS {
        q = p - vec2<i32>(frame.output_offset);
        if any(q < vec2<i32>(0)) || any(q >= vec2<i32>(frame.output_size)) {
            return;
        }
    }
    textureStore(lit_out, q, vec4<f32>(e, 1.0));
}
