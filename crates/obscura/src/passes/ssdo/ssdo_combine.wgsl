// The SSDO combine (src/ssdo.rs): radiance = albedo · (V · E(b) + bounce), with V the AO,
// b the bent normal (the surface normal without one) and E the environment's irradiance
// (ssdo_env.wgsl): the environment seen through the bent cone, the approximation engines
// pair with XeGTAO's bent normals, exact for a constant sky. Composed after a prepared
// source and ssdo_env.wgsl. Sky: 0. CPU mirror: src/reference.rs, `ssdo_combine`.

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(4) var ao_in: texture_2d<f32>;
@group(0) @binding(5) var bent_in: texture_2d<f32>;
@group(0) @binding(6) var bounce_in: texture_2d<f32>;
@group(0) @binding(7) var radiance_out: texture_storage_2d<rgba32float, write>;

// One invocation per output pixel `o`: with a guard band (crate::AoInput::guard_band) the
// inputs but the AO cover the processed rectangle, and `o` reads them at
// `p = o + frame.output_offset`; the AO and the radiance are the output's size.
@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if any(gid.xy >= frame.output_size) {
        return;
    }
    let o = vec2<i32>(gid.xy);
    let p = o + vec2<i32>(frame.output_offset);
    let centre = prepared_at(p);
    if !(centre.x > 0.0) {
        textureStore(radiance_out, o, vec4<f32>(0.0));
        return;
    }
    var dir = centre.yzw;
    if ssdo.flags.x != 0u {
        let b = textureLoad(bent_in, p, 0).xyz;
        if dot(b, b) > 1e-12 {
            dir = normalize(b);
        }
    }
    var e = textureLoad(ao_in, o, 0).x * env_irradiance(dir);
    if ssdo.flags.y != 0u {
        e += textureLoad(bounce_in, p, 0).xyz;
    }
    textureStore(radiance_out, o, vec4<f32>(albedo_at(p) * e, 1.0));
}
