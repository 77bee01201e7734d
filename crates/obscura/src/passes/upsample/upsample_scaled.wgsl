// Upsampling the AO of the working grid of Resolution::Scaled (any scale s in [1/4, 1]) to
// full resolution: full-resolution pixel p reads the 2x2 working texels around
// u = (p + 0.5) s - 0.5 (working texel q has its centre at full-resolution (q + 0.5) / s,
// the mapping of FrameUniforms::at_scale and rescale.wgsl) with bilinear weights, and the
// weight fragment composed after it (upsample_bilateral.wgsl: Yang et al. 2008's joint
// bilateral weights) turns them geometry-aware. One invocation per full-resolution pixel:
// at a scale that is not a power of two, blocks of pixels no longer share footprints.
// At s = 1 every pixel reads its own texel with weight 1: the identity. Sky pixels get 1.
// Bound with the full-resolution frame. CPU mirror: src/reference.rs, `upsample_scaled`.

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var full_in: texture_2d<f32>;
@group(0) @binding(2) var ao_low: texture_2d<f32>;
@group(0) @binding(3) var prepared_low: texture_2d<f32>;
@group(0) @binding(4) var ao_out: texture_storage_2d<r32float, write>;

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if any(gid.xy >= frame.size) {
        return;
    }
    let pi = vec2<i32>(gid.xy);
    let centre = textureLoad(full_in, pi, 0);
    var ao = 1.0;
    var wts = vec4<f32>(0.0);
    var fp: Footprint;
    if centre.x > 0.0 {
        let u = (vec2<f32>(gid.xy) + 0.5) * frame.scale - 0.5;
        let base = vec2<i32>(floor(u));
        let t = u - floor(u);
        fp.w = vec4<f32>((1.0 - t.x) * (1.0 - t.y), t.x * (1.0 - t.y), (1.0 - t.x) * t.y, t.x * t.y);
        let last = vec2<i32>(frame.work_size) - 1;
        for (var i = 0u; i < 4u; i++) {
            let q = clamp(base + vec2<i32>(i32(i & 1u), i32(i >> 1u)), vec2<i32>(0), last);
            fp.texel[i] = q;
            fp.low[i] = textureLoad(prepared_low, q, 0);
            fp.ao[i] = textureLoad(ao_low, q, 0).x;
            fp.pos[i] = view_position((vec2<f32>(q) + 0.5) * frame.inv_scale, fp.low[i].x);
        }
        wts = upsample_weights(view_position(vec2<f32>(gid.xy) + 0.5, centre.x), centre, fp);
        // The weights sum to 1 up to rounding, which must not leave [0, 1].
        ao = clamp(dot(wts, fp.ao), 0.0, 1.0);
    }
    store_output(pi, ao);
    upsample_bent(pi, wts, centre, fp);
}
