//! Temporal accumulation in `eval`: each accumulated variant's still frames (and one more
//! for the flicker), then one orbit ending at the view's camera, which single frames join
//! for its last two frames.

use super::args::EvalArgs;
use super::rows::TemporalFigures;
use super::variants::Variants;
use crate::options::NormalSource;
use anyhow::{Context, Result};
use obscura::{Ao, AoInput, AoParams, GpuContext, Resolution};
use obscura_eval::metrics;
use obscura_scene::{Camera, GBufferRenderer, GpuMesh};

/// A view's scene as the orbit renders it.
pub(super) struct Scene<'a> {
    pub(super) ctx: &'a GpuContext,
    pub(super) raster: &'a GBufferRenderer,
    pub(super) mesh: &'a GpuMesh,
    pub(super) cam: &'a Camera,
    /// The AO radius (the second layer is peeled at a prior times it).
    pub(super) radius: f32,
    /// The widest guard band of the run: the orbit's frames are rasterized with it.
    pub(super) widest: u32,
}

/// What accumulation gives, per variant (`None` for single frames): the figures, the
/// still camera's last frame, and the orbit's last frame with each pixel's history count;
/// and for every variant, single frames too, the orbit's last two frames (`None` without
/// an orbit).
pub(super) struct Accumulated {
    pub(super) temporal: Vec<Option<TemporalFigures>>,
    pub(super) still_images: Vec<Option<Vec<f32>>>,
    pub(super) orbit_images: Vec<Option<(Vec<f32>, Vec<f32>)>>,
    pub(super) last_two: Vec<Option<[Vec<f32>; 2]>>,
}

/// N frames of the still camera for each accumulated variant, one more for the flicker
/// over `mask`, then an orbit of the longest count ending at this camera, each variant of
/// N frames joining it N frames before its end.
pub(super) fn accumulate<'i>(
    a: &EvalArgs,
    scene: &Scene,
    v: &Variants,
    aos: &mut [Ao],
    of_variant: &dyn Fn(usize) -> AoParams,
    input_of: &dyn Fn(usize) -> AoInput<'i>,
    mask: &[bool],
) -> Result<Accumulated> {
    let &Scene {
        ctx,
        raster,
        mesh: gpu_mesh,
        cam,
        radius,
        widest,
    } = scene;
    let Variants {
        list: variants,
        scales,
        thickness_of,
        frames_of,
        guard_of,
        ..
    } = v;
    let orbit_frames = v.orbit_frames;
    let (w, h) = (a.width, a.height);
    let mut temporal: Vec<Option<TemporalFigures>> = vec![None; aos.len()];
    let mut still_images: Vec<Option<Vec<f32>>> = vec![None; aos.len()];
    let mut orbit_images: Vec<Option<(Vec<f32>, Vec<f32>)>> = vec![None; aos.len()];
    let mut last_two: Vec<Option<[Vec<f32>; 2]>> = vec![None; aos.len()];
    if orbit_frames <= 1 {
        return Ok(Accumulated {
            temporal,
            still_images,
            orbit_images,
            last_two,
        });
    }
    let mut before_last: Vec<Option<Vec<f32>>> = vec![None; aos.len()];
    for (i, ao) in aos.iter_mut().enumerate() {
        if frames_of[i] == 1 {
            continue;
        }
        ao.reset_history();
        let p = of_variant(i);
        let input = input_of(i);
        for _ in 0..frames_of[i] {
            ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, &input, &p))?;
        }
        let still = ctx.read_f32(ao.output().context("AO output missing")?)?;
        ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, &input, &p))?;
        let next = ctx.read_f32(ao.output().context("AO output missing")?)?;
        let flicker = metrics::mean_abs_diff(&still, &next, mask);
        temporal[i] = Some(TemporalFigures {
            frames: frames_of[i],
            flicker,
            orbit_rmse: 0.0,
            disoccluded: None,
        });
        still_images[i] = Some(still);
    }
    // One orbit of the longest count, rasterized once; a variant of N frames joins
    // it N frames before its end, with a cut.
    let mut previous: Option<Camera> = None;
    for k in 0..orbit_frames {
        let c = cam.orbit(a.orbit_step * (k as f32 - (orbit_frames - 1) as f32));
        // With guard bands, the orbit's frames carry the widest band too.
        let gk = raster.render_guarded(ctx, gpu_mesh, &c, (w, h), widest)?;
        let gbuffer_normals = a.normal_source() == NormalSource::Gbuffer;
        // With --second-layer, each frame's own peel at each finite prior.
        let mut peels_k = Vec::new();
        if a.second_layer {
            for t in a.priors().into_iter().filter(|t| t.is_finite()) {
                peels_k.push((t, raster.peel(ctx, gpu_mesh, &c, &gk, t * radius)?));
            }
        }
        for (i, ao) in aos.iter_mut().enumerate() {
            // Single frames join for the last two frames (the moving camera's flicker).
            let first = orbit_frames - frames_of[i].max(2);
            if k < first {
                continue;
            }
            let motion = match previous {
                Some(p) if k > first => c.motion_since(&p),
                _ => obscura::CameraMotion::Cut,
            };
            let p = AoParams {
                motion,
                ..of_variant(i)
            };
            let second = variants[i].1.second_layer;
            let ik = AoInput {
                guard_band: guard_of[i],
                second_layer: peels_k
                    .iter()
                    .find(|p| second && p.0 == thickness_of[i])
                    .map(|p| &p.1.view),
                ..gk.ao_input(&c, gbuffer_normals)
            };
            ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, &ik, &p))?;
            if k + 2 == orbit_frames {
                before_last[i] = Some(ctx.read_f32(ao.output().context("AO output missing")?)?);
            }
        }
        previous = Some(c);
    }
    for (i, ao) in aos.iter().enumerate() {
        let last = ctx.read_f32(ao.output().context("AO output missing")?)?;
        last_two[i] = before_last[i].take().map(|b| [b, last]);
    }
    for (i, ao) in aos.iter().enumerate().filter(|(i, _)| frames_of[*i] > 1) {
        let out = last_two[i].as_ref().context("orbit's last frame missing")?[1].clone();
        // The history's frame counts at full resolution (the working texel whose
        // footprint holds the pixel). A scaled history is on the working grid of
        // a texture created at full size.
        let hist = ctx.read_f32(ao.history().context("history missing")?)?;
        let scaled = ao.options().resolution == Resolution::Scaled;
        let f = ao.options().resolution.factor();
        // With a guard band the history covers the view and the band, the view's
        // pixel c at c + band.
        let g = guard_of[i];
        let hw = (w + 2 * g).div_ceil(f);
        let texel = |c: u32| {
            if scaled {
                ((c as f32 + g as f32 + 0.5) * scales[i]) as u32
            } else {
                (c + g) / f
            }
        };
        let frames: Vec<f32> = (0..(w * h))
            .map(|p| {
                let (x, y) = (texel(p % w), texel(p / w));
                hist[((y * hw + x) * 4 + 1) as usize]
            })
            .collect();
        orbit_images[i] = Some((out, frames));
    }
    Ok(Accumulated {
        temporal,
        still_images,
        orbit_images,
        last_two,
    })
}
