//! The report's pictures: AO in grey, the signed error as a heat map and ꟻLIP maps,
//! box-filtered to `--picture-scale`.

use crate::output::save_png;
use anyhow::Result;
use std::path::Path;

/// Box-filters `img` by `scale` (1/scale rounded to an integer factor).
pub(super) fn shrink(img: &[[f32; 3]], w: u32, h: u32, scale: f32) -> (Vec<[f32; 3]>, u32, u32) {
    let f = (1.0 / scale).round().max(1.0) as u32;
    let (ow, oh) = ((w / f).max(1), (h / f).max(1));
    let mut out = vec![[0.0; 3]; (ow * oh) as usize];
    for y in 0..oh {
        for x in 0..ow {
            let mut acc = [0.0; 3];
            for dy in 0..f {
                for dx in 0..f {
                    let p = img[((y * f + dy).min(h - 1) * w + (x * f + dx).min(w - 1)) as usize];
                    for c in 0..3 {
                        acc[c] += p[c];
                    }
                }
            }
            out[(y * ow + x) as usize] = acc.map(|v| v / (f * f) as f32);
        }
    }
    (out, ow, oh)
}

fn to8(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

pub(super) fn write_gray(path: &Path, img: &[f32], w: u32, h: u32, scale: f32) -> Result<()> {
    let rgb: Vec<[f32; 3]> = img.iter().map(|v| [*v; 3]).collect();
    let (s, sw, sh) = shrink(&rgb, w, h, scale);
    let px: Vec<u8> = s.iter().map(|p| to8(p[0])).collect();
    save_png(path, &px, sw, sh, image::ExtendedColorType::L8)
}

/// Signed error heat map: white = exact, red = too bright, blue = too dark (±`range`
/// saturates), grey = not compared.
pub(super) fn write_error(
    path: &Path,
    img: &[f32],
    reference: &[f32],
    mask: &[bool],
    (w, h): (u32, u32),
    range: f32,
    scale: f32,
) -> Result<()> {
    let rgb: Vec<[f32; 3]> = img
        .iter()
        .zip(reference)
        .zip(mask)
        .map(|((a, b), m)| {
            if !m {
                return [0.5; 3];
            }
            let e = ((a - b) / range).clamp(-1.0, 1.0);
            if e >= 0.0 {
                [1.0, 1.0 - e, 1.0 - e]
            } else {
                [1.0 + e, 1.0 + e, 1.0]
            }
        })
        .collect();
    let (s, sw, sh) = shrink(&rgb, w, h, scale);
    let px: Vec<u8> = s.iter().flat_map(|p| p.map(to8)).collect();
    save_png(path, &px, sw, sh, image::ExtendedColorType::Rgb8)
}

/// A ꟻLIP map in ꟻLIP's magma colours (black: no difference), grey where not compared.
pub(super) fn write_flip(
    path: &Path,
    map: &[f32],
    mask: &[bool],
    (w, h): (u32, u32),
    scale: f32,
) -> Result<()> {
    let colours = obscura_eval::flip::magma(map, w, h);
    let rgb: Vec<[f32; 3]> = colours
        .chunks_exact(3)
        .zip(mask)
        .map(|(c, m)| {
            if *m {
                [c[0], c[1], c[2]].map(|v| v as f32 / 255.0)
            } else {
                [0.5; 3]
            }
        })
        .collect();
    let (s, sw, sh) = shrink(&rgb, w, h, scale);
    let px: Vec<u8> = s.iter().flat_map(|p| p.map(to8)).collect();
    save_png(path, &px, sw, sh, image::ExtendedColorType::Rgb8)
}
