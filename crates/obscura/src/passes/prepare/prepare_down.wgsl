// Prepare fused with the first depth downsampling, for AO below full resolution: one
// invocation per half-resolution texel t linearizes its 2x2 full-resolution children
// (each one's `surface`, fitted depth included, where its normal is stored), stores what
// the passes after the AO read at full resolution (`store_child`, from a
// prepare_down_*.wgsl: linear depth only, or vec4(depth, normal) for the bilateral
// upsampler), picks one child by RULE (downsample_rule.wgsl) and stores it with its normal
// as texel t. The full-resolution pass and the downsample's read-back of its output
// disappear; texel t equals what prepare.wgsl + downsample.wgsl give (a test checks it bit
// for bit, with a noise model too for the bilateral upsampler; for the others the children
// keep the depth given, not the fitted one: fitting all four doubled the frame on noisy
// depth and measured neutral, docs/depth-noise.md). Composed like prepare.wgsl with a
// depth_input_*.wgsl, prepare_input.wgsl and a normals_*.wgsl.

@group(0) @binding(3) var level_out: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let t = vec2<i32>(gid.xy);
    if any(t >= vec2<i32>(textureDimensions(level_out))) {
        return;
    }
    let size = vec2<i32>(frame.size);
    var v: array<vec4<f32>, 4>;
    var depth: array<f32, 4>;
    var alive: array<bool, 4>;
    var count = 0u;
    for (var i = 0u; i < 4u; i++) {
        let c = 2 * t + child_offset(i);
        depth[i] = 0.0;
        if all(c < size) {
            let d = linear_depth_at(c);
            v[i] = vec4<f32>(select(0.0, d, d > 0.0), 0.0, 0.0, 1.0);
            if d > 0.0 && CHILD_NORMALS {
                v[i] = surface(c, d);
            }
            depth[i] = v[i].x;
            store_child(c, v[i]);
        }
        alive[i] = depth[i] > 0.0;
        count += u32(alive[i]);
    }
    if count == 0u {
        textureStore(level_out, t, vec4<f32>(0.0, 0.0, 0.0, 1.0));
        return;
    }
    let pick = pick_child(t, depth, alive, count);
    var picked = v[pick];
    if !CHILD_NORMALS {
        picked = surface(2 * t + child_offset(pick), depth[pick]);
    }
    textureStore(level_out, t, recentred(t, pick, picked));
}
