// Horizon-based ambient occlusion (Bavoil, Sainz & Dimitrov, "Image-Space Horizon-Based
// Ambient Occlusion", SIGGRAPH 2008): the estimator only. It knows nothing of how pixels
// are laid out: the entry point it is composed with (ao_full.wgsl or ao_layered.wgsl)
// provides `snap_offset` (screen offset -> integer pixel offset on its sampling lattice:
// any pixel, or multiples of N for N x N layers) and `sample_depth` (linear depth of a
// full-resolution pixel).
//
// For each of DIRECTIONS screen-space directions, march STEPS samples out to the radius.
// A sample's elevation above the tangent plane is sin(e) = dot(n, v)/|v|; whenever it
// raises the horizon, the direction's occlusion grows by (sin e - sin h) * W(r), with
// falloff W(r) = 1 - r^2/R^2. The horizon starts at the tangent bias angle. Samples
// farther than R, sky and off-screen samples do not occlude.
//
// Output: AO in [0, 1], 1 = unoccluded. CPU mirror: src/reference.rs, `hbao_pixel`.
// Every estimator fragment defines `estimate` with this signature.
//
// With BENT_NORMALS the bent normal (the cosine-weighted mean of the unoccluded directions)
// comes from the same horizons: in direction i, with t_i its unit tangent (the line the
// march follows on the tangent plane: in the plane of the view vector and the screen
// direction) and h_i the final horizon
// elevation, the directions above the horizon, (cos a) t_i + (sin a) n for a from h_i to
// pi/2, weighted by cos(angle to n) = sin a over dω = cos a da, integrate to
//   t_i cos³(h_i) / 3 + n (1 − sin³(h_i)) / 3,
// summed over the directions and normalised (zero on sky). A plane gives n; a horizon
// raised on one side tilts it away. Mirror: `hbao_pixel_bent`.

override DIRECTIONS: u32 = 8u;
override STEPS: u32 = 4u;
override BENT_NORMALS: bool = false;

// Pixel `p` (full resolution), its prepared value vec4(d, n), its pattern (cos, sin, offset, _).
fn estimate(p: vec2<i32>, centre: vec4<f32>, pattern: vec4<f32>) -> f32 {
    let d = centre.x;
    if BENT_NORMALS {
        bent_normal = vec3<f32>(0.0);
    }
    if d <= 0.0 {
        return 1.0;
    }
    let n = centre.yzw;
    let pos = estimator_origin(vec2<f32>(p) + 0.5, d, centre.yzw);
    let step_px = march_step_px(d, STEPS);
    let size = vec2<i32>(frame.size);
    var occlusion = 0.0;
    var bent = vec3<f32>(0.0);
    var view = vec3<f32>(0.0, 0.0, 1.0);
    if frame.perspective != 0u {
        view = normalize(-pos);
    }
    for (var i = 0u; i < DIRECTIONS; i++) {
        let a = f32(i) * (TAU / f32(DIRECTIONS));
        let base = vec2<f32>(cos(a), sin(a));
        let dir = vec2<f32>(base.x * pattern.x - base.y * pattern.y, base.x * pattern.y + base.y * pattern.x);
        // The first sample lies one lattice step out (one pixel of the layer being marched).
        // Marching starts one pixel out in every mode. (Starting one lattice step out in
        // the N x N modes raised their error against ray-traced AO: docs/quality.md.)
        var ray = pattern.z * step_px + 1.0;
        var sin_h = frame.sin_bias;
        for (var s = 0u; s < STEPS; s++) {
            let q = p + snap_offset(dir * ray);
            ray += step_px;
            if any(q < vec2<i32>(0)) || any(q >= size) {
                break;
            }
            let sd = sample_depth(q);
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
        if BENT_NORMALS {
            // The screen direction in view space (y flips), moved along the view vector
            // into the tangent plane.
            let d3 = vec3<f32>(dir.x, -dir.y, 0.0);
            let along = d3 * max(dot(view, n), 1e-4) - view * dot(d3, n);
            let t = along * inverseSqrt(max(dot(along, along), 1e-12));
            let s = clamp(sin_h, -1.0, 1.0);
            let c2 = 1.0 - s * s;
            bent += t * (c2 * sqrt(c2) / 3.0) + n * ((1.0 - s * s * s) / 3.0);
        }
    }
    if BENT_NORMALS {
        bent_normal = select(n, normalize(bent), dot(bent, bent) > 1e-12);
    }
    return clamp(1.0 - occlusion * frame.ao_scale, 0.0, 1.0);
}
