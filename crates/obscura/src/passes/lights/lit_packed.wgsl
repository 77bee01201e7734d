// The packed texel of interleaved many-light shading (LIT_PACKED_FORMAT, rgba32uint): what
// the merge (lights_merge.wgsl) needs of a tap, geometry and irradiance, in one fetch
// instead of two (the prepared texel and the lit one), decoded with a few integer
// operations (BENCHMARKS.md "Many-light shading"):
//   x: linear depth, its f32 bits (0 or NaN: sky);
//   y: the view normal's x, y and z, each (v + 1) / 2 rounded to LIT_NORMAL_MAX (10 bits),
//      low bits first; not renormalised (each component within 1/1023; 0 on sky);
//   z: m, the largest of the irradiance's r, g and b, its f32 bits (exact; an overflow
//      to infinity is kept as the largest f32);
//   w: r / m, g / m and b / m rounded to LIT_RATIO_MAX (11, 11 and 10 bits), low bits
//      first: each component within m / 4094, m / 4094 and m / 2046, whatever the range.
// CPU mirror: src/reference.rs, `pack_lit`, `unpack_lit`.

fn pack_lit(g: vec4<f32>, e: vec3<f32>) -> vec4<u32> {
    let u = clamp(g.yzw * 0.5 + 0.5, vec3<f32>(0.0), vec3<f32>(1.0));
    let n = vec3<u32>(u * LIT_NORMAL_MAX + 0.5);
    let normal = select(0u, n.x | (n.y << 10u) | (n.z << 20u), g.x > 0.0);
    // At most the largest finite f32.
    let c = min(e, vec3<f32>(bitcast<f32>(0x7f7fffffu)));
    let m = max(max(c.x, c.y), c.z);
    let q = vec3<u32>(select(vec3<f32>(0.0), c / m, m > 0.0) * LIT_RATIO_MAX + 0.5);
    return vec4<u32>(bitcast<u32>(g.x), normal, bitcast<u32>(m), q.x | (q.y << 11u) | (q.z << 22u));
}

// vec4(linear depth, view normal) of a packed texel.
fn unpack_geometry(t: vec4<u32>) -> vec4<f32> {
    let n = vec3<u32>(t.y & 0x3ffu, (t.y >> 10u) & 0x3ffu, t.y >> 20u);
    return vec4<f32>(bitcast<f32>(t.x), vec3<f32>(n) * (2.0 / LIT_NORMAL_MAX) - 1.0);
}

// The irradiance of a packed texel.
fn unpack_irradiance(t: vec4<u32>) -> vec3<f32> {
    let q = vec3<u32>(t.w & 0x7ffu, (t.w >> 11u) & 0x7ffu, t.w >> 22u);
    return bitcast<f32>(t.z) * (vec3<f32>(q) / LIT_RATIO_MAX);
}
