// One marched sample of a GTAO slice, shared by gtao.wgsl and bitmask.wgsl (after an entry
// fragment that provides `sample_depth`). CPU mirror: `slice_sample` and `slice_cos` in
// passes/estimators/mod.rs.

// The sample at pixel q for a slice through the origin `pos` with plane normal `axis`:
// its vector from the origin in the slice plane (pixel snapping moves samples slightly
// off the plane, where a plane's points can rise above its in-slice horizon), its pixel
// centre and its depth. ok = false off the viewport, on sky and beyond R.
struct SliceSample {
    w: vec3<f32>,
    at: vec2<f32>,
    sd: f32,
    ok: bool,
}

fn slice_sample(q: vec2<i32>, pos: vec3<f32>, axis: vec3<f32>) -> SliceSample {
    var r: SliceSample;
    r.ok = false;
    if any(q < vec2<i32>(0)) || any(q >= vec2<i32>(frame.size)) {
        return r;
    }
    r.sd = sample_depth(q);
    if r.sd <= 0.0 {
        return r;
    }
    r.at = vec2<f32>(q) + 0.5;
    let full = view_position(r.at, r.sd) - pos;
    let r2 = dot(full, full) * frame.inv_radius2;
    r.w = full - axis * dot(full, axis);
    r.ok = r2 < 1.0 && dot(r.w, r.w) > 0.0;
    return r;
}

// The cosine between an in-slice vector `w` (nonzero) and the view vector `v`.
fn slice_cos(w: vec3<f32>, v: vec3<f32>) -> f32 {
    return clamp(dot(w, v) * inverseSqrt(dot(w, w)), -1.0, 1.0);
}
