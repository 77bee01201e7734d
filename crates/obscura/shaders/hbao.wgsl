// Horizon-based ambient occlusion (Bavoil, Sainz & Dimitrov, "Image-Space Horizon-Based
// Ambient Occlusion", SIGGRAPH 2008), in one full-resolution pass whose sampling pattern
// is jittered per pixel from a 4x4 table of rotations and ray offsets: the "before" of
// the deinterleaved-texturing paper (seed 000).
//
// For each of DIRECTIONS screen-space directions, march STEPS samples out to the radius.
// A sample's elevation above the tangent plane is sin(e) = dot(n, v)/|v|; whenever it
// raises the horizon, the direction's occlusion grows by (sin e - sin h) * W(r), with
// falloff W(r) = 1 - r^2/R^2. The horizon starts at the tangent bias angle. Samples
// farther than R, sky and off-screen samples do not occlude.
//
// Inputs: prepared vec4(d, n). Output: AO in [0, 1], 1 = unoccluded. CPU mirror:
// src/reference.rs, `hbao_pixel`.

override DIRECTIONS: u32 = 8u;
override STEPS: u32 = 4u;

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var prepared_in: texture_2d<f32>;
@group(0) @binding(2) var ao_out: texture_storage_2d<r32float, write>;

// The estimator: pixel `p`, its prepared value, and its pattern (cos, sin, offset, _).
fn hbao(p: vec2<i32>, centre: vec4<f32>, pattern: vec4<f32>) -> f32 {
    let d = centre.x;
    if d <= 0.0 {
        return 1.0;
    }
    let n = centre.yzw;
    let pos = view_position(vec2<f32>(p) + 0.5, d);
    var radius_px = frame.radius * frame.radius_to_px;
    if frame.perspective != 0u {
        radius_px = radius_px / d;
    }
    radius_px = min(radius_px, frame.max_radius_px);
    let step_px = radius_px / f32(STEPS + 1u);
    let size = vec2<i32>(frame.size);
    var occlusion = 0.0;
    for (var i = 0u; i < DIRECTIONS; i++) {
        let a = f32(i) * (TAU / f32(DIRECTIONS));
        let base = vec2<f32>(cos(a), sin(a));
        let dir = vec2<f32>(base.x * pattern.x - base.y * pattern.y, base.x * pattern.y + base.y * pattern.x);
        var ray = pattern.z * step_px + 1.0;
        var sin_h = frame.sin_bias;
        for (var s = 0u; s < STEPS; s++) {
            let q = p + vec2<i32>(round(dir * ray));
            ray += step_px;
            if any(q < vec2<i32>(0)) || any(q >= size) {
                break;
            }
            let sd = textureLoad(prepared_in, q, 0).x;
            if sd <= 0.0 {
                continue;
            }
            let v = view_position(vec2<f32>(q) + 0.5, sd) - pos;
            let r2 = dot(v, v) * frame.inv_radius2;
            if r2 >= 1.0 || r2 <= 0.0 {
                continue;
            }
            let sin_e = dot(n, v) * inverseSqrt(dot(v, v));
            if sin_e > sin_h {
                occlusion += (sin_e - sin_h) * (1.0 - r2);
                sin_h = sin_e;
            }
        }
    }
    return clamp(1.0 - occlusion * frame.ao_scale, 0.0, 1.0);
}

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if any(gid.xy >= frame.size) {
        return;
    }
    let p = vec2<i32>(gid.xy);
    let pattern = frame.patterns[(gid.x % PATTERN_DIM) + PATTERN_DIM * (gid.y % PATTERN_DIM)];
    let ao = hbao(p, textureLoad(prepared_in, p, 0), pattern);
    textureStore(ao_out, p, vec4<f32>(ao, 0.0, 0.0, 0.0));
}
