// sphere.wgsl's chords read by Volumetric Obscurance's area integral (Loos & Sloan, I3D
// 2010; seed 002: "a mip-map of depth average and variance ... sample the mip-map level in
// which a texel covers about the same amount of screen-space"). Each of the DIRECTIONS ×
// STEPS samples stands for 1/(DIRECTIONS × STEPS) of the sphere's screen disk and reads the
// moments (passes/pyramid/moments.wgsl) of the largest texels that fit in that area, so the disk
// is covered instead of point-sampled. The depths in the texel's footprint are taken as
// uniform over mean ± sqrt(3) σ, the uniform distribution with that mean and variance (our
// choice: no tails, unlike a normal distribution's, and in closed form; on a bimodal
// footprint, a silhouette, it spreads depth between the two surfaces and past them); the
// chord's expected occupied length over it is integrated exactly, times the footprint's
// non-sky fraction. Where a sample's share is under 4 px² (level 0) it is
// VO's line integral exactly. CPU mirror: src/reference.rs, `sphere_pixel` with `area`.

@group(0) @binding(3) var moments: texture_2d<f32>;

// The largest moments level of this frame's grid whose texel area, 4^level, fits in a
// sample's share of the disk of screen radius `rs_px` (nearest in log2 was tried: 0.1614
// against 0.1541 mean RMSE at the low preset on the shared views, the coarser texels mixing
// silhouettes); level L of the full-resolution buffer is level L - pyramid_offset of this
// grid, and is the texture's mip L - 1.
fn sample_level(rs_px: f32) -> i32 {
    let share = 0.5 * TAU * rs_px * rs_px / f32(DIRECTIONS * STEPS);
    let most = max(i32(textureNumLevels(moments)) - i32(frame.pyramid_offset), 0);
    // floor(log2(share) / 2), exactly (as SAO's level): the leading bit of floor(share).
    return min(i32(firstLeadingBit(u32(max(share, 1.0)))) >> 1u, most);
}

// E[max(z - c, 0)] for z uniform on [lo, hi] (a point where lo = hi).
fn expected_ramp(lo: f32, hi: f32, c: f32) -> f32 {
    if hi <= c {
        return 0.0;
    }
    if lo >= c {
        return 0.5 * (lo + hi) - c;
    }
    let x = hi - c;
    return x * x / (2.0 * (hi - lo));
}

// Where the chord of the sample at pixel `q` runs: the centre of the moments texel it reads
// (2^level pixels of this grid wide), so that the chord and its depths cover one area.
fn chord_point(q: vec2<i32>, level: i32) -> vec2<f32> {
    if level == 0 {
        return vec2<f32>(q) + 0.5;
    }
    let side = f32(1 << u32(level));
    return (vec2<f32>(q >> vec2<u32>(u32(level))) + 0.5) * side;
}

fn chord_occupied(q: vec2<i32>, level: i32, dc: f32, h: f32) -> f32 {
    if level == 0 {
        return line_occupied(q, dc, h);
    }
    let mip = u32(level) + frame.pyramid_offset - 1u;
    // Mip sizes from the base size (wgpu's rule; see sao.wgsl).
    let size = max(vec2<i32>(textureDimensions(moments)) >> vec2<u32>(mip), vec2<i32>(1));
    let m = textureLoad(moments, min(q >> vec2<u32>(u32(level)), size - 1), mip);
    if m.x <= 0.0 {
        return 0.0;
    }
    // occupied_length(z) = min(a, z + T) - max(z, b), clipped at 0, with a = dc + h,
    // b = dc - h, T the thickness, is r(z - b + T) - r(z - a + T) - r(z - b) + r(z - a)
    // with r(x) = max(x, 0): its expectation is the same sum of expected ramps.
    let w = sqrt(3.0 * max(m.z, 0.0));
    let lo = m.y - w;
    let hi = m.y + w;
    let t = SPHERE_THICKNESS * frame.radius;
    let a = dc + h;
    let b = dc - h;
    let e = expected_ramp(lo, hi, b - t) - expected_ramp(lo, hi, a - t) - expected_ramp(lo, hi, b)
        + expected_ramp(lo, hi, a);
    return m.x * clamp(e, 0.0, 2.0 * h);
}
