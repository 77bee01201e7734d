// Temporal accumulation at the AO's working resolution, with camera-only reprojection
// (reverse reprojection caching: Nehab et al. 2007; Scherzer et al. 2007, seed 002):
//  1. this pixel's view position, moved into the previous frame's view space
//     (frame.prev_from_view) and projected with the previous projection;
//  2. the history (vec4(AO, frames accumulated, linear depth, packed normal)) read
//     bilinearly there, each of the four texels kept only if its surface point lies within
//     plane_tolerance(depth) of this pixel's tangent plane and its normal within
//     HISTORY_NORMAL_COS of this pixel's (else it was another surface: disocclusion, or
//     the other face of an edge), the weights renormalised;
//  3. the history AO clamped to the min/max of this frame's raw AO over the 3×3
//     neighbourhood, which spans every sampling pattern of a 2×2 tile (Karis 2014's
//     neighbourhood clamp, applied before any spatial filter so the clamp window holds
//     the sampling spread and a still camera keeps accumulating);
//  4. blended: AO = mix(history, current, 1 / frames), frames = min(history frames + 1,
//     frame.history_max): a plain average of up to history_max frames, then an
//     exponential one.
// Without valid history (first frame, cut, resize, sky, disocclusion) frames = 1, AO =
// current. Bent normals, when on, follow with the same texels and weights
// (temporal_bent.wgsl). Composed after prepared_full.wgsl or prepared_layers.wgsl and a
// temporal_out_*.wgsl (the AO alone, or packed with its geometry for the spatial denoiser).
// CPU mirror: src/reference.rs, `temporal`.

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(2) var ao_in: texture_2d<f32>;
@group(0) @binding(3) var history_in: texture_2d<f32>;
@group(0) @binding(4) var history_out: texture_storage_2d<rgba32float, write>;

// A unit normal as one float: octahedral coordinates (Meyer et al. 2010, "On
// floating-point normal vectors"), 12 bits each, q.x * 4096 + q.y < 2^24 so exact in f32.
fn pack_normal(n: vec3<f32>) -> f32 {
    var o = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    if n.z < 0.0 {
        o = (1.0 - abs(o.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), o >= vec2<f32>(0.0));
    }
    let q = round(clamp(o * 0.5 + 0.5, vec2<f32>(0.0), vec2<f32>(1.0)) * 4095.0);
    return q.x * 4096.0 + q.y;
}

fn unpack_normal(w: f32) -> vec3<f32> {
    let qx = floor(w / 4096.0);
    let o = vec2<f32>(qx, w - qx * 4096.0) / 4095.0 * 2.0 - 1.0;
    var n = vec3<f32>(o, 1.0 - abs(o.x) - abs(o.y));
    if n.z < 0.0 {
        n = vec3<f32>((1.0 - abs(n.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), n.xy >= vec2<f32>(0.0)), n.z);
    }
    return normalize(n);
}

// The history's (AO, frames) where this pixel's surface point `pos` (normal `n`) was in the
// previous frame, from the valid ones of the four nearest texels; (0, 0) when none is.
fn reprojected(pos: vec3<f32>, n: vec3<f32>) -> vec2<f32> {
    let prev = (frame.prev_from_view * vec4<f32>(pos, 1.0)).xyz;
    let prev_n = (frame.prev_from_view * vec4<f32>(n, 0.0)).xyz;
    let depth = -prev.z;
    if depth <= 0.0 {
        return vec2<f32>(0.0);
    }
    var ndc = prev.xy / frame.prev_ndc_to_view;
    if frame.perspective != 0u {
        ndc = ndc / depth;
    }
    // Pixel coordinates on the previous frame's grid (another size when the working scale
    // of Resolution::Scaled changed).
    let px = vec2<f32>(ndc.x + 1.0, 1.0 - ndc.y) * 0.5 / frame.prev_inv_size;
    let base = floor(px - 0.5);
    let f = px - 0.5 - base;
    let tol = plane_tolerance(depth);
    let size = vec2<i32>(frame.prev_size);
    var sum = vec2<f32>(0.0);
    var total = 0.0;
    for (var i = 0; i < 4; i++) {
        let o = vec2<i32>(i & 1, i >> 1u);
        let t = vec2<i32>(base) + o;
        if any(t < vec2<i32>(0)) || any(t >= size) {
            continue;
        }
        let h = textureLoad(history_in, t, 0);
        if h.z <= 0.0 {
            continue;
        }
        let q = view_position_scaled(vec2<f32>(t) + 0.5, h.z, frame.prev_ndc_to_view, frame.prev_inv_size);
        if abs(dot(q - prev, prev_n)) >= tol || dot(unpack_normal(h.w), prev_n) < HISTORY_NORMAL_COS {
            continue;
        }
        let w = select(1.0 - f.x, f.x, o.x == 1) * select(1.0 - f.y, f.y, o.y == 1);
        sum += w * h.xy;
        total += w;
        bent_history_tap(t, w);
    }
    if total < 1e-3 {
        return vec2<f32>(0.0);
    }
    return sum / total;
}

@compute @workgroup_size(WG_SIZE, WG_SIZE)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if any(gid.xy >= frame.size) {
        return;
    }
    let p = vec2<i32>(gid.xy);
    let current = textureLoad(ao_in, p, 0).x;
    let centre = prepared_at(p);
    var ao = current;
    var frames = 1.0;
    var kept = false;
    if frame.history != 0u && centre.x > 0.0 {
        let h = reprojected(view_position(vec2<f32>(p) + 0.5, centre.x), centre.yzw);
        if h.y > 0.0 {
            var lo = current;
            var hi = current;
            let size = vec2<i32>(frame.size);
            for (var i = 0; i < 9; i++) {
                let q = p + vec2<i32>(i % 3 - 1, i / 3 - 1);
                if all(q >= vec2<i32>(0)) && all(q < size) {
                    let a = textureLoad(ao_in, q, 0).x;
                    lo = min(lo, a);
                    hi = max(hi, a);
                }
            }
            frames = min(h.y + 1.0, frame.history_max);
            ao = mix(clamp(h.x, lo, hi), current, 1.0 / frames);
            kept = true;
        }
    }
    if centre.x <= 0.0 {
        frames = 0.0;
    }
    textureStore(history_out, p, vec4<f32>(ao, frames, centre.x, pack_normal(centre.yzw)));
    store_temporal(p, ao, centre);
    bent_finish(p, kept, 1.0 / max(frames, 1.0));
}
