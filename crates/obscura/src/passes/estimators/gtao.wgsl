// Ground-Truth AO (Jimenez, Wu, Pesce & Jarabo, "Practical Realtime Strategies for Accurate
// Indirect Occlusion", 2016): the estimator only; composed like hbao.wgsl with an entry
// fragment that provides `snap_offset` and `sample_depth`, after gtao_arcs.wgsl (the
// slice frame and the closed-form arcs, shared with ssdo_bounce.wgsl).
//
// For each of DIRECTIONS screen-space slices, march STEPS samples to each side and keep the highest
// horizon (largest cos between the sample vector and the view vector V). Sky and off-screen samples
// are ignored. A front within R counts in full, as the ray-traced reference counts hits within R;
// beyond it, the front's horizon is mixed toward the tangent plane's by a falloff that reaches 0 at
// GTAO_FALLOFF_END × R (`gtao_falloff`, gtao_arcs.wgsl; the constant in constants.rs): a front seen
// beyond R usually has its body within R, which the published test at R leaves out (too bright on
// every shared view). The horizons are clamped to the normal's hemisphere and the cosine-weighted
// visible arc is integrated in closed form, weighted by the projected normal's length. Slices are
// spaced evenly in screen angle, which is not even in azimuth around V off the image centre; each
// slice is weighted by d(azimuth)/d(screen angle) so that an unoccluded surface integrates to
// exactly 1 (without it, a plane near the image edge reads 2-5% occluded). AO = weighted mean. With
// BENT_NORMALS the bent normal is integrated from the same horizons (`gtao_bent`) into
// `bent_normal` (declared by ao_bent*.wgsl). CPU mirror: src/reference.rs, `gtao_pixel`.

override DIRECTIONS: u32 = 4u;
override STEPS: u32 = 4u;
override MARCH_EXPONENT: f32 = 1.0;
override BENT_NORMALS: bool = false;

fn estimate(p: vec2<i32>, centre: vec4<f32>, pattern: vec4<f32>) -> f32 {
    let d = centre.x;
    if BENT_NORMALS {
        bent_normal = vec3<f32>(0.0);
    }
    if d <= 0.0 {
        return 1.0;
    }
    let normal = centre.yzw;
    let pos = estimator_origin(vec2<f32>(p) + 0.5, d, centre.yzw);
    var v = vec3<f32>(0.0, 0.0, 1.0);
    if frame.perspective != 0u {
        v = normalize(-pos);
    }
    let step_px = march_step_px(d, STEPS);
    let size = vec2<i32>(frame.size);
    // view_position(q, 1) is linear in q (common.wgsl): its xy at the centre and per pixel
    // of offset, so a sample's position costs a multiply-add (as in bitmask.wgsl).
    let unit_p = view_position(vec2<f32>(p) + 0.5, 1.0).xy;
    let unit_dq = view_xy_per_pixel();
    var visibility = 0.0;
    var weights = 0.0;
    var bent = vec3<f32>(0.0);
    // Slices cover half a turn (each marches both ways): the pattern's direction, turned by
    // pi / DIRECTIONS after each slice.
    let turn = vec2<f32>(cos(PI / f32(DIRECTIONS)), sin(PI / f32(DIRECTIONS)));
    var dir = pattern.xy;
    for (var i = 0u; i < DIRECTIONS; i++) {
        if i > 0u {
            dir = vec2<f32>(dir.x * turn.x - dir.y * turn.y, dir.x * turn.y + dir.y * turn.x);
        }
        let slice = gtao_slice(dir, v, normal);
        let axis = slice.axis;
        let weight = slice.weight;
        weights += weight;
        let proj_len = slice.proj_len;
        if proj_len < 1e-6 {
            visibility += weight;
            continue;
        }
        let n = slice.n;
        let cos_n = slice.cos_n;
        let sin_n = slice.sin_n;
        // Horizon cosines start at the tangent plane's (the normal's hemisphere edge):
        // cos(n + pi/2) and cos(n - pi/2).
        var hc0 = -sin_n;
        var hc1 = sin_n;
        for (var s = 0u; s < STEPS; s++) {
            let off = snap_offset(dir * march_ray(s, STEPS, pattern.z, step_px, lattice_cell(), MARCH_EXPONENT));
            // A short step snapped to the N x N lattice can land on the centre itself. With
            // the origin raised off the surface (noisy depth) that sample lies straight
            // below it and, on a surface turned over 45 degrees from V, reads as a horizon
            // inside the hemisphere; the centre is never its own occluder.
            if all(off == vec2<i32>(0)) {
                continue;
            }
            let step_xy = unit_dq * vec2<f32>(off);
            for (var side = 0; side < 2; side++) {
                var q = p + off;
                var xy = unit_p + step_xy;
                if side == 1 {
                    q = p - off;
                    xy = unit_p - step_xy;
                }
                if any(q < vec2<i32>(0)) || any(q >= size) {
                    continue;
                }
                let sd = sample_depth(q);
                if sd <= 0.0 {
                    continue;
                }
                if frame.perspective != 0u {
                    xy *= sd;
                }
                let full = vec3<f32>(xy, -sd) - pos;
                let f2 = dot(full, full);
                // Pixel snapping moves samples slightly off the slice plane, where a plane's
                // points can rise above its in-slice horizon: measure in the slice plane,
                // w = full - axis (full . axis), with |w|² = |full|² - (full . axis)² and
                // w . V = full . V (the axis is orthogonal to V).
                let along = dot(full, axis);
                let w2 = f2 - along * along;
                let k = gtao_falloff(f2 * frame.inv_radius2);
                if k <= 0.0 || w2 <= 0.0 {
                    continue;
                }
                // Above 1 only by rounding; below -1 it cannot raise the horizon.
                let c = min(dot(full, v) * inverseSqrt(w2), 1.0);
                if side == 0 {
                    hc0 = max(hc0, mix(-sin_n, c, k));
                } else {
                    hc1 = max(hc1, mix(sin_n, c, k));
                }
            }
        }
        // Side 0 marched along +dir (positive angles), side 1 along -dir.
        let arcs = gtao_side(hc0, 1.0, n, cos_n, sin_n) + gtao_side(hc1, -1.0, n, cos_n, sin_n);
        visibility += weight * proj_len * arcs;
        if BENT_NORMALS {
            let b = gtao_bent(hc0, 1.0, n, cos_n, sin_n) + gtao_bent(hc1, -1.0, n, cos_n, sin_n);
            bent += weight * proj_len * (b.x * slice.ortho + b.y * v);
        }
    }
    if BENT_NORMALS {
        bent_normal = select(normal, normalize(bent), dot(bent, bent) > 1e-12);
    }
    let per_slice = f32(DIRECTIONS) * visibility / weights;
    return clamp(1.0 - (f32(DIRECTIONS) - per_slice) * frame.ao_scale, 0.0, 1.0);
}
