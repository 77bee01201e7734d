// Visibility-bitmask AO (Therrien, Levesque & Gilet, "Screen Space Indirect Lighting with
// Visibility Bitmask", 2023): the estimator only; composed like gtao.wgsl, after
// gtao_arcs.wgsl (the slice frame and `fast_acos`).
//
// GTAO's slices and samples, but a slice keeps a 32-bit field of occluded sectors instead of two
// horizons. A sample is a solid from its front (the depth seen) to its back (the front pushed away
// from the camera by the thickness prior, frame.model.x), and occludes the sectors between the
// directions of the ends of its stretch within R of the centre: the ray-traced reference counts
// hits within R, and a solid whose front lies beyond R (a ledge above the centre, seen from above)
// can still reach into that sphere. An infinitely thick solid counts from GTAO's horizon, with its
// falloff beyond R (`falloff_front`), as in GTAO. Sky and off-screen samples are ignored. The
// sectors are equal steps of a pseudo-angle, which costs a division where an angle costs an arc
// cosine (`sector_pair`). A slice's visibility is its cosine-weighted integral (Jimenez et al.
// 2016, eq. 10) less that over its runs of occluded sectors, exact between sector edges
// (`sectors_integral`), so with infinite thickness the estimate is GTAO's with each horizon rounded
// to the nearest sector edge; the rounding has no sign. Slice weights and the final mapping are
// GTAO's; so is the bent normal, integrated over the clear runs (`bitmask_bent`). With a second
// depth layer (AoOptions::second_layer) a sample is two solids, the second from the surface behind
// the first (second_layer.wgsl). CPU mirror: passes/estimators/bitmask.rs, `bitmask_pixel`.

override DIRECTIONS: u32 = 4u;
override STEPS: u32 = 4u;
override MARCH_EXPONENT: f32 = 1.0;
override BENT_NORMALS: bool = false;

// SECTORS (constants.rs) as a float.
const SECTORS_F: f32 = f32(SECTORS);

// Sector edge k (0 to SECTORS) is the direction (p, 1 - |p|), p = 2k / SECTORS - 1, in
// (tangent, normal) coordinates: its angle a from the normal, cos a and sin a, from an
// inverse square root and A&S 4.4.46's arc cosine (ACOS_POLY_FINE, constants.rs) where
// atan2 and a cosine cost more. Mirror: `sector_edge`.
fn sector_edge(k: u32) -> vec3<f32> {
    let p = f32(k) * (2.0 / SECTORS_F) - 1.0;
    let b = 1.0 - abs(p);
    let inv_len = inverseSqrt(p * p + b * b);
    let x = b * inv_len;
    let c = ACOS_POLY_FINE;
    let poly = c[0] + x * (c[1] + x * (c[2] + x * (c[3] + x * (c[4] + x * (c[5] + x * (c[6] + x * c[7]))))));
    let a = sqrt(1.0 - x) * poly;
    return vec3<f32>(select(a, -a, p < 0.0), x, p * inv_len);
}

// The running integral D at sector edge k, the slice angle h = n + a:
// cos(2h - n) = cos(n + 2a) from cos a and sin a. Mirror: `slice_at_edge`.
fn slice_at_edge(k: u32, n: f32, cos_n: f32, sin_n: f32) -> f32 {
    let e = sector_edge(k);
    let h = n + e.x;
    let cos_2h_n = cos_n * (e.y * e.y - e.z * e.z) - sin_n * (2.0 * e.y * e.z);
    let g = (cos_n + 2.0 * h * sin_n - cos_2h_n) * 0.25;
    return select(g, -g, h < 0.0);
}

// The running bent-normal integral at sector edge k, signed like D: gtao_bent's closed form
// (gtao_arcs.wgsl) at cos h and sin h (h = n + a), in (ortho, V) coordinates.
// Mirror: `bent_at_edge`.
fn bent_at_edge(k: u32, n: f32, cos_n: f32, sin_n: f32) -> vec2<f32> {
    let e = sector_edge(k);
    let ch = cos_n * e.y - sin_n * e.z;
    let sh = sin_n * e.y + cos_n * e.z;
    let sh3 = sh * sh * sh;
    let ch3 = ch * ch * ch;
    let f = vec2<f32>(cos_n * sh3 + sin_n * (2.0 - 3.0 * ch + ch3), cos_n * (1.0 - ch3) + sin_n * sh3) / 3.0;
    return select(f, -f, n + e.x < 0.0);
}

// A slice's sectors: SECTORS bits from the normal's hemisphere edge n - pi/2 (bit 0) to
// n + pi/2, in equal steps of the pseudo-angle p = a / (|a| + b) of a direction with
// components a along the tangent (toward the edge n + pi/2) and b along the projected
// normal. p runs monotonically from -1 to 1 and costs one division where the angle costs
// an arc cosine; a sector spans 3.6 degrees at the normal and the edges, 7.2 halfway.
// The positions (0 to SECTORS) of two in-slice directions w = (a, b) on side s, with one
// division (a0 / d0 = a0 d1 / (d0 d1)); below the hemisphere (b <= 0) a direction takes its
// side's edge. Mirror: `sector_of`.
fn sector_pair(w0: vec2<f32>, w1: vec2<f32>, s: f32) -> vec2<f32> {
    let d0 = max(abs(w0.x) + w0.y, 1e-18);
    let d1 = max(abs(w1.x) + w1.y, 1e-18);
    let r = 1.0 / (d0 * d1);
    let p = vec2<f32>(select(w0.x * d1 * r, s, w0.y <= 0.0), select(w1.x * d0 * r, s, w1.y <= 0.0));
    return p * (0.5 * SECTORS_F) + 0.5 * SECTORS_F;
}

// An infinitely thick front beyond R, its direction `w` in the slice's (tangent, normal)
// frame on side `sgn`, at `r2` radii² from the centre: the direction whose cosine to V is
// GTAO's horizon there, the front's mixed toward the tangent plane's by `gtao_falloff`, so
// that infinitely thick, the bitmask is GTAO. Mirror: `falloff_front`.
fn falloff_front(w: vec2<f32>, sgn: f32, r2: f32, cos_n: f32, sin_n: f32) -> vec2<f32> {
    let c = clamp((cos_n * w.y - sin_n * w.x) * inverseSqrt(dot(w, w)), -1.0, 1.0);
    let h = mix(-sgn * sin_n, c, gtao_falloff(r2));
    let o = sgn * sqrt(max(1.0 - h * h, 0.0));
    return vec2<f32>(cos_n * o - sin_n * h, sin_n * o + cos_n * h);
}

// 32 bits hold at most 16 runs of set bits: the bound of the loops over runs below
// (counted loops, as every shader loop here; tests/gpu/shaders.rs).
const MAX_RUNS: u32 = 16u;

// The lowest run of set bits of `bits` (not 0): [start, end).
fn lowest_run(bits: u32) -> vec2<u32> {
    let start = firstTrailingBit(bits);
    let filled = bits | ((1u << start) - 1u);
    let end = select(firstTrailingBit(~filled), 32u, filled == 0xffffffffu);
    return vec2<u32>(start, end);
}

// The slice's cosine-weighted integral over the sectors set in `bits`: the running
// integral D at each run's edge angles, so it is exact between sector edges, whatever
// their widths. Mirror: `sectors_integral`.
fn sectors_integral(bits_in: u32, n: f32, cos_n: f32, sin_n: f32) -> f32 {
    var bits = bits_in;
    var sum = 0.0;
    for (var i = 0u; i < MAX_RUNS; i++) {
        if bits == 0u {
            break;
        }
        let r = lowest_run(bits);
        sum += slice_at_edge(r.y, n, cos_n, sin_n) - slice_at_edge(r.x, n, cos_n, sin_n);
        bits = insertBits(bits, 0u, r.x, r.y - r.x);
    }
    return sum;
}

// The slice's share of the bent normal (Jimenez et al. 2016, sec. 5: the cosine-weighted
// mean of the unoccluded directions): gtao_bent's closed form between the edge angles of
// each run of clear sectors. Mirror: `bitmask_bent`.
fn bitmask_bent(occluded: u32, n: f32, cos_n: f32, sin_n: f32) -> vec2<f32> {
    var bits = ~occluded;
    var bent = vec2<f32>(0.0);
    for (var i = 0u; i < MAX_RUNS; i++) {
        if bits == 0u {
            break;
        }
        let r = lowest_run(bits);
        bent += bent_at_edge(r.y, n, cos_n, sin_n) - bent_at_edge(r.x, n, cos_n, sin_n);
        bits = insertBits(bits, 0u, r.x, r.y - r.x);
    }
    return bent;
}

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
    let persp = frame.perspective != 0u;
    // Positions in units of R, so that a point lies within R where its squared length is
    // below 1. A sample at pixel q and linear depth t lies at base(q) + t ray(q) with
    // unit(q) = view_position(q, 1), linear in q (common.wgsl): in perspective base 0 and
    // ray unit(q); in orthographic projection ray -z and base unit(q) + z.
    let inv_r = sqrt(frame.inv_radius2);
    let thickness = frame.model.x;
    let unit_p = view_position(vec2<f32>(p) + 0.5, 1.0) * inv_r;
    let unit_dq = view_xy_per_pixel() * inv_r;
    let pos_r = pos * inv_r;
    let z_ray = vec3<f32>(0.0, 0.0, -inv_r);
    var visibility = 0.0;
    var weights = 0.0;
    var bent = vec3<f32>(0.0);
    let turn = vec2<f32>(cos(PI / f32(DIRECTIONS)), sin(PI / f32(DIRECTIONS)));
    var dir = pattern.xy;
    for (var i = 0u; i < DIRECTIONS; i++) {
        if i > 0u {
            dir = vec2<f32>(dir.x * turn.x - dir.y * turn.y, dir.x * turn.y + dir.y * turn.x);
        }
        let slice = gtao_slice(dir, v, normal);
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
        // The slice's integral from D(n - pi/2) to D(n + pi/2), where cos(2h - n) = -cos n:
        // cos n + n sin n (mirror: `slice_total`).
        let total = cos_n + n * sin_n;
        // Each point projected once, onto the slice's tangent (toward the edge n + pi/2),
        // its projected normal and its axis: the first two are the pseudo-angle's a and b
        // (`sector_pair`), all three its distance from the centre. unit(q) is unit(p) plus a
        // step's pixel offset times unit_dq, so a step projects its offset once for both
        // sides. Mirror: `clip_solid` and `sector_of`, which project the clipped ends.
        let e_t = cos_n * slice.ortho - sin_n * v;
        let e_n = sin_n * slice.ortho + cos_n * v;
        let e_a = slice.axis;
        let unit_s = vec3<f32>(dot(unit_p, e_t), dot(unit_p, e_n), dot(unit_p, e_a));
        let pos_s = vec3<f32>(dot(pos_r, e_t), dot(pos_r, e_n), dot(pos_r, e_a));
        let z_s = vec3<f32>(z_ray.z * e_t.z, z_ray.z * e_n.z, z_ray.z * e_a.z);
        let dq_t = unit_dq * e_t.xy;
        let dq_n = unit_dq * e_n.xy;
        let dq_a = unit_dq * e_a.xy;
        var occluded = 0u;
        for (var s = 0u; s < STEPS; s++) {
            let off = snap_offset(dir * march_ray(s, STEPS, pattern.z, step_px, lattice_cell(), MARCH_EXPONENT));
            // The centre is never its own occluder (gtao.wgsl).
            if all(off == vec2<i32>(0)) {
                continue;
            }
            let offf = vec2<f32>(off);
            let step_s = vec3<f32>(dot(offf, dq_t), dot(offf, dq_n), dot(offf, dq_a));
            for (var side = 0; side < 2; side++) {
                var q = p + off;
                var sgn = 1.0;
                if side == 1 {
                    q = p - off;
                    sgn = -1.0;
                }
                if any(q < vec2<i32>(0)) || any(q >= size) {
                    continue;
                }
                let sd = sample_depth(q);
                if sd <= 0.0 {
                    continue;
                }
                let unit_q = unit_s + sgn * step_s;
                let ray = select(z_s, unit_q, persp);
                let base = select(unit_q - z_s, vec3<f32>(0.0), persp) - pos_s;
                let seg = thickness * ray;
                let qa = dot(seg, seg);
                // The solids along the sample's view ray: the first layer's, and the second
                // layer's where one lies behind it (second_layer*.wgsl; mirror: `solids`).
                let sd2 = sample_second(q);
                for (var k = 0u; k < DEPTH_LAYERS; k++) {
                    var fd = sd;
                    if k == 1u {
                        if !(sd2 > sd) {
                            break;
                        }
                        fd = sd2;
                    }
                    let front = base + fd * ray;
                    let c = dot(front, front) - 1.0;
                    // The ends' (a, b), the front's and the back's; an infinitely thick solid
                    // reaches its side's edge (b <= 0 reads as the edge in `sector_pair`).
                    var fa = front.xy;
                    var ba = vec2<f32>(sgn, -1.0);
                    var inside = c < GTAO_FALLOFF_END * GTAO_FALLOFF_END - 1.0;
                    if thickness > 0.0 {
                        // The solid's stretch of the view ray within R of the centre: the
                        // roots s of |front + s seg| = 1, clamped to [0, 1], each times qa
                        // (> 0, which the pseudo-angle's ratio does not see), so that no
                        // division is needed. Mirror: `clip_solid`.
                        let qb = dot(front, seg);
                        let disc = qb * qb - qa * c;
                        let sq = sqrt(max(disc, 0.0));
                        let s0 = max(-qb - sq, 0.0);
                        let s1 = min(-qb + sq, qa);
                        inside = disc > 0.0 && s1 > s0;
                        fa = qa * front.xy + s0 * seg.xy;
                        ba = qa * front.xy + s1 * seg.xy;
                    }
                    if !inside || all(fa == vec2<f32>(0.0)) {
                        continue;
                    }
                    if thickness <= 0.0 && c > 0.0 {
                        fa = falloff_front(fa, sgn, c + 1.0, cos_n, sin_n);
                    }
                    let u = sector_pair(fa, ba, sgn);
                    let a = u32(round(min(u.x, u.y)));
                    let b = u32(round(max(u.x, u.y)));
                    occluded |= insertBits(0u, 0xffffffffu, a, b - a);
                }
            }
        }
        visibility += weight * proj_len * max(total - sectors_integral(occluded, n, cos_n, sin_n), 0.0);
        if BENT_NORMALS {
            let b = bitmask_bent(occluded, n, cos_n, sin_n);
            bent += weight * proj_len * (b.x * slice.ortho + b.y * v);
        }
    }
    if BENT_NORMALS {
        bent_normal = select(normal, normalize(bent), dot(bent, bent) > 1e-12);
    }
    let per_slice = f32(DIRECTIONS) * visibility / weights;
    return clamp(1.0 - (f32(DIRECTIONS) - per_slice) * frame.ao_scale, 0.0, 1.0);
}
