//! Image error metrics over a mask of valid pixels (surfaces seen by both images):
//! RMSE, mean signed error (bias), SSIM (Wang et al. 2004: 11×11 Gaussian window,
//! σ = 1.5, C1 = 0.01², C2 = 0.03² for data in [0, 1]), and the depth-discontinuity band.

/// Root-mean-square error of `a` against `b` over `mask`.
pub fn rmse(a: &[f32], b: &[f32], mask: &[bool]) -> f32 {
    let (s, n) = masked(a, b, mask).fold((0.0f64, 0usize), |(s, n), (x, y)| {
        (s + ((x - y) as f64).powi(2), n + 1)
    });
    if n == 0 {
        0.0
    } else {
        (s / n as f64).sqrt() as f32
    }
}

/// Mean of `|a − b|` over `mask` (0 when the mask is empty).
pub fn mean_abs_diff(a: &[f32], b: &[f32], mask: &[bool]) -> f32 {
    let (s, n) = masked(a, b, mask).fold((0.0f64, 0usize), |(s, n), (x, y)| {
        (s + (x - y).abs() as f64, n + 1)
    });
    if n == 0 {
        0.0
    } else {
        (s / n as f64) as f32
    }
}

/// Mean of `a − b` over `mask` (positive: `a` is brighter, i.e. under-occludes).
pub fn bias(a: &[f32], b: &[f32], mask: &[bool]) -> f32 {
    let (s, n) = masked(a, b, mask).fold((0.0f64, 0usize), |(s, n), (x, y)| {
        (s + (x - y) as f64, n + 1)
    });
    if n == 0 {
        0.0
    } else {
        (s / n as f64) as f32
    }
}

fn masked<'a>(
    a: &'a [f32],
    b: &'a [f32],
    mask: &'a [bool],
) -> impl Iterator<Item = (f32, f32)> + 'a {
    a.iter()
        .zip(b)
        .zip(mask)
        .filter(|(_, m)| **m)
        .map(|((x, y), _)| (*x, *y))
}

/// Mean SSIM over `mask` (each pixel's SSIM from its Gaussian-weighted neighbourhood).
pub fn ssim(a: &[f32], b: &[f32], w: usize, h: usize, mask: &[bool]) -> f32 {
    const R: i32 = 5;
    const C1: f64 = 0.01 * 0.01;
    const C2: f64 = 0.03 * 0.03;
    let g: Vec<f64> = (-R..=R)
        .map(|i| (-(i * i) as f64 / (2.0 * 1.5 * 1.5)).exp())
        .collect();
    let gs: f64 = g.iter().sum();
    let g: Vec<f64> = g.iter().map(|v| v / gs).collect();
    // Separable Gaussian blur with clamped borders.
    let blur = |img: &[f64]| -> Vec<f64> {
        let mut tmp = vec![0.0; w * h];
        let mut out = vec![0.0; w * h];
        for y in 0..h {
            for x in 0..w {
                tmp[y * w + x] = (-R..=R)
                    .map(|k| {
                        g[(k + R) as usize]
                            * img[y * w + (x as i32 + k).clamp(0, w as i32 - 1) as usize]
                    })
                    .sum();
            }
        }
        for y in 0..h {
            for x in 0..w {
                out[y * w + x] = (-R..=R)
                    .map(|k| {
                        g[(k + R) as usize]
                            * tmp[(y as i32 + k).clamp(0, h as i32 - 1) as usize * w + x]
                    })
                    .sum();
            }
        }
        out
    };
    let fa: Vec<f64> = a.iter().map(|v| *v as f64).collect();
    let fb: Vec<f64> = b.iter().map(|v| *v as f64).collect();
    let prod = |p: &[f64], q: &[f64]| p.iter().zip(q).map(|(x, y)| x * y).collect::<Vec<f64>>();
    let (ma, mb) = (blur(&fa), blur(&fb));
    let (saa, sbb, sab) = (
        blur(&prod(&fa, &fa)),
        blur(&prod(&fb, &fb)),
        blur(&prod(&fa, &fb)),
    );
    let (mut s, mut n) = (0.0, 0usize);
    for i in 0..w * h {
        if !mask[i] {
            continue;
        }
        let va = saa[i] - ma[i] * ma[i];
        let vb = sbb[i] - mb[i] * mb[i];
        let cov = sab[i] - ma[i] * mb[i];
        s += ((2.0 * ma[i] * mb[i] + C1) * (2.0 * cov + C2))
            / ((ma[i] * ma[i] + mb[i] * mb[i] + C1) * (va + vb + C2));
        n += 1;
    }
    if n == 0 {
        1.0
    } else {
        (s / n as f64) as f32
    }
}

/// Pixels within `radius` pixels of a depth discontinuity: a 4-neighbour whose linear
/// depth differs by more than `rel` (relative to the nearer of the two), or a surface
/// pixel next to sky (depth ≤ 0). Silhouette halos and bleeding live here.
pub fn discontinuity_band(depth: &[f32], w: usize, h: usize, rel: f32, radius: usize) -> Vec<bool> {
    let mut edge = vec![false; w * h];
    for y in 0..h {
        for x in 0..w {
            let d = depth[y * w + x];
            for (nx, ny) in [(x + 1, y), (x, y + 1)] {
                if nx >= w || ny >= h {
                    continue;
                }
                let e = depth[ny * w + nx];
                let jump = if d <= 0.0 || e <= 0.0 {
                    (d > 0.0) != (e > 0.0)
                } else {
                    (d - e).abs() > rel * d.min(e)
                };
                if jump {
                    edge[y * w + x] = true;
                    edge[ny * w + nx] = true;
                }
            }
        }
    }
    let r = radius as i32;
    let mut band = vec![false; w * h];
    for y in 0..h as i32 {
        for x in 0..w as i32 {
            if !edge[(y * w as i32 + x) as usize] {
                continue;
            }
            for dy in -r..=r {
                for dx in -r..=r {
                    let (px, py) = (x + dx, y + dy);
                    if px >= 0 && py >= 0 && px < w as i32 && py < h as i32 {
                        band[(py * w as i32 + px) as usize] = true;
                    }
                }
            }
        }
    }
    band
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn metrics_on_images_with_known_answers() {
        let (w, h) = (32, 24);
        let a: Vec<f32> = (0..w * h)
            .map(|i| ((i * 37) % 101) as f32 / 100.0)
            .collect();
        let all = vec![true; w * h];
        assert_eq!(rmse(&a, &a, &all), 0.0);
        assert_eq!(bias(&a, &a, &all), 0.0);
        assert!((ssim(&a, &a, w, h, &all) - 1.0).abs() < 1e-6);
        // A constant offset c: RMSE = |c|, bias = c.
        let b: Vec<f32> = a.iter().map(|v| v - 0.1).collect();
        assert!((rmse(&a, &b, &all) - 0.1).abs() < 1e-6);
        assert!((bias(&a, &b, &all) - 0.1).abs() < 1e-6);
        // Half the pixels off by 0.2, the other half exact: RMSE = sqrt(0.5 · 0.04).
        let c: Vec<f32> = a
            .iter()
            .enumerate()
            .map(|(i, v)| if i % 2 == 0 { v + 0.2 } else { *v })
            .collect();
        assert!((rmse(&a, &c, &all) - (0.02f32).sqrt()).abs() < 1e-5);
        // The mask restricts: only the exact half.
        let odd: Vec<bool> = (0..w * h).map(|i| i % 2 == 1).collect();
        assert_eq!(rmse(&a, &c, &odd), 0.0);
        // Structure destroyed (inverted image) → SSIM well below 1; a constant shift of
        // a constant image keeps the structure term but loses luminance.
        let inv: Vec<f32> = a.iter().map(|v| 1.0 - v).collect();
        assert!(ssim(&a, &inv, w, h, &all) < 0.0);
        let k1 = vec![0.5f32; w * h];
        let k2 = vec![0.7f32; w * h];
        // Closed form for constants: (2·0.5·0.7 + C1) / (0.25 + 0.49 + C1).
        let expect = (0.7 + 1e-4) / (0.74 + 1e-4);
        assert!((ssim(&k1, &k2, w, h, &all) - expect).abs() < 1e-5);
    }

    #[test]
    fn band_marks_pixels_near_steps_and_sky() {
        let (w, h) = (20, 6);
        // Left half at depth 2, right half at depth 5, last column sky.
        let depth: Vec<f32> = (0..w * h)
            .map(|i| match i % w {
                x if x == w - 1 => 0.0,
                x if x < 10 => 2.0,
                _ => 5.0,
            })
            .collect();
        let band = discontinuity_band(&depth, w, h, 0.1, 1);
        for x in 0..w {
            let expected = (8..=11).contains(&x) || x >= w - 3;
            assert_eq!(band[2 * w + x], expected, "column {x}");
        }
    }
}
