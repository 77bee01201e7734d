// One level of the depth moments pyramid for Volumetric Obscurance's area integral (Loos &
// Sloan 2010; seed 002: "a mip-map of depth average and variance"). Texel t of level L+1
// covers the texels of level L that pyramid.wgsl's does (2t .. 2t+1, and the orphan
// column/row of an odd-sized level) and stores vec4(valid fraction, mean, variance, 0) of
// the linear depths under it, sky (0) excluded from mean and variance, which are 0 where
// all is sky. Children count equally, so an orphan row or column at the image's far border
// weighs as much as a full one. Children merge by the pairwise update of the mean and of
// the sum of squared deviations (Chan, Golub & LeVeque 1979), which keeps the variance of a
// surface far from the camera exact where E[z^2] - E[z]^2 would cancel.
// Composed with a pyramid_from_*.wgsl (@binding(1), `source_texel`, `source_size`): linear
// depths when FROM_DEPTH, else the level above. CPU mirror: src/reference.rs, `moments`.

override FROM_DEPTH: bool = true;

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(2) var moments_out: texture_storage_2d<rgba32float, write>;

// A child's (valid fraction, mean, variance).
fn child(p: vec2<i32>) -> vec3<f32> {
    let s = source_texel(p);
    if FROM_DEPTH {
        return select(vec3<f32>(0.0), vec3<f32>(1.0, s.x, 0.0), s.x > 0.0);
    }
    return s;
}

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let dst = vec2<i32>(textureDimensions(moments_out));
    let t = vec2<i32>(gid.xy);
    if any(t >= dst) {
        return;
    }
    let src = source_size();
    let lo = 2 * t;
    let hi = min(select(lo + 1, src - 1, t == dst - 1), src - 1);
    var count = 0.0;
    var weight = 0.0;
    var mean = 0.0;
    var deviations = 0.0;
    for (var y = lo.y; y <= hi.y; y++) {
        for (var x = lo.x; x <= hi.x; x++) {
            let c = child(vec2<i32>(x, y));
            count += 1.0;
            if c.x > 0.0 {
                let merged = weight + c.x;
                let delta = c.y - mean;
                mean += delta * c.x / merged;
                deviations += c.z * c.x + delta * delta * weight * c.x / merged;
                weight = merged;
            }
        }
    }
    let variance = select(0.0, deviations / weight, weight > 0.0);
    textureStore(moments_out, t, vec4<f32>(weight / count, mean, variance, 0.0));
}
