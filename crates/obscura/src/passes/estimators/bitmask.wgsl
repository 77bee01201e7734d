// Visibility-bitmask AO (Therrien, Levesque & Gilet, "Screen Space Indirect Lighting with
// Visibility Bitmask", 2023): the estimator only; composed like gtao.wgsl, after
// gtao_arcs.wgsl (the slice frame and `fast_acos`).
//
// GTAO's slices and samples, but a slice keeps a 32-bit field of occluded sectors instead
// of two horizons. A sample is a solid from its front (the depth seen) to its back (the
// front pushed away from the camera by the thickness prior, frame.model.x), and occludes
// the sectors between the directions of the ends of its stretch within R of the centre:
// the ray-traced reference counts hits within R, and a solid whose front lies beyond R
// (a ledge above the centre, seen from above) can still reach into that sphere. An
// infinitely thick solid counts where its front is within R, as in GTAO. Sky and
// off-screen samples are ignored. The sectors are not equal angles (the paper's choice)
// but equal shares of the slice's cosine-weighted integral (Jimenez et al. 2016, eq. 10),
// so a slice's visibility is its unoccluded integral times the share of clear bits, and
// with infinite thickness the estimate is GTAO's up to the 1/32 quantisation. Sector
// edges are rounded to the nearest bit, so the quantisation has no sign. Slice weights
// and the final mapping are GTAO's; so is the bent normal, integrated over the clear
// sectors (`bitmask_bent`). With a second depth layer (AoOptions::second_layer) a sample
// is two solids, the second from the surface behind the first (second_layer.wgsl). CPU
// mirror: passes/estimators/bitmask.rs, `bitmask_pixel`.

override DIRECTIONS: u32 = 4u;
override STEPS: u32 = 4u;
override MARCH_EXPONENT: f32 = 1.0;
override BENT_NORMALS: bool = false;

const SECTORS: f32 = 32.0;

// The slice's cosine-weighted integral from 0 to the angle h of the unit in-slice direction
// w = (sin, cos) of h in (ortho, V) coordinates, on side s (h = s * acos(w.y), clamped to
// the normal's hemisphere n +- pi/2), signed: the running integral D(h) of cos(t - n)
// |sin t|, D(0) = 0. gtao_side's closed form, with the sign of h; |sin h| is |w.x|.
fn slice_cumulative(w: vec2<f32>, s: f32, n: f32, cos_n: f32, sin_n: f32) -> f32 {
    let c = clamp(w.y, -1.0, 1.0);
    let t = s * fast_acos(c) - n;
    let h = n + clamp(t, -HALF_PI, HALF_PI);
    let sin_h = s * abs(w.x);
    let cos_2h_n = select((2.0 * c * c - 1.0) * cos_n + 2.0 * sin_h * c * sin_n, -cos_n, abs(t) > HALF_PI);
    let g = (cos_n + 2.0 * h * sin_n - cos_2h_n) * 0.25;
    return select(g, -g, h < 0.0);
}

// D at the hemisphere's edge n + e * pi/2 (e = +1 or -1), where cos(2h - n) = -cos n.
fn slice_edge(e: f32, n: f32, cos_n: f32, sin_n: f32) -> f32 {
    let h = n + e * HALF_PI;
    let g = (cos_n + h * sin_n) * 0.5;
    return select(g, -g, h < 0.0);
}

// The running integral D at an angle h of the slice (h within the normal's hemisphere).
fn slice_at(h: f32, n: f32, cos_n: f32, sin_n: f32) -> f32 {
    let g = (cos_n + 2.0 * h * sin_n - cos(2.0 * h - n)) * 0.25;
    return select(g, -g, h < 0.0);
}

// The running bent-normal integral at angle h, signed like D: gtao_bent's closed form
// (gtao_arcs.wgsl) at cos h and sin h, in (ortho, V) coordinates.
fn bent_at(h: f32, cos_n: f32, sin_n: f32) -> vec2<f32> {
    let ch = cos(h);
    let sh = sin(h);
    let sh3 = sh * sh * sh;
    let ch3 = ch * ch * ch;
    let f = vec2<f32>(cos_n * sh3 + sin_n * (2.0 - 3.0 * ch + ch3), cos_n * (1.0 - ch3) + sin_n * sh3) / 3.0;
    return select(f, -f, h < 0.0);
}

// The slice's share of the bent normal (Jimenez et al. 2016, sec. 5: the cosine-weighted
// mean of the unoccluded directions), summed over the runs of clear sectors. A sector edge
// at share u of the integral is turned back into an angle by interpolating D between
// BENT_KNOTS + 1 angles evenly spread over the hemisphere. Mirror: `bitmask_bent`.
const BENT_KNOTS: u32 = 8u;

fn bitmask_bent(occluded: u32, n: f32, cos_n: f32, sin_n: f32, lower: f32, total: f32) -> vec2<f32> {
    let first = n - HALF_PI;
    let width = PI / f32(BENT_KNOTS);
    var knots: array<f32, 9>;
    for (var i = 0u; i <= BENT_KNOTS; i++) {
        knots[i] = (slice_at(first + f32(i) * width, n, cos_n, sin_n) - lower) / max(total, 1e-6);
    }
    var bent = vec2<f32>(0.0);
    var run_start = 0.0;
    var start = -1;
    for (var k = 0; k <= 32; k++) {
        let clear = k < 32 && (occluded & (1u << u32(k))) == 0u;
        if clear == (start >= 0) {
            continue;
        }
        // An edge of a clear run: its angle from its share of the integral.
        let u = f32(k) / SECTORS;
        var h = first + PI;
        for (var i = 0u; i < BENT_KNOTS; i++) {
            if u <= knots[i + 1u] {
                let t = clamp((u - knots[i]) / max(knots[i + 1u] - knots[i], 1e-6), 0.0, 1.0);
                h = first + (f32(i) + t) * width;
                break;
            }
        }
        if clear {
            start = k;
            run_start = h;
        } else {
            bent += bent_at(h, cos_n, sin_n) - bent_at(run_start, cos_n, sin_n);
            start = -1;
        }
    }
    return bent;
}

// Bits [a, b) set, 0 <= a, b <= 32.
fn sector_bits(a: u32, b: u32) -> u32 {
    let below_b = select((1u << b) - 1u, 0xffffffffu, b >= 32u);
    let below_a = select((1u << a) - 1u, 0xffffffffu, a >= 32u);
    return below_b & ~below_a;
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
    let thickness = frame.model.x;
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
        // The slice's integral runs from D(n - pi/2) to D(n + pi/2); bit k is the k-th 1/32
        // of it.
        let lower = slice_edge(-1.0, n, cos_n, sin_n);
        let total = slice_edge(1.0, n, cos_n, sin_n) - lower;
        let to_bits = SECTORS / max(total, 1e-6);
        var occluded = 0u;
        for (var s = 0u; s < STEPS; s++) {
            let off = snap_offset(dir * march_ray(s, STEPS, pattern.z, step_px, lattice_cell(), MARCH_EXPONENT));
            // The centre is never its own occluder (gtao.wgsl).
            if all(off == vec2<i32>(0)) {
                continue;
            }
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
                // The sample's view ray: view_position(at, z) = base + z * ray (common.wgsl;
                // base 0 in perspective, ray -z in orthographic projection), so a solid of
                // depth t spans t * ray.
                let unit = view_position(vec2<f32>(q) + 0.5, 1.0);
                let persp = frame.perspective != 0u;
                let ray = select(vec3<f32>(0.0, 0.0, -1.0), unit, persp);
                let base = select(vec3<f32>(unit.xy, 0.0), vec3<f32>(0.0), persp);
                let seg = thickness * ray;
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
                    let front0 = base + fd * ray - pos;
                    let c = dot(front0, front0) * frame.inv_radius2 - 1.0;
                    // The ends in the slice plane's (ortho, V) coordinates, measured there as in
                    // gtao.wgsl (pixel snapping moves samples slightly off the plane).
                    let f2 = vec2<f32>(dot(front0, slice.ortho), dot(front0, v));
                    var wf = f2;
                    var wb = f2;
                    var inside = c < 0.0;
                    if thickness > 0.0 {
                        // The solid's stretch of the view ray within R of the centre: the
                        // roots s of |front0 + s seg| = R, clamped to [0, 1]. Mirror: `clip_solid`.
                        let qa = dot(seg, seg) * frame.inv_radius2;
                        let qb = dot(front0, seg) * frame.inv_radius2;
                        let disc = qb * qb - qa * c;
                        let sq = sqrt(max(disc, 0.0));
                        let inv_qa = 1.0 / qa;
                        let s0 = max((-qb - sq) * inv_qa, 0.0);
                        let s1 = min((-qb + sq) * inv_qa, 1.0);
                        inside = qa > 0.0 && disc > 0.0 && s1 > s0;
                        let seg2 = vec2<f32>(dot(seg, slice.ortho), dot(seg, v));
                        wf = f2 + s0 * seg2;
                        wb = f2 + s1 * seg2;
                    }
                    let lf = dot(wf, wf);
                    if !inside || lf <= 0.0 {
                        continue;
                    }
                    let uf = slice_cumulative(wf * inverseSqrt(lf), sgn, n, cos_n, sin_n) - lower;
                    // Infinitely thick: the solid reaches the hemisphere's edge on this side.
                    var ub = select(0.0, total, sgn > 0.0);
                    if thickness > 0.0 {
                        let lb = dot(wb, wb);
                        if lb > 0.0 {
                            ub = slice_cumulative(wb * inverseSqrt(lb), sgn, n, cos_n, sin_n) - lower;
                        }
                    }
                    let a = u32(clamp(round(min(uf, ub) * to_bits), 0.0, SECTORS));
                    let b = u32(clamp(round(max(uf, ub) * to_bits), 0.0, SECTORS));
                    occluded |= sector_bits(a, b);
                }
            }
        }
        let clear = 1.0 - f32(countOneBits(occluded)) / SECTORS;
        visibility += weight * proj_len * total * clear;
        if BENT_NORMALS {
            let b = bitmask_bent(occluded, n, cos_n, sin_n, lower, total);
            bent += weight * proj_len * (b.x * slice.ortho + b.y * v);
        }
    }
    if BENT_NORMALS {
        bent_normal = select(normal, normalize(bent), dot(bent, bent) > 1e-12);
    }
    let per_slice = f32(DIRECTIONS) * visibility / weights;
    return clamp(1.0 - (f32(DIRECTIONS) - per_slice) * frame.ao_scale, 0.0, 1.0);
}
