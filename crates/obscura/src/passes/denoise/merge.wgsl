// The geometric weight shared by the filters that merge samples spread over an N×N tile of
// pixel classes (jitter patterns, deinterleaved layers, light subsets): the AO denoiser
// (denoise.wgsl) and the merge of interleaved many-light shading (lights_merge.wgsl).
// Composed after common.wgsl (view_position). A tap is weighted by
//   plane:  exp(-(z / tolerance)^2), z the larger of the tap's distance from the centre's
//           tangent plane and the centre's from the tap's (a crease fails one of the two);
//   normal: max(n_tap . n, 0)^8 (halves at 25 degrees), as the bilateral upsampler.
// CPU mirror: src/reference.rs, `merge_weight`.

// Weight of tap `q` (prepared `s`, not sky) for a centre at view position `pos` with
// normal `n`; `inv_tol`: 1 / plane tolerance.
fn merge_weight(pos: vec3<f32>, n: vec3<f32>, inv_tol: f32, q: vec2<i32>, s: vec4<f32>) -> f32 {
    let off = view_position(vec2<f32>(q) + 0.5, s.x) - pos;
    let z = max(abs(dot(off, n)), abs(dot(off, s.yzw))) * inv_tol;
    let c = max(dot(s.yzw, n), 0.0);
    let c2 = c * c;
    let c4 = c2 * c2;
    return exp(-z * z) * c4 * c4;
}
