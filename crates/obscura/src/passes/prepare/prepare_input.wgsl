// Inputs of the prepare passes (prepare.wgsl, prepare_down.wgsl): the frame, the caller's
// optional normal texture, and linear depth of a viewport pixel. Composed after a
// depth_input_*.wgsl (`load_raw_depth`) and before a normals_*.wgsl (`view_normal`).

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(2) var normals_in: texture_2d<f32>;

// Linear depth of viewport-local pixel `p`; 0 outside the viewport.
fn linear_depth_at(p: vec2<i32>) -> f32 {
    if any(p < vec2<i32>(0)) || any(p >= vec2<i32>(frame.size)) {
        return 0.0;
    }
    return linearize_depth(load_raw_depth(p + vec2<i32>(frame.viewport_origin)));
}
