// Bent normals through the upsampler (AoOptions::bent_normals below full resolution): with
// the AO's footprint weights, each low texel contributes its bent normal's offset from its
// own normal, added to this pixel's normal and renormalised (as in denoise_bent.wgsl: the
// tilt that occlusion gives is what is interpolated, so a pixel keeps its own orientation).
// Where the full-resolution input holds no normals (FULL_NORMALS false: the fused
// downsampling prepare wrote linear depth only, for upsamplers other than the bilateral
// one) the bent normals themselves are interpolated. Sky pixels get zero. Composed before
// upsample.wgsl.

override FULL_NORMALS: bool = true;

@group(0) @binding(6) var bent_low: texture_2d<f32>;
@group(0) @binding(7) var bent_out: texture_storage_2d<rgba32float, write>;

fn upsample_bent(p: vec2<i32>, w: vec4<f32>, centre: vec4<f32>, fp: Footprint) {
    var b = vec3<f32>(0.0);
    if centre.x > 0.0 {
        var sum = vec3<f32>(0.0);
        for (var i = 0u; i < 4u; i++) {
            var o = textureLoad(bent_low, fp.texel[i], 0).xyz;
            if FULL_NORMALS {
                o -= fp.low[i].yzw;
            }
            sum += w[i] * o;
        }
        if FULL_NORMALS {
            sum += centre.yzw;
        }
        if dot(sum, sum) > 1e-12 {
            b = normalize(sum);
        }
    }
    textureStore(bent_out, p, vec4<f32>(b, 0.0));
}
