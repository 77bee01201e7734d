//! Deinterleaved layout maths (seed 000, "Deinterleaved Texturing"): a W×H image split
//! into N×N layers, layer `(i, j)` holding the pixels with `x % N == i`, `y % N == j`.
//! Layer index `l = i + N·j`; pixel `(x, y)` sits at `(x / N, y / N)` in its layer. The
//! WGSL (`prepare_store_layers.wgsl`, `ao_layered.wgsl`, `deinterleave.wgsl`,
//! `interleave.wgsl`) uses exactly these expressions. Layers have the size of the largest
//! one, `ceil(W/N) × ceil(H/N)`; texels with no source pixel are never read.

/// Layer of full-resolution pixel `(x, y)`.
pub fn layer_of(x: u32, y: u32, n: u32) -> u32 {
    x % n + n * (y % n)
}

/// Position of pixel `(x, y)` inside its layer.
pub fn layer_texel(x: u32, y: u32, n: u32) -> (u32, u32) {
    (x / n, y / n)
}

/// Size of every layer of a `w` × `h` image.
pub fn layer_size(w: u32, h: u32, n: u32) -> (u32, u32) {
    (w.div_ceil(n), h.div_ceil(n))
}

/// The full-resolution pixel at `texel` of `layer`, or `None` when that texel is padding
/// (sizes that are not multiples of N).
pub fn full_pixel(layer: u32, texel: (u32, u32), n: u32, w: u32, h: u32) -> Option<(u32, u32)> {
    let x = texel.0 * n + layer % n;
    let y = texel.1 * n + layer / n;
    (x < w && y < h).then_some((x, y))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_and_merge_are_inverse_for_odd_sizes() {
        for n in [2, 3, 4] {
            for (w, h) in [(1919, 1079), (1281, 721), (7, 5), (1, 1), (8, 8)] {
                let (lw, lh) = layer_size(w, h, n);
                let mut seen = vec![false; (w * h) as usize];
                for l in 0..n * n {
                    for ty in 0..lh {
                        for tx in 0..lw {
                            if let Some((x, y)) = full_pixel(l, (tx, ty), n, w, h) {
                                assert_eq!(layer_of(x, y, n), l);
                                assert_eq!(layer_texel(x, y, n), (tx, ty));
                                assert!(!seen[(y * w + x) as usize], "pixel hit twice");
                                seen[(y * w + x) as usize] = true;
                            }
                        }
                    }
                }
                assert!(
                    seen.iter().all(|s| *s),
                    "n={n} {w}x{h}: a pixel has no texel"
                );
            }
        }
    }

    #[test]
    fn padding_only_where_sizes_are_not_multiples() {
        assert_eq!(layer_size(1919, 1079, 4), (480, 270));
        // 1919 = 4·479 + 3: the last texel column exists for layers i < 3 only.
        assert!(full_pixel(2, (479, 0), 4, 1919, 1079).is_some());
        assert!(full_pixel(3, (479, 0), 4, 1919, 1079).is_none());
    }
}
