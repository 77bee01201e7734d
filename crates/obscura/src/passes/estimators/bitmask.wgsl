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
// off-screen samples are ignored. The sectors are equal steps of a pseudo-angle, which
// costs a division where an angle costs an arc cosine (`sector_of`). A slice's
// visibility is its cosine-weighted integral (Jimenez et al. 2016, eq. 10) less that over
// its runs of occluded sectors, exact between sector edges (`sectors_integral`), so with
// infinite thickness the estimate is GTAO's with each horizon rounded to the nearest
// sector edge; the rounding has no sign. Slice weights and the final mapping are GTAO's;
// so is the bent normal, integrated over the clear runs (`bitmask_bent`). With a second
// depth layer (AoOptions::second_layer) a sample is two solids, the second from the
// surface behind the first (second_layer.wgsl). CPU mirror: passes/estimators/bitmask.rs,
// `bitmask_pixel`.

override DIRECTIONS: u32 = 4u;
override STEPS: u32 = 4u;
override MARCH_EXPONENT: f32 = 1.0;
override BENT_NORMALS: bool = false;

const SECTORS: f32 = 32.0;

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

// A slice's sectors: SECTORS bits from the normal's hemisphere edge n - pi/2 (bit 0) to
// n + pi/2, in equal steps of the pseudo-angle p = a / (|a| + b) of a direction with
// components a along the tangent (toward the edge n + pi/2) and b along the projected
// normal. p runs monotonically from -1 to 1 and costs one division where the angle costs
// an arc cosine; a sector spans 3.6 degrees at the normal and the edges, 7.2 halfway.
// The position (0 to SECTORS) of in-slice direction w, (ortho, V) coordinates, on side s;
// below the hemisphere a direction takes its side's edge. Mirror: `sector_of`.
fn sector_of(w: vec2<f32>, s: f32, tangent: vec2<f32>, normal2: vec2<f32>) -> f32 {
    let ws = vec2<f32>(s * abs(w.x), w.y);
    let a = dot(ws, tangent);
    let b = dot(ws, normal2);
    let p = select(a / (abs(a) + b), s, b <= 0.0);
    return (p + 1.0) * (0.5 * SECTORS);
}

// The slice angle of sector edge k (0 to SECTORS): direction (p, 1 - |p|) in (tangent,
// normal) coordinates. Mirror: `edge_angle`.
fn edge_angle(k: u32, n: f32) -> f32 {
    let p = f32(k) * (2.0 / SECTORS) - 1.0;
    return n + atan2(p, 1.0 - abs(p));
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
        sum += slice_at(edge_angle(r.y, n), n, cos_n, sin_n) - slice_at(edge_angle(r.x, n), n, cos_n, sin_n);
        bits &= ~sector_bits(r.x, r.y);
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
        bent += bent_at(edge_angle(r.y, n), cos_n, sin_n) - bent_at(edge_angle(r.x, n), cos_n, sin_n);
        bits &= ~sector_bits(r.x, r.y);
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
        // The slice's integral runs from D(n - pi/2) to D(n + pi/2).
        let total = slice_edge(1.0, n, cos_n, sin_n) - slice_edge(-1.0, n, cos_n, sin_n);
        let tangent = vec2<f32>(cos_n, -sin_n);
        let normal2 = vec2<f32>(sin_n, cos_n);
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
                    let uf = sector_of(wf, sgn, tangent, normal2);
                    // Infinitely thick: the solid reaches the hemisphere's edge on this side.
                    var ub = select(0.0, SECTORS, sgn > 0.0);
                    if thickness > 0.0 && dot(wb, wb) > 0.0 {
                        ub = sector_of(wb, sgn, tangent, normal2);
                    }
                    let a = u32(clamp(round(min(uf, ub)), 0.0, SECTORS));
                    let b = u32(clamp(round(max(uf, ub)), 0.0, SECTORS));
                    occluded |= sector_bits(a, b);
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
