// MSAA depth resolve: the first pass when the depth input is multisampled. One depth per
// pixel of the viewport, written at its texel of the depth texture so the prepare pass
// reads it as it would a single-sampled float depth input.
//
// When every sample sees the same surface (linear depths within PLANE_TOLERANCE of the
// nearest), their mean raw depth: raw depth is affine in screen space across a plane, for
// perspective and orthographic projections alike, and the standard sample patterns
// (Vulkan, D3D, Metal) are centred on the pixel, so the mean is the depth at the pixel
// centre, what a single-sampled buffer holds. Otherwise (a silhouette) the nearest
// sample: the foreground keeps its outline, so thin objects still occlude. Sky samples
// count only when every sample is sky. CPU mirror: src/reference.rs, `resolve_msaa_depth`.

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var depth_in: texture_depth_multisampled_2d;
@group(0) @binding(2) var resolved: texture_storage_2d<r32float, write>;

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if any(gid.xy >= frame.size) {
        return;
    }
    let q = vec2<i32>(gid.xy + frame.viewport_origin);
    let n = i32(textureNumSamples(depth_in));
    var nearest_raw = textureLoad(depth_in, q, 0);
    // Linear depths of the nearest and farthest non-sky samples (0: none yet).
    var nearest = 0.0;
    var farthest = 0.0;
    var sky = false;
    var sum = 0.0;
    for (var s = 0; s < n; s++) {
        let raw = textureLoad(depth_in, q, s);
        let d = linearize_depth(raw);
        sum += raw;
        if d <= 0.0 {
            sky = true;
        } else {
            if nearest == 0.0 || d < nearest {
                nearest = d;
                nearest_raw = raw;
            }
            farthest = max(farthest, d);
        }
    }
    var out = nearest_raw;
    if !sky && farthest - nearest <= PLANE_TOLERANCE * nearest {
        out = sum / f32(n);
    }
    textureStore(resolved, q, vec4<f32>(out, 0.0, 0.0, 0.0));
}
