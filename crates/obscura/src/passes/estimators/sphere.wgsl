// Volumetric estimators (summarized in seed 002): the fraction of a sphere's volume that
// lies behind the depth buffer, by line integrals — each sample is a chord of the sphere
// along the view axis, and the depth buffer tells how much of that chord is occupied.
// - Volumetric Obscurance (Loos & Sloan, I3D 2010): the sphere of radius R is centred on
//   the pixel's surface point; a flat surface fills half of it, so AO = 2·(1 − occupied).
// - Volumetric AO (Szirmay-Kalos et al. 2009): the sphere of radius R/2 is centred R/2
//   along the normal, so it touches the tangent plane: AO = 1 − occupied, no tangent maths.
// SPHERE_OFFSET (0 for VO, 0.5 for VAO) selects which. Samples: DIRECTIONS × STEPS points of
// the sphere's screen disk, area-uniform in radius, rotated and offset by the pattern.
// How a sample's chord is read comes from a fragment: sphere_line.wgsl (one depth: the line
// integral) or sphere_area.wgsl (VO's area integral: the depth moments of the sample's
// share of the disk), as `sample_level` and `chord_occupied`.
// Composed like hbao.wgsl with an entry fragment (`snap_offset`, `sample_depth`).
// CPU mirror: src/reference.rs, `sphere_pixel`.

override DIRECTIONS: u32 = 4u;
override STEPS: u32 = 4u;
override SPHERE_OFFSET: f32 = 0.0;

// Pixel-space point (viewport-local, not centred) of view-space point `v`.
fn project_to_pixel(v: vec3<f32>) -> vec2<f32> {
    var xy = v.xy / frame.ndc_to_view;
    if frame.perspective != 0u {
        xy = xy / -v.z;
    }
    return vec2<f32>((xy.x + 1.0) * 0.5 / frame.inv_size.x, (1.0 - xy.y) * 0.5 / frame.inv_size.y);
}

// The occupied length of the chord dc ± h by a surface at depth sd > 0. The solid behind
// the visible surface is SPHERE_THICKNESS radii deep (Loos & Sloan's thickness model), not
// infinite: a foreground object far in front of the sphere does not fill the chords behind it.
fn occupied_length(sd: f32, dc: f32, h: f32) -> f32 {
    let back = sd + SPHERE_THICKNESS * frame.radius;
    return clamp(min(dc + h, back) - max(sd, dc - h), 0.0, 2.0 * h);
}

// The occupied length of the chord by the one depth at pixel `q` (sky: none).
fn line_occupied(q: vec2<i32>, dc: f32, h: f32) -> f32 {
    let sd = sample_depth(q);
    if sd <= 0.0 {
        return 0.0;
    }
    return occupied_length(sd, dc, h);
}

fn estimate(p: vec2<i32>, centre: vec4<f32>, pattern: vec4<f32>) -> f32 {
    let d = centre.x;
    if d <= 0.0 {
        return 1.0;
    }
    let pos = estimator_origin(vec2<f32>(p) + 0.5, d, centre.yzw);
    // VO: radius R around the point; VAO: radius R/2, centre R/2 along the normal.
    let rs = frame.radius * (1.0 - SPHERE_OFFSET);
    let c = pos + centre.yzw * (frame.radius * SPHERE_OFFSET);
    let dc = -c.z;
    if dc <= 0.0 {
        return 1.0;
    }
    // The sphere's screen radius, from radius_px's projection at the centre's depth.
    let rs_px = radius_px(dc) * (1.0 - SPHERE_OFFSET);
    let c_px = project_to_pixel(c) - (vec2<f32>(p) + 0.5);
    let level = sample_level(rs_px);
    var occupied = 0.0;
    var total = 0.0;
    for (var i = 0u; i < DIRECTIONS; i++) {
        let a = f32(i) * (TAU / f32(DIRECTIONS));
        let base = vec2<f32>(cos(a), sin(a));
        let dir = vec2<f32>(base.x * pattern.x - base.y * pattern.y, base.x * pattern.y + base.y * pattern.x);
        for (var s = 0u; s < STEPS; s++) {
            let r = sqrt((f32(s) + pattern.z) / f32(STEPS));
            let q = p + snap_offset(c_px + dir * (r * rs_px));
            if any(q < vec2<i32>(0)) || any(q >= vec2<i32>(frame.size)) {
                continue;
            }
            // The chord through the sample's pixel (or moments texel) at the centre's depth.
            let lateral = view_position(chord_point(q, level), dc).xy - c.xy;
            let l2 = dot(lateral, lateral) / (rs * rs);
            if l2 >= 1.0 {
                continue;
            }
            let h = rs * sqrt(1.0 - l2);
            total += 2.0 * h;
            occupied += chord_occupied(q, level, dc, h);
        }
    }
    if total <= 0.0 {
        return 1.0;
    }
    let f = occupied / total;
    var open = 1.0 - f;
    if SPHERE_OFFSET == 0.0 {
        open = 2.0 * open;
    }
    return clamp(1.0 - (1.0 - min(open, 1.0)) * frame.ao_scale, 0.0, 1.0);
}
