//! `render --depth-out` and `--normals-out`: the prepared buffer's linear depth and view
//! normals as PNGs, the ones the AO read, for a scene or a depth map (cropped back from
//! the padding that centres its principal point).

use super::args::RenderArgs;
use crate::output::save_png;
use anyhow::{Context, Result};
use obscura::depth_map::Framed;
use obscura::{layout, Ao, AoInput, AoMode, AoOptions, AoParams, Denoise, GpuContext, Resolution};

/// Writes `--depth-out` and `--normals-out` of the frame `ao` recorded from `input` at
/// `size`; `crop`: the depth map's framing, whose padding is cropped away.
pub(super) fn write_prepared(
    a: &RenderArgs,
    (ctx, ao): (&GpuContext, &Ao),
    (input, params): (&AoInput<'_>, &AoParams),
    (w, h): (u32, u32),
    crop: Option<&Framed>,
) -> Result<()> {
    if a.depth_out.is_none() && a.normals_out.is_none() {
        return Ok(());
    }
    let mut prepared = read_prepared(ctx, ao, input, params, w, h)?;
    let (mut w, mut h) = (w, h);
    if let Some(f) = crop {
        let channels = (0..4)
            .map(|k| {
                f.crop(
                    &prepared
                        .iter()
                        .skip(k)
                        .step_by(4)
                        .copied()
                        .collect::<Vec<_>>(),
                )
            })
            .collect::<std::result::Result<Vec<_>, _>>()?;
        prepared = (0..channels[0].len())
            .flat_map(|i| channels.iter().map(move |c| c[i]))
            .collect();
        (w, h) = (f.width, f.height);
    }
    if let Some(path) = &a.depth_out {
        save_png(
            path,
            &depth_visual(&prepared),
            w,
            h,
            image::ExtendedColorType::L8,
        )?;
        eprintln!("wrote {}", path.display());
    }
    if let Some(path) = &a.normals_out {
        let rgb: Vec<u8> = prepared
            .chunks_exact(4)
            .flat_map(|p| {
                let sky = p[0] <= 0.0;
                [p[1], p[2], p[3]].map(|c| {
                    if sky {
                        0
                    } else {
                        ((c * 0.5 + 0.5).clamp(0.0, 1.0) * 255.0).round() as u8
                    }
                })
            })
            .collect();
        save_png(path, &rgb, w, h, image::ExtendedColorType::Rgb8)?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

/// The prepared `vec4(depth, normal)` buffer at full resolution: read directly, or
/// re-interleaved on the CPU from the deinterleaved layers (fused modes keep no full copy),
/// or, below full resolution without a full-resolution copy, prepared once more by a
/// full-resolution single pass.
fn read_prepared(
    ctx: &GpuContext,
    ao: &Ao,
    input: &obscura::AoInput<'_>,
    params: &AoParams,
    w: u32,
    h: u32,
) -> Result<Vec<f32>> {
    if let Some(view) = ao.prepared_view() {
        return Ok(ctx.read_f32(view.texture())?);
    }
    if ao.options().resolution != Resolution::Full {
        let mut full = Ao::new(
            &ctx.device,
            AoOptions {
                mode: AoMode::Randomized,
                resolution: Resolution::Full,
                denoise: Denoise::None,
                ..*ao.options()
            },
        )?;
        ctx.run(|enc| full.record(&ctx.device, &ctx.queue, enc, input, params))?;
        let view = full
            .prepared_view()
            .context("full-resolution prepared buffer missing")?;
        return Ok(ctx.read_f32(view.texture())?);
    }
    let view = ao
        .prepared_layers_view()
        .context("prepared buffer missing")?;
    let layers = ctx.read_f32(view.texture())?;
    let n = ao.options().mode.split();
    let (lw, lh) = layout::layer_size(w, h, n);
    let mut out = vec![0.0; (w * h * 4) as usize];
    for y in 0..h {
        for x in 0..w {
            let (tx, ty) = layout::layer_texel(x, y, n);
            let src = (((layout::layer_of(x, y, n) * lh + ty) * lw + tx) * 4) as usize;
            let dst = ((y * w + x) * 4) as usize;
            out[dst..dst + 4].copy_from_slice(&layers[src..src + 4]);
        }
    }
    Ok(out)
}

/// Log-scaled linear depth: nearest surface white, farthest dark grey, sky black.
fn depth_visual(prepared: &[f32]) -> Vec<u8> {
    let depths = prepared.chunks_exact(4).map(|p| p[0]);
    let (lo, hi) = depths
        .clone()
        .filter(|d| *d > 0.0)
        .fold((f32::INFINITY, 0.0f32), |(lo, hi), d| {
            (lo.min(d), hi.max(d))
        });
    let span = (hi / lo).ln().max(1e-6);
    depths
        .map(|d| {
            if d <= 0.0 {
                0
            } else {
                (255.0 - 215.0 * ((d / lo).ln() / span)).round() as u8
            }
        })
        .collect()
}
