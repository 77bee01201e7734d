//! The 4×4 table of per-pixel sampling patterns (rotation + ray offset). The randomized
//! single pass picks `pattern[(x % 4) + 4 * (y % 4)]` per pixel, the configuration the
//! deinterleaving paper compares against (seed 000: "SSAO pass with a 4x4 random texture").
//! Deinterleaved N×N modes give layer `(i, j)` the pattern `pattern[i + 4 * j]`.

use crate::passes::constants::{IGN_SHIFT, IGN_WEIGHTS};

/// Side of the pattern tile in pixels.
pub const PATTERN_DIM: u32 = 4;
/// Number of distinct patterns.
pub const PATTERN_COUNT: usize = (PATTERN_DIM * PATTERN_DIM) as usize;

/// The 4×4 Bayer (ordered-dither) matrix, row-major: every aligned 2×2 block holds one
/// value from each quarter of 0..16, so the 2×2 deinterleaved mode, which uses the
/// top-left block, is stratified too.
const BAYER4: [u32; PATTERN_COUNT] = [0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5];

/// The rotation that maps an estimator's set of directions onto itself: π/D for GTAO's D
/// slices (each slice is a line marched both ways), 2π/D for D directions otherwise. The
/// patterns' rotations divide this sector; with 2π/D for GTAO, the 2×2 tile's four
/// rotations would fall on two pairs of nearly equal slice sets.
pub fn rotation_sector(estimator: crate::Estimator, directions: u32) -> f32 {
    let turn = match estimator {
        crate::Estimator::Gtao | crate::Estimator::Bitmask => std::f32::consts::PI,
        _ => std::f32::consts::TAU,
    };
    turn / directions.max(1) as f32
}

/// The pattern table for rotation sector `sector` ([`rotation_sector`]): entry `k = x + 4y`
/// is `(cos θ, sin θ, offset, 0)`, with θ a rotation in `[0, sector)` and `offset` the
/// fraction of one ray step by which marching starts. Rotation ranks follow the Bayer
/// matrix and offset ranks its reversed transpose, so both are stratified over the 16
/// entries and over the top-left 2×2 block.
pub fn pattern_table(sector: f32) -> [[f32; 4]; PATTERN_COUNT] {
    let n = PATTERN_COUNT as f32;
    std::array::from_fn(|k| {
        let (x, y) = (k % 4, k / 4);
        let rot = BAYER4[k] as f32;
        let off = (PATTERN_COUNT as u32 - 1 - BAYER4[x * 4 + y]) as f32;
        let theta = (rot + 0.5) / n * sector;
        [theta.cos(), theta.sin(), (off + 0.5) / n, 0.0]
    })
}

/// The per-frame shift of the patterns, in [0, 1)²: the rotation follows the base-2 van
/// der Corput sequence (radical inverse; any 2^k consecutive frames from 0 put one shift in
/// each 1/2^k of the sector), the ray offset the golden-ratio sequence (well spread for any
/// count); both start at ½ on frame 0 (no shift).
pub fn frame_shift(k: u32) -> [f32; 2] {
    let vdc = k.reverse_bits() as f64 / 4_294_967_296.0;
    const GOLDEN: f64 = 0.618_033_988_749_894_8;
    [
        (0.5 + vdc).fract() as f32,
        (0.5 + k as f64 * GOLDEN).fract() as f32,
    ]
}

/// The pattern table of frame `frame` for temporal accumulation: every entry's rotation and
/// ray offset moved by the frame's [`frame_shift`], over the whole rotation sector and offset
/// range, so each pixel on its own sees every direction and offset over frames, while
/// within a frame the entries stay as stratified as in [`pattern_table`] (they all move
/// together). Frame 0 is [`pattern_table`].
pub fn pattern_table_frame(sector: f32, frame: u32) -> [[f32; 4]; PATTERN_COUNT] {
    if frame == 0 {
        return pattern_table(sector);
    }
    let [u, v] = frame_shift(frame);
    pattern_table(sector).map(|[c, s, o, w]| {
        let theta = s.atan2(c) + (u - 0.5) * sector;
        [theta.cos(), theta.sin(), (o + v - 0.5).rem_euclid(1.0), w]
    })
}

/// The table with every entry the same fixed pattern: rotation half a sector, offset ½
/// (no jitter; [`crate::AoOptions::jitter`]).
pub fn fixed_table(sector: f32) -> [[f32; 4]; PATTERN_COUNT] {
    let theta = 0.5 * sector;
    [[theta.cos(), theta.sin(), 0.5, 0.0]; PATTERN_COUNT]
}

/// Two values in [0, 1) per pixel whose neighbours differ widely, so a small filter
/// averages them out: interleaved gradient noise ([`IGN_WEIGHTS`]) at the pixel and at the
/// pixel shifted by [`IGN_SHIFT`]. Pixels are the AO grid's, so a guard band is the crop
/// of the widened frame (and moves the noise under the view by the band). Mirrors
/// `pixel_noise` in passes/estimators/ao_layered.wgsl.
pub fn pixel_noise(x: i32, y: i32) -> [f32; 2] {
    let [a, b, c] = IGN_WEIGHTS;
    let fract = |v: f32| v - v.floor();
    let ign = |x: f32, y: f32| fract(c * fract(a * x + b * y));
    let (x, y) = (x as f32, y as f32);
    [ign(x, y), ign(x + IGN_SHIFT, y + IGN_SHIFT)]
}

/// The pattern of full-resolution pixel `(x, y)` in an N×N deinterleaved layout: its
/// layer's `base` entry turned within the layer's stratum of the rotation sector `sector`
/// (1/N² of it) and its ray offset moved within its 1/N² of a step, both by
/// [`pixel_noise`] of `(x, y)`, the AO grid's pixel. A layer's pixels
/// then march nearby directions (the layout's cache benefit) but not one set of directions,
/// whose streaks the denoiser cannot remove. Mirrors `pixel_pattern` in
/// passes/estimators/ao_layered.wgsl; `sector` 0 keeps `base`.
pub fn pixel_pattern(base: [f32; 4], x: i32, y: i32, split: u32, sector: f32) -> [f32; 4] {
    if sector == 0.0 {
        return base;
    }
    let [u, v] = pixel_noise(x, y);
    let share = 1.0 / (split * split) as f32;
    let half = 0.5 / PATTERN_COUNT as f32;
    let turn = (u * share - half) * sector;
    let (s, c) = turn.sin_cos();
    let [bc, bs, o, w] = base;
    [
        bc * c - bs * s,
        bs * c + bc * s,
        (o + v * share - half).rem_euclid(1.0),
        w,
    ]
}

/// Index into [`pattern_table`] of full-resolution pixel `(x, y)` when sampling patterns
/// repeat every `dim` pixels (4 for the randomized pass and 4×4 deinterleaving, 2 for 2×2).
pub fn pattern_index(x: u32, y: u32, dim: u32) -> usize {
    ((x % dim) + PATTERN_DIM * (y % dim)) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bins(t: &[[f32; 4]; PATTERN_COUNT], ks: &[usize], sector: f32) -> (Vec<usize>, Vec<usize>) {
        let m = ks.len() as f32;
        let mut rot = vec![0; ks.len()];
        let mut off = vec![0; ks.len()];
        for &k in ks {
            let [c, s, o, _] = t[k];
            assert!(((c * c + s * s) - 1.0).abs() < 1e-5);
            let theta = s.atan2(c);
            assert!((0.0..sector).contains(&theta), "{theta}");
            rot[(theta / sector * m) as usize] += 1;
            off[(o * m) as usize] += 1;
        }
        (rot, off)
    }

    #[test]
    fn frames_cover_the_sector_evenly() {
        let sector = std::f32::consts::TAU / 4.0;
        assert_eq!(pattern_table_frame(sector, 0), pattern_table(sector));
        // Over 16 frames one entry's rotations fall in 16 distinct sixteenths of the sector
        // and its offsets spread over the range.
        let first = pattern_table(sector)[0];
        let start = first[1].atan2(first[0]);
        let (mut rot, mut off) = ([0; 16], [0; 4]);
        for k in 0..16 {
            let [c, s, o, _] = pattern_table_frame(sector, k)[0];
            let d = ((s.atan2(c) - start) / sector + 0.5).rem_euclid(1.0);
            rot[(d * 16.0) as usize] += 1;
            assert!((0.0..1.0).contains(&o));
            off[(o * 4.0) as usize] += 1;
        }
        assert_eq!(rot, [1; 16], "{off:?}");
        assert!(off.iter().all(|&n| n >= 3), "{off:?}");
    }

    /// Every pixel of a deinterleaved layer turns its layer's pattern within the layer's own
    /// 1/N² of the sector and moves its offset within its own 1/N² of a step: the layers stay
    /// stratified, and a layer's pixels do not all march one set of directions.
    #[test]
    fn pixel_patterns_stay_in_their_layers_strata() {
        let sector = std::f32::consts::PI / 3.0;
        let t = pattern_table(sector);
        for split in [2u32, 4] {
            let share = 1.0 / (split * split) as f32;
            for layer in 0..split * split {
                let (lx, ly) = (layer % split, layer / split);
                let base = t[pattern_index(lx, ly, split)];
                let start = base[1].atan2(base[0]) - 0.5 / PATTERN_COUNT as f32 * sector;
                let o_start = base[2] - 0.5 / PATTERN_COUNT as f32;
                let mut turns = Vec::new();
                for (x, y) in (0..16).flat_map(|i| (0..16).map(move |j| (i, j))) {
                    let (px, py) = ((x * split + lx) as i32 - 9, (y * split + ly) as i32);
                    let [c, s, o, _] = pixel_pattern(base, px, py, split, sector);
                    assert!((c * c + s * s - 1.0).abs() < 1e-5);
                    let turn = (s.atan2(c) - start) / sector;
                    assert!(
                        (-1e-5..share + 1e-5).contains(&turn),
                        "{split} {layer}: {turn}"
                    );
                    let moved = (o - o_start).rem_euclid(1.0);
                    assert!(moved < share + 1e-5, "{split} {layer}: offset {moved}");
                    turns.push(turn);
                }
                // Spread over the stratum, not one direction.
                let (lo, hi) = turns
                    .iter()
                    .fold((1.0f32, 0.0f32), |(l, h), t| (l.min(*t), h.max(*t)));
                assert!(hi - lo > 0.8 * share, "{split} {layer}: {lo}..{hi}");
            }
        }
        // Without jitter (sector 0) the pattern is the layer's.
        let base = t[0];
        assert_eq!(pixel_pattern(base, 5, 7, 2, 0.0), base);
    }

    #[test]
    fn patterns_are_stratified_for_4x4_and_2x2() {
        let sector = std::f32::consts::TAU / 8.0;
        let t = pattern_table(sector);
        let all: Vec<usize> = (0..PATTERN_COUNT).collect();
        assert_eq!(bins(&t, &all, sector), (vec![1; 16], vec![1; 16]));
        let two: Vec<usize> = (0..4).map(|l| pattern_index(l % 2, l / 2, 2)).collect();
        assert_eq!(bins(&t, &two, sector), (vec![1; 4], vec![1; 4]));
    }
}
