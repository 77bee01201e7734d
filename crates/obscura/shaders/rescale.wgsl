// The prepared buffer at any working scale s in [1/4, 1] (Resolution::Scaled; seed 002:
// Yang, Sander & Lawrence's geometry-aware framebuffer level of detail, whose resolution
// changes every frame). Working texel q stands for the full-resolution footprint centred at
// c = (q + 0.5) / s; it takes the prepared value of the full-resolution pixel nearest that
// centre (a real depth and normal of one surface, never an average, as the depth rules of
// seed 004), moved along its own tangent plane to the ray through c (RECENTRE) so positions
// rebuilt at texel centres lie on the surface. At s = 1 it is the identity. Bound with the
// working frame (FrameUniforms::at_scale). CPU mirror: src/reference.rs, `rescale`.

override RECENTRE: bool = true;

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var full_in: texture_2d<f32>;
@group(0) @binding(2) var work_out: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if any(gid.xy >= frame.size) {
        return;
    }
    let q = vec2<f32>(gid.xy) + 0.5;
    let c = q * frame.inv_scale;
    let p = min(vec2<u32>(c), frame.full_size - 1u);
    let v = textureLoad(full_in, p, 0);
    var out = v;
    if RECENTRE && v.x > 0.0 {
        // This grid's pixel coordinates: full-resolution x maps to x * scale.
        out = recentred_to((vec2<f32>(p) + 0.5) * frame.scale, q, v);
    }
    textureStore(work_out, gid.xy, out);
}
