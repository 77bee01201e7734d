// Depth downsampling, 2x2 -> 1 (seed 004): low-resolution texel t is one of the prepared
// texels 2t + (0..1, 0..1) of the level above, chosen by RULE (downsample_rule.wgsl), with
// that texel's normal (the value is copied whole: depth and normal stay a real pair, never
// an average). Children outside the source (odd sizes: dst = ceil(src / 2)) and sky
// children are skipped.

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var src: texture_2d<f32>;
@group(0) @binding(2) var dst: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let t = vec2<i32>(gid.xy);
    if any(t >= vec2<i32>(textureDimensions(dst))) {
        return;
    }
    let size = vec2<i32>(textureDimensions(src));
    var v: array<vec4<f32>, 4>;
    var depth: array<f32, 4>;
    var alive: array<bool, 4>;
    var count = 0u;
    for (var i = 0u; i < 4u; i++) {
        let c = 2 * t + child_offset(i);
        alive[i] = false;
        depth[i] = 0.0;
        if all(c < size) {
            v[i] = textureLoad(src, c, 0);
            depth[i] = v[i].x;
            alive[i] = v[i].x > 0.0;
        }
        count += u32(alive[i]);
    }
    if count == 0u {
        textureStore(dst, t, vec4<f32>(0.0, 0.0, 0.0, 1.0));
        return;
    }
    let pick = pick_child(t, depth, alive, count);
    textureStore(dst, t, recentred(t, pick, v[pick]));
}
