//! The 4×4 table of per-pixel sampling patterns (rotation + ray offset). The randomized
//! single pass picks `pattern[(x % 4) + 4 * (y % 4)]` per pixel, the configuration the
//! deinterleaving paper compares against (seed 000: "SSAO pass with a 4x4 random texture").

/// Side of the pattern tile in pixels.
pub const PATTERN_DIM: u32 = 4;
/// Number of distinct patterns.
pub const PATTERN_COUNT: usize = (PATTERN_DIM * PATTERN_DIM) as usize;

/// Deterministic pseudo-random permutation of `0..PATTERN_COUNT` (splitmix64-driven
/// Fisher–Yates), so the table is the same on every run and machine.
fn permutation(seed: u64) -> [usize; PATTERN_COUNT] {
    let mut state = seed;
    let mut next = || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    let mut p: [usize; PATTERN_COUNT] = std::array::from_fn(|i| i);
    for i in (1..PATTERN_COUNT).rev() {
        let j = (next() % (i as u64 + 1)) as usize;
        p.swap(i, j);
    }
    p
}

/// The pattern table for `directions` directions: entry `k` is
/// `(cos θ_k, sin θ_k, offset_k, 0)`, with θ_k a rotation in `[0, 2π/directions)` and
/// `offset_k` the fraction of one ray step by which marching starts. Rotations and
/// offsets are each stratified over the 16 entries (one per 1/16 interval), so every 4×4
/// tile covers the angle between directions and the step evenly.
pub fn pattern_table(directions: u32) -> [[f32; 4]; PATTERN_COUNT] {
    let rot = permutation(0x0b5c_u64);
    let off = permutation(0xa0_5eed_u64);
    let sector = std::f32::consts::TAU / directions.max(1) as f32;
    std::array::from_fn(|k| {
        let n = PATTERN_COUNT as f32;
        let theta = (rot[k] as f32 + 0.5) / n * sector;
        [theta.cos(), theta.sin(), (off[k] as f32 + 0.5) / n, 0.0]
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patterns_are_stratified_unit_rotations() {
        let t = pattern_table(8);
        let mut rot_bins = [0; PATTERN_COUNT];
        let mut off_bins = [0; PATTERN_COUNT];
        let sector = std::f32::consts::TAU / 8.0;
        for [c, s, o, _] in t {
            assert!(((c * c + s * s) - 1.0).abs() < 1e-5);
            let theta = s.atan2(c);
            assert!((0.0..sector).contains(&theta), "{theta}");
            rot_bins[(theta / sector * PATTERN_COUNT as f32) as usize] += 1;
            off_bins[(o * PATTERN_COUNT as f32) as usize] += 1;
        }
        assert_eq!(rot_bins, [1; PATTERN_COUNT]);
        assert_eq!(off_bins, [1; PATTERN_COUNT]);
    }
}
