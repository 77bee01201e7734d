// One diffuse bounce of screen-space directional occlusion (Ritschel, Grosch & Seidel
// 2009), on GTAO's slices (Jimenez et al. 2016; gtao_arcs.wgsl). Composed after a
// prepared source, gtao_arcs.wgsl, ssdo_env.wgsl and an output (lit_out_packed.wgsl when
// the merge follows, else lit_out_plain.wgsl).
//
// Per slice and side the march finds the horizon as GTAO does (samples within the radius,
// measured in the slice plane; samples on the receiver's own tangent plane, within
// SSDO_SELF_TOLERANCE of the depth or the depth noise's tolerance, are not occluders). The cosine-weighted arc between the tangent plane and the
// horizon, gtao_side(tangent) − gtao_side(horizon), is the share of the hemisphere the
// occluders cover on that side; it is lit by the sample that set the horizon, whose
// radiance is its albedo times the environment's irradiance at its normal (no shadowing
// at the sender: one bounce of the unshadowed environment). Slices are weighted as GTAO
// weights them, so on the same slices a pixel's open arcs (GTAO's AO at strength 1) and
// its covered arcs sum to 1.
//
// With PERIOD n > 1 each pixel class of the n × n tile takes its own pattern (first slice
// direction, step offset; `SsdoOptions::patterns`), and lights_merge.wgsl reconstructs
// the tile from every class. Output: bounce irradiance / π (rgb, before the receiver's
// albedo), 0 on sky. CPU mirror: src/reference.rs, `ssdo_bounce`.

override PERIOD: u32 = 1u;
override DIRECTIONS: u32 = 2u;
override STEPS: u32 = 4u;

@group(0) @binding(0) var<uniform> frame: FrameUniforms;

// The light a sender pixel reflects: its albedo times the environment's irradiance at its
// normal.
fn sender_radiance(q: vec2<i32>) -> vec3<f32> {
    return albedo_at(q) * env_irradiance(prepared_at(q).yzw);
}

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if any(gid.xy >= frame.size) {
        return;
    }
    let p = vec2<i32>(gid.xy);
    let centre = prepared_at(p);
    let d = centre.x;
    if !(d > 0.0) {
        store_lit(p, centre, vec3<f32>(0.0));
        return;
    }
    let normal = centre.yzw;
    let pos = estimator_origin(vec2<f32>(p) + 0.5, d, normal);
    var v = vec3<f32>(0.0, 0.0, 1.0);
    if frame.perspective != 0u {
        v = normalize(-pos);
    }
    let pattern = ssdo.patterns[layer_of(gid.xy, PERIOD)];
    let step_px = march_step_px(d, STEPS);
    // Below this height over the tangent plane a sample is the receiver's own surface.
    let tolerance = SSDO_SELF_TOLERANCE * d + NOISE_TOLERANCE_SIGMAS * depth_sigma(d);
    let size = vec2<i32>(frame.size);
    let turn = vec2<f32>(cos(PI / f32(DIRECTIONS)), sin(PI / f32(DIRECTIONS)));
    var dir = pattern.xy;
    var weights = 0.0;
    var bounce = vec3<f32>(0.0);
    for (var i = 0u; i < DIRECTIONS; i++) {
        if i > 0u {
            dir = vec2<f32>(dir.x * turn.x - dir.y * turn.y, dir.x * turn.y + dir.y * turn.x);
        }
        let slice = gtao_slice(dir, v, normal);
        weights += slice.weight;
        if slice.proj_len < 1e-6 {
            continue;
        }
        // Side 0 marches along +dir (tangent cosine −sin n), side 1 along −dir (+sin n);
        // each keeps its horizon cosine and the sample that set it (scalars, not arrays
        // indexed by the side: lavapipe spills those to memory).
        var hc0 = -slice.sin_n;
        var hc1 = slice.sin_n;
        var hq0 = p;
        var hq1 = p;
        var ray = pattern.z * step_px + 1.0;
        for (var s = 0u; s < STEPS; s++) {
            let off = vec2<i32>(round(dir * ray));
            ray += step_px;
            if all(off == vec2<i32>(0)) {
                continue;
            }
            for (var side = 0; side < 2; side++) {
                let q = select(p + off, p - off, side == 1);
                if any(q < vec2<i32>(0)) || any(q >= size) {
                    continue;
                }
                let sd = prepared_at(q).x;
                if !(sd > 0.0) {
                    continue;
                }
                let full = view_position(vec2<f32>(q) + 0.5, sd) - pos;
                let r2 = dot(full, full) * frame.inv_radius2;
                let w = full - slice.axis * dot(full, slice.axis);
                // A sample on the tangent plane is the receiver's own surface (snapped off
                // the slice it can read a hair above the horizon), not an occluder.
                if r2 >= 1.0 || dot(w, w) <= 0.0 || dot(full, normal) <= tolerance {
                    continue;
                }
                let c = clamp(dot(w, v) * inverseSqrt(dot(w, w)), -1.0, 1.0);
                if side == 0 && c > hc0 {
                    hc0 = c;
                    hq0 = q;
                } else if side == 1 && c > hc1 {
                    hc1 = c;
                    hq1 = q;
                }
            }
        }
        let weight = slice.weight * slice.proj_len;
        let covered0 = gtao_side(-slice.sin_n, 1.0, slice.n, slice.cos_n, slice.sin_n)
            - gtao_side(hc0, 1.0, slice.n, slice.cos_n, slice.sin_n);
        let covered1 = gtao_side(slice.sin_n, -1.0, slice.n, slice.cos_n, slice.sin_n)
            - gtao_side(hc1, -1.0, slice.n, slice.cos_n, slice.sin_n);
        if covered0 > 0.0 {
            bounce += (weight * covered0) * sender_radiance(hq0);
        }
        if covered1 > 0.0 {
            bounce += (weight * covered1) * sender_radiance(hq1);
        }
    }
    store_lit(p, centre, bounce / weights);
}
