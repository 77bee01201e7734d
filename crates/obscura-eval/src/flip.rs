//! ꟻLIP (Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström and Fairchild 2020, "ꟻLIP: A
//! Difference Evaluator for Alternating Images"), NVIDIA's perceptual difference of two
//! images, through the `nv-flip` bindings to its reference implementation. AO is compared
//! as it is shown: one grey, 8-bit sRGB, as a PNG viewer displays it. Per pixel ꟻLIP is in
//! [0, 1]; the paper recommends its mean as the one number.

/// The viewing condition: pixels per degree of visual angle. ꟻLIP's default, 67: a
/// 0.7 m wide monitor of 3840 pixels seen from 0.7 m.
pub const PIXELS_PER_DEGREE: f32 = nv_flip::DEFAULT_PIXELS_PER_DEGREE;

/// An AO image (`w` × `h`, values in [0, 1]) as displayed RGB, 8 bits per channel.
fn displayed(ao: &[f32], w: u32, h: u32) -> nv_flip::FlipImageRgb8 {
    let rgb: Vec<u8> = ao
        .iter()
        .flat_map(|v| [(v.clamp(0.0, 1.0) * 255.0).round() as u8; 3])
        .collect();
    nv_flip::FlipImageRgb8::with_data(w, h, &rgb)
}

/// The ꟻLIP error map of `test` against `reference` (`w` × `h` AO), one value per pixel.
/// Pixels outside `mask` show the reference's value in both, so they differ nowhere.
pub fn flip_map(test: &[f32], reference: &[f32], mask: &[bool], w: u32, h: u32) -> Vec<f32> {
    assert!(test.len() == (w * h) as usize && reference.len() == test.len());
    let shown: Vec<f32> = test
        .iter()
        .zip(reference)
        .zip(mask)
        .map(|((t, r), m)| if *m { *t } else { *r })
        .collect();
    let map = nv_flip::flip(
        displayed(reference, w, h),
        displayed(&shown, w, h),
        PIXELS_PER_DEGREE,
    );
    map.to_vec()
}

/// Mean of `map` over `mask` (0 when the mask is empty).
pub fn mean_over(map: &[f32], mask: &[bool]) -> f32 {
    let (s, n) = map
        .iter()
        .zip(mask)
        .filter(|(_, m)| **m)
        .fold((0.0f64, 0usize), |(s, n), (v, _)| (s + *v as f64, n + 1));
    if n == 0 {
        0.0
    } else {
        (s / n as f64) as f32
    }
}

/// Mean ꟻLIP of `test` against `reference` over `mask`.
pub fn flip(test: &[f32], reference: &[f32], mask: &[bool], w: u32, h: u32) -> f32 {
    mean_over(&flip_map(test, reference, mask, w, h), mask)
}

/// A ꟻLIP map as RGB through ꟻLIP's own colour map (magma: black is no difference,
/// yellow-white the largest).
pub fn magma(map: &[f32], w: u32, h: u32) -> Vec<u8> {
    nv_flip::FlipImageFloat::with_data(w, h, map)
        .apply_color_lut(&nv_flip::magma_lut())
        .to_vec()
}

#[cfg(test)]
mod tests {
    use super::*;

    const W: u32 = 64;
    const H: u32 = 48;

    fn image(f: impl Fn(u32, u32) -> f32) -> Vec<f32> {
        (0..W * H).map(|i| f(i % W, i / W)).collect()
    }

    /// An image against itself reads 0 on every pixel.
    #[test]
    fn identical_images_read_zero() {
        let a = image(|x, y| ((x * 7 + y * 3) % 17) as f32 / 16.0);
        let mask = vec![true; (W * H) as usize];
        let map = flip_map(&a, &a, &mask, W, H);
        assert!(
            map.iter().all(|v| *v == 0.0),
            "max {:?}",
            map.iter().copied().reduce(f32::max)
        );
    }

    /// Black against white is near ꟻLIP's largest difference (above 0.5 on the mean); a grey
    /// step of 0.2 reads more than one of 0.02, and both less than black against white.
    #[test]
    fn known_differences_order_and_bound() {
        let mask = vec![true; (W * H) as usize];
        let grey = |v: f32| image(|_, _| v);
        let black_white = flip(&grey(0.0), &grey(1.0), &mask, W, H);
        assert!(black_white > 0.5, "black against white: {black_white}");
        let small = flip(&grey(0.52), &grey(0.5), &mask, W, H);
        let large = flip(&grey(0.7), &grey(0.5), &mask, W, H);
        assert!(
            0.0 < small && small < large && large < black_white,
            "{small} {large} {black_white}"
        );
    }

    /// Stripes of ±0.1 about the reference's grey, 8 pixels wide (4 cycles per degree at 67
    /// pixels per degree, near the eye's peak contrast sensitivity), read more than a uniform
    /// offset of the same RMSE: ꟻLIP sees the pattern RMSE does not. (Stripes 2 pixels wide
    /// read less than the offset: at 17 cycles per degree the eye filters them.)
    #[test]
    fn a_pattern_reads_more_than_an_offset_of_the_same_rmse() {
        let mask = vec![true; (W * H) as usize];
        let reference = image(|_, _| 0.5);
        let stripes = image(|x, _| if (x / 8) % 2 == 0 { 0.6 } else { 0.4 });
        let offset = image(|_, _| 0.6);
        let (s, o) = (
            flip(&stripes, &reference, &mask, W, H),
            flip(&offset, &reference, &mask, W, H),
        );
        assert!(s > o, "stripes {s}, offset {o}");
    }

    /// Pixels outside the mask differ nowhere, whatever the test image holds there.
    #[test]
    fn masked_pixels_do_not_count() {
        let reference = image(|_, _| 0.5);
        let test = image(|x, _| if x < W / 2 { 0.0 } else { 0.5 });
        let mask: Vec<bool> = (0..W * H).map(|i| i % W >= W / 2).collect();
        assert_eq!(flip(&test, &reference, &mask, W, H), 0.0);
    }
}
