//! `obscura eval`: AO from each pass layout against ray-traced ground truth, on a scene
//! file or the standard views of the shared scenes. Writes a markdown report with
//! pictures (AO, reference, signed error) and a quality-versus-time plot, and JSON.
//!
//! `run` is the evaluation itself; the arguments are in `args`, the variants in `variants`,
//! the truth in `truth`, accumulated frames and the orbit in `orbit`, the figures of one
//! variant on one view in `rows`, and the report in `document`, `report`, `frontier`,
//! `plots` and `pictures`; `--sensor` depth is made in `sensor_depth`, and `--ssdo` runs
//! `ssdo` instead.

mod args;
mod document;
mod flicker;
mod frontier;
mod images;
mod orbit;
mod pictures;
mod plots;
mod report;
mod rows;
mod sensor_depth;
mod ssdo;
mod truth;
mod variants;

pub use args::EvalArgs;

use args::{check, FalloffArg, NoiseArg, SensorArg, TruthArg};
use document::Scored;
use frontier::{frontier_table, variant_means};
use plots::{frontier_plot, scatter};
use report::{
    bent_table, json, mixed_summary, relative_dir, sampling_bias_table, summary_table,
    temporal_table,
};
use rows::{bent_error, Row};
use sensor_depth::{linear_depth, sensor_depth};
use variants::{thickness_label, variant_list, Variants};

use crate::options::NormalSource;
use crate::output::{check_png_path, fmt_ms, write_text};
use crate::timing::{frame_ms, median, warm_up};
use crate::views::{camera_for, Job};
use anyhow::{bail, Context, Result};
use obscura::{Ao, AoInput, AoOptions, AoParams, Estimator, GpuContext, Timing};
use obscura_eval::{layers, metrics, sensor, Bvh};
use obscura_scene::{GBufferRenderer, Mesh};
use std::fmt::Write as _;
use std::time::Instant;

/// A view's AO radius: --radius, else a fixed fraction of its bounds' diagonal (the CLI's
/// default rule, `obscura::depth_map::DEFAULT_RADIUS_FRACTION`).
fn view_radius(a: &EvalArgs, bounds: &obscura_scene::Aabb) -> f32 {
    a.radius
        .unwrap_or(obscura::depth_map::DEFAULT_RADIUS_FRACTION * bounds.diagonal())
}

fn jobs(a: &EvalArgs) -> Result<Vec<Job>> {
    a.views
        .jobs()?
        .context("choose what to evaluate: --scene FILE, --view NAME or --all")
}

pub fn run(a: &EvalArgs) -> Result<()> {
    check(a)?;
    let temporal_run = a.temporal_run();
    let jobs = jobs(a)?;
    if a.ssdo {
        if temporal_run || a.falloff != FalloffArg::None || a.truth != TruthArg::Centre {
            bail!("--ssdo evaluates single frames against centre-sampled truth without falloff");
        }
        if !(0.0..=1.0).contains(&a.albedo_scale) {
            bail!("--albedo-scale must be in 0..=1 (got {})", a.albedo_scale);
        }
        return ssdo::evaluate(a, &jobs);
    }
    for p in [&a.json, &a.export_views].into_iter().flatten() {
        crate::output::check_folder(p)?;
    }
    if let Some(path) = &a.export_views {
        return images::export_views(a, &jobs, path);
    }
    let image_dirs = images::image_dirs(&a.score_images)?;
    // Every image read once before any work: a bad one fails the run before a folder is
    // made or a reference traced.
    for d in &image_dirs {
        for job in &jobs {
            images::load_view(&d.dir, &job.name, a.width, a.height)?;
        }
    }
    if let Some(dir) = &a.report {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create `{}`", dir.display()))?;
    }
    let md_path = a
        .report
        .as_ref()
        .map(|d| a.markdown.clone().unwrap_or_else(|| d.join("index.md")));
    if let Some(p) = &md_path {
        check_png_path(&p.with_extension("png"))?;
    }

    let ctx = GpuContext::new()?;
    eprintln!("adapter: {}", ctx.describe());
    let raster = GBufferRenderer::new(&ctx.device);
    let v = variant_list(a)?;
    let Variants {
        list: variants,
        scales,
        thickness_of,
        guard_of,
        samples_of,
        ..
    } = &v;
    let mut aos: Vec<Ao> = variants
        .iter()
        .map(|(_, o)| Ao::new(&ctx.device, *o))
        .collect::<Result<_, _>>()?;
    let mut estimators: Vec<Estimator> = Vec::new();
    for &e in &a.estimators {
        if !estimators.contains(&e.into()) {
            estimators.push(e.into());
        }
    }
    // One screen-space reference per estimator and guard band, and per thickness prior
    // for the bitmask (and with a second layer, for a finite prior with --second-layer).
    let mut screen_aos: Vec<(Estimator, f32, u32, bool, Ao)> = Vec::new();
    if !a.no_screen_reference {
        for &e in &estimators {
            let priors = match e {
                Estimator::Bitmask => a.priors(),
                _ => vec![obscura::DEFAULT_THICKNESS],
            };
            for t in priors {
                let layered = a.second_layer && e == Estimator::Bitmask && t.is_finite();
                for guard in a.guards() {
                    for second_layer in [false, true].into_iter().take(1 + layered as usize) {
                        let o = AoOptions {
                            second_layer,
                            ..AoOptions::screen_reference(e)
                        };
                        screen_aos.push((e, t, guard, second_layer, Ao::new(&ctx.device, o)?));
                    }
                }
            }
        }
    }
    let (w, h) = (a.width, a.height);
    let mut rows = Vec::new();
    let mut sections = String::new();
    let mut info = Vec::new();
    for job in &jobs {
        let t0 = Instant::now();
        let bytes = std::fs::read(&job.file)
            .with_context(|| format!("cannot read scene `{}`", job.file.display()))?;
        let mesh = Mesh::load(&job.file)
            .with_context(|| format!("cannot load scene `{}`", job.file.display()))?;
        let cam = camera_for(job, &mesh)?;
        let bounds = mesh.bounds().context("the scene has no triangles")?;
        let radius = view_radius(a, &bounds);
        let settings = truth::trace_settings(a, radius);
        eprintln!(
            "{}: {} triangles, radius {radius:.3}",
            job.name,
            mesh.triangle_count()
        );

        let reference = truth::reference(a, &bytes, &mesh, &cam, &settings);
        info.push((
            job.name.clone(),
            radius,
            reference.mean_std_error,
            mesh.triangle_count(),
        ));

        // Screen-space AO in each mode, timed interleaved.
        let gpu_mesh = raster.upload(&ctx, &mesh)?;
        let g = raster.render(&ctx, &gpu_mesh, &cam, w, h)?;
        let msaa = if a.msaa {
            Some(raster.render_msaa_depth(&ctx, &gpu_mesh, &cam, w, h)?)
        } else {
            None
        };
        let mut input = match &msaa {
            Some(m) => m.ao_input(&cam),
            None => g.ao_input(&cam, a.normal_source() == NormalSource::Gbuffer),
        };
        // With guard bands, the view rasterized once with the widest (clean single-sampled
        // depth; `check`), and every band's variants, 0 included, read it: a widened
        // projection moves some depths by a rounding step of Depth32Float, which alone
        // moves a view's error by up to 0.002, so the bands are compared on one raster.
        let widest = a.guards().into_iter().max().unwrap_or(0);
        let banded = (widest > 0 && !a.msaa)
            .then(|| raster.render_guarded(&ctx, &gpu_mesh, &cam, (w, h), widest))
            .transpose()?;
        // With --msaa, the multisampled depth likewise.
        let banded_msaa = (widest > 0 && a.msaa)
            .then(|| raster.render_msaa_depth_guarded(&ctx, &gpu_mesh, &cam, (w, h), widest))
            .transpose()?;
        // With --second-layer, a second layer peeled from the raster the variants read at
        // each finite prior (a renderer's pass, timed apart: the median of 5 peels).
        let mut peels: Vec<(f32, obscura_scene::DepthLayer)> = Vec::new();
        if a.second_layer {
            let layered = banded.as_ref().unwrap_or(&g);
            for t in a.priors().into_iter().filter(|t| t.is_finite()) {
                let mut ms = Vec::new();
                for _ in 0..5 {
                    let t0 = Instant::now();
                    let layer = raster.peel(&ctx, &gpu_mesh, &cam, layered, t * radius)?;
                    ms.push(t0.elapsed().as_secs_f64() * 1e3);
                    peels.retain(|p| p.0 != t);
                    peels.push((t, layer));
                }
                eprintln!(
                    "  second layer peeled at {} (median of 5, with its wait): {} ms",
                    thickness_label(t),
                    fmt_ms(median(ms))
                );
            }
        }
        let noisy = match a.sensor {
            SensorArg::None => None,
            SensorArg::Kinect => Some(sensor::Sensor::Kinect),
            SensorArg::Stereo => Some(sensor::Sensor::Stereo),
        }
        .map(|s| sensor_depth(&ctx, &g, &input, s, a.sensor_noise))
        .transpose()?;
        let mut params = AoParams {
            radius,
            ..Default::default()
        };
        // --traced-depth: the ray tracer's exact depth in place of the raster's.
        let traced = a.traced_depth.then(|| {
            let depth: Vec<f32> = reference
                .depth
                .iter()
                .map(|&z| if z > 0.0 && z.is_finite() { z } else { 0.0 })
                .collect();
            let texture = ctx.upload_r32("traced depth", &depth, w, h);
            let view = texture.create_view(&Default::default());
            (texture, view, depth)
        });
        if let Some((_, view, _)) = &traced {
            eprintln!("  depth: the ray tracer's (--traced-depth), not the raster's");
            input.depth = view;
            input.convention = obscura::DepthConvention::LinearView;
        }
        if let Some(s) = &noisy {
            input.depth = &s.view;
            input.convention = obscura::DepthConvention::LinearView;
            if a.depth_noise == NoiseArg::Known {
                params.depth_noise = s.known;
            }
        }
        if a.depth_noise == NoiseArg::Estimate
            || (a.depth_noise == NoiseArg::Auto && noisy.is_some())
        {
            let depth = match (&noisy, &traced) {
                (Some(s), _) => std::borrow::Cow::Borrowed(&s.depth),
                (None, Some(t)) => std::borrow::Cow::Borrowed(&t.2),
                (None, None) => std::borrow::Cow::Owned(linear_depth(&ctx, &g, &input)?),
            };
            // An integer encoding (Kinect-like millimetres) is known to the estimate, as
            // `render --depth` knows it of a 16-bit PNG.
            let quantum = noisy.as_ref().and_then(|s| s.quantum);
            let e = obscura::DepthNoise::estimate(&depth, w, h, &input.projection, quantum)?;
            params.depth_noise = e.model;
            eprintln!(
                "  depth noise: estimated {} (σ up to {:.3} px){}",
                obscura::depth_map::describe_noise(&e.model),
                e.sigma_px,
                match &noisy {
                    Some(s) => format!(
                        "; the sensor's {}",
                        obscura::depth_map::describe_noise(&s.known)
                    ),
                    None => String::new(),
                }
            );
        }
        // Variant i's parameters: its scale and its thickness prior.
        let of_variant = |i: usize| AoParams {
            scale: scales[i],
            thickness: thickness_of[i],
            ..params
        };
        // The input with a guard band of `guard` pixels (the view's own without bands).
        let guarded = |guard: u32| match (&banded, &banded_msaa) {
            (Some(b), _) => AoInput {
                guard_band: guard,
                ..b.ao_input(&cam, a.normal_source() == NormalSource::Gbuffer)
            },
            (None, Some(m)) => AoInput {
                guard_band: guard,
                ..m.ao_input(&cam)
            },
            (None, None) => input,
        };
        // ... with the second layer peeled at `thickness` when `second`.
        let layered = |guard: u32, thickness: f32, second: bool| AoInput {
            second_layer: peels
                .iter()
                .find(|p| second && p.0 == thickness)
                .map(|p| &p.1.view),
            ..guarded(guard)
        };
        // Variant i's input.
        let input_of = |i: usize| layered(guard_of[i], thickness_of[i], variants[i].1.second_layer);
        let mut times = vec![Vec::new(); aos.len()];
        let timing = Timing::best_for(&ctx);
        warm_up(timing, || {
            for (i, ao) in aos.iter_mut().enumerate() {
                frame_ms(&ctx, ao, &input_of(i), &of_variant(i), timing)?;
            }
            Ok(())
        })?;
        for _ in 0..a.runs {
            for (i, ao) in aos.iter_mut().enumerate() {
                times[i].push(frame_ms(&ctx, ao, &input_of(i), &of_variant(i), timing)?);
            }
        }
        let gpu_depth = ctx.read_f32(&g.depth)?;
        // Compare where both see a surface.
        let mask: Vec<bool> = reference
            .depth
            .iter()
            .zip(&gpu_depth)
            .map(|(r, g)| *r > 0.0 && *g > obscura_scene::SKY_DEPTH)
            .collect();
        let band: Vec<bool> =
            metrics::discontinuity_band(&reference.depth, w as usize, h as usize, 0.05, 2)
                .into_iter()
                .zip(&mask)
                .map(|(b, m)| b && *m)
                .collect();
        // Temporal accumulation: N frames of the still camera, one more for the flicker,
        // then an orbit of N frames ending at this camera.
        let scene = orbit::Scene {
            ctx: &ctx,
            raster: &raster,
            mesh: &gpu_mesh,
            cam: &cam,
            radius,
            widest,
        };
        let orbit::Accumulated {
            mut temporal,
            mut still_images,
            orbit_images,
            last_two,
        } = orbit::accumulate(a, &scene, &v, &mut aos, &of_variant, &input_of, &mask)?;
        // The moving camera's flicker: the orbit's last frame (this camera) against the one
        // before, reprojected, less the truth's own change (the truth traced there too).
        let orbit_flicker: Vec<Option<f32>> = if last_two.iter().any(Option::is_some) {
            let before = cam.orbit(-a.orbit_step);
            let truth_before = truth::reference(a, &bytes, &mesh, &before, &settings);
            let depths = (&reference.depth[..], &truth_before.depth[..]);
            let pairs = flicker::reproject((&cam, &before), depths, &mask, (w, h));
            let truths = (&reference.ao[..], &truth_before.ao[..]);
            last_two
                .iter()
                .map(|l| {
                    l.as_ref()
                        .map(|[b, l]| flicker::moving_flicker(&pairs, (l, b), truths))
                })
                .collect()
        } else {
            vec![None; aos.len()]
        };
        let mut screen = Vec::new();
        let several = a.priors().len() > 1;
        // An estimator's name in labels: the bitmask's with its prior when several are run,
        // and "L2" with a second layer; with its guard band when some band is above 0.
        let named = |e: Estimator, thickness: f32, guard: u32, second: bool| {
            let mut name = match e {
                Estimator::Bitmask if several => {
                    format!("bitmask {}", thickness_label(thickness))
                }
                e => e.name().to_string(),
            };
            if second {
                name = format!("{name} L2");
            }
            if a.guard_labels() {
                name = format!("{name} g{guard}");
            }
            name
        };
        for (e, thickness, guard, second, ao) in screen_aos.iter_mut() {
            let t = Instant::now();
            let p = AoParams {
                thickness: *thickness,
                ..params
            };
            let input = layered(*guard, *thickness, *second);
            ctx.run(|enc| ao.record(&ctx.device, &ctx.queue, enc, &input, &p))?;
            let out = ctx.read_f32(ao.output().context("AO output missing")?)?;
            eprintln!(
                "  {} screen-space reference: {:.1} s",
                named(*e, *thickness, *guard, *second),
                t.elapsed().as_secs_f64()
            );
            screen.push((*e, *thickness, *guard, *second, out));
        }
        let screen_of = |e: Estimator, thickness: f32, guard: u32, second: bool| {
            screen
                .iter()
                .find(|s| {
                    s.0 == e
                        && (e != Estimator::Bitmask || s.1 == thickness)
                        && s.2 == guard
                        && s.3 == second
                })
                .map(|s| &s.4)
        };
        let white = vec![1.0f32; (w * h) as usize];
        let mut results: Vec<Scored> = vec![(
            "white (no AO)".into(),
            "none".into(),
            String::new(),
            white,
            None,
            None,
        )];
        for (e, thickness, guard, second, img) in &screen {
            results.push((
                format!(
                    "{} screen-space reference",
                    named(*e, *thickness, *guard, *second)
                ),
                e.name().into(),
                "screen-reference".into(),
                img.clone(),
                None,
                None,
            ));
        }
        for (i, ao) in aos.iter().enumerate() {
            let out = match still_images[i].take() {
                Some(img) => img,
                None => ctx.read_f32(ao.output().context("AO output missing")?)?,
            };
            if let (Some(t), Some((orbit, frames))) = (temporal[i].as_mut(), &orbit_images[i]) {
                t.orbit_rmse = metrics::rmse(orbit, &reference.ao, &mask);
                // Visible for 4 frames before the last: a history of 5 frames.
                let young: Vec<bool> = frames
                    .iter()
                    .zip(&mask)
                    .map(|(f, m)| *m && (*f - 5.0).abs() < 0.5)
                    .collect();
                let count = young.iter().filter(|y| **y).count();
                // Only an orbit longer than 5 frames (and a history longer than 5) tells
                // those pixels from the ones seen since its first frame.
                if count > 0 && t.frames > 5 && a.history > 5 {
                    t.disoccluded = Some((
                        metrics::rmse(orbit, &reference.ao, &young),
                        metrics::rmse(&out, &reference.ao, &young),
                        count,
                    ));
                }
            }
            let o = variants[i].1;
            results.push((
                variants[i].0.clone(),
                o.estimator.name().into(),
                o.mode.name().into(),
                out,
                Some(median(times[i].clone())),
                Some(o),
            ));
        }
        // The bitmask's screen-space limits with renderer layers (CPU, untimed).
        if let Some(samples) = a.layer_limits {
            let t = Instant::now();
            let bvh = Bvh::new(obscura_eval::triangles(&mesh));
            let guard = a.guards().into_iter().max().unwrap_or(0);
            let thickness = a.priors()[0];
            let prior = thickness * radius;
            let deep = layers::deep_layers(&bvh, &cam, (w, h), guard, prior);
            let mut bands = vec![false];
            if guard > 0 {
                bands.push(true);
            }
            for guarded in bands {
                for r in layers::Representation::ALL {
                    let samples = (samples.0, samples.1, a.layer_jitter);
                    let img =
                        layers::layer_limit(&deep, &cam, (radius, thickness), samples, r, guarded)?;
                    let mut label = if a.layer_jitter {
                        format!("bitmask {}×{} jittered, {}", samples.0, samples.1, r.name())
                    } else {
                        format!("limit {}", r.name())
                    };
                    if guarded {
                        label = format!("{label} g{guard}");
                    }
                    results.push((label, "limit".into(), String::new(), img, None, None));
                }
            }
            eprintln!(
                "  layer limits ({}x{} samples): {:.1} s",
                samples.0,
                samples.1,
                t.elapsed().as_secs_f64()
            );
        }
        // AO made elsewhere, after the variants (untimed).
        for d in &image_dirs {
            let img = images::load_view(&d.dir, &job.name, w, h)?;
            results.push((
                d.label.clone(),
                "image".into(),
                String::new(),
                img,
                None,
                None,
            ));
        }
        // Bent normals of GTAO's and HBAO's single-frame variants (untimed; unfused, which is the same
        // work, so that the prepared normals can be read back), where they come out at full
        // resolution (not after box/tent filtering below it).
        let mut bent_of = std::collections::HashMap::new();
        for (_, (label, o)) in variants.iter().enumerate().filter(|(i, (_, o))| {
            a.bent_normals
                && guard_of[*i] == 0
                && !o.second_layer
                && o.estimator.has_bent_normals()
                && (o.resolution == obscura::Resolution::Full || !o.denoise.downsamples())
                && o.resolution != obscura::Resolution::Scaled
                && o.history == 0
        }) {
            let mut b = Ao::new(
                &ctx.device,
                AoOptions {
                    bent_normals: true,
                    fused: false,
                    ..*o
                },
            )?;
            let input = guarded(0);
            ctx.run(|enc| b.record(&ctx.device, &ctx.queue, enc, &input, &params))?;
            let bent = ctx.read_f32(b.bent_normals().context("bent normals missing")?)?;
            let prepared = b.prepared_view().context("prepared buffer missing")?;
            let prepared = ctx.read_f32(prepared.texture())?;
            let e = bent_error(&bent, &prepared, &reference, &mask);
            eprintln!(
                "  {label}: bent normals {:.1}° from the traced ones ({:.1}° where occluded), \
                 the surface normal {:.1}° ({:.1}°)",
                e.bent, e.bent_occluded, e.normal, e.normal_occluded
            );
            bent_of.insert(label.clone(), e);
        }
        let r = &reference.ao;
        // The full-resolution result of the same estimator, mode and sample choice (a
        // preset's counts follow the resolution), if evaluated. (Variant i is results row
        // first_variant + i; its guard band must match too.)
        let first_variant = 1 + screen.len();
        let full_of = |o: &AoOptions, i: usize| {
            results.iter().enumerate().find_map(|(k, r)| {
                let same = k.checked_sub(first_variant).is_some_and(|j| {
                    guard_of.get(j) == guard_of.get(i) && samples_of.get(j) == samples_of.get(i)
                });
                r.5.filter(|f| same && f.direct() && f.estimator == o.estimator && f.mode == o.mode)
                    .map(|_| &r.3)
            })
        };
        // Per scored image, its ꟻLIP map and its screen-space reference (for the pictures).
        let mut maps = Vec::new();
        for (k, (name, estimator, mode, img, ms, options)) in results.iter().enumerate() {
            // The variant's thickness prior picks the bitmask's screen-space reference.
            // (Rows after the variants are images scored: no prior.)
            let variant = k.checked_sub(first_variant);
            let thickness = variant
                .and_then(|i| thickness_of.get(i).copied())
                .unwrap_or(obscura::DEFAULT_THICKNESS);
            let guard = variant.and_then(|i| guard_of.get(i).copied()).unwrap_or(0);
            let full_rmse = options.filter(|o| !o.direct()).and_then(|o| {
                full_of(&o, variant?)
                    .map(|f| (metrics::rmse(img, f, &mask), metrics::rmse(img, f, &band)))
            });
            let screen = ms
                .and(Estimator::ALL.into_iter().find(|e| e.name() == estimator))
                .and_then(|e| {
                    let second = options.is_some_and(|o| o.second_layer);
                    screen_of(e, thickness, guard, second)
                });
            let flip_map = obscura_eval::flip::flip_map(img, r, &mask, w, h);
            let default = variant.is_some_and(|i| {
                options.is_some_and(|o| o == a.default_frame())
                    && guard == 0
                    && scales[i] == 1.0
                    && thickness == obscura::DEFAULT_THICKNESS
            });
            rows.push(Row {
                view: job.name.clone(),
                variant: name.clone(),
                estimator: estimator.clone(),
                mode: mode.clone(),
                rmse: metrics::rmse(img, r, &mask),
                bias: metrics::bias(img, r, &mask),
                ssim: metrics::ssim(img, r, w as usize, h as usize, &mask),
                flip: obscura_eval::flip::mean_over(&flip_map, &mask),
                default,
                band_rmse: metrics::rmse(img, r, &band),
                screen_rmse: screen.map(|s| metrics::rmse(img, s, &mask)),
                screen_bias: screen.map(|s| metrics::bias(img, s, &mask)),
                screen_flip: screen.map(|s| obscura_eval::flip::flip(img, s, &mask, w, h)),
                full_rmse,
                ms: *ms,
                temporal: variants
                    .iter()
                    .position(|v| &v.0 == name)
                    .and_then(|i| temporal[i]),
                orbit_flicker: variant.and_then(|i| orbit_flicker.get(i).copied().flatten()),
                bent: bent_of.get(name).copied(),
            });
            maps.push((flip_map, screen.map(Vec::as_slice)));
        }
        for row in rows.iter().filter(|x| x.view == job.name) {
            eprintln!(
                "  {:<30} RMSE {:.4}  bias {:+.4}  SSIM {:.3}  ꟻLIP {:.4}  band RMSE {:.4}  {}{}",
                row.variant,
                row.rmse,
                row.bias,
                row.ssim,
                row.flip,
                row.band_rmse,
                row.screen_rmse
                    .zip(row.screen_bias)
                    .zip(row.screen_flip)
                    .map_or(String::new(), |((m, b), f)| format!(
                        "vs screen ref {m:.4} (bias {b:+.4}, ꟻLIP {f:.4})  "
                    )),
                row.ms
                    .map_or(String::new(), |m| format!("{} ms", fmt_ms(m)))
            );
        }

        if let (Some(dir), Some(md), false) = (&a.report, &md_path, a.no_pictures) {
            let facts = document::ViewFacts {
                job,
                triangles: mesh.triangle_count(),
                radius,
                std_error: reference.mean_std_error,
                seconds: t0.elapsed().as_secs_f64(),
            };
            let scored = &results[1 + screen.len()..];
            let pictures = document::Pictures {
                truth: r,
                mask: &mask,
                scored,
                maps: &maps[1 + screen.len()..],
            };
            document::view_section(&mut sections, a, (dir, md), &facts, &pictures)?;
        }
    }

    let means = variant_means(&rows);
    let table = format!(
        "{}{}{}{}{}{}",
        mixed_summary(&rows),
        frontier_table(&means),
        sampling_bias_table(&rows),
        bent_table(&rows),
        summary_table(&rows),
        temporal_table(&rows, a)
    );
    print!("{table}");
    if let (Some(dir), Some(md)) = (&a.report, &md_path) {
        let rel = relative_dir(dir, md);
        write_text(&dir.join("quality-vs-time.svg"), &scatter(&rows, variants))?;
        if means.len() > 1 {
            write_text(&dir.join("frontier.svg"), &frontier_plot(&means))?;
        }
        let mut doc = document::header(a, &ctx, variants);
        doc.push_str(&table);
        let _ = write!(doc, "\n![quality versus time]({rel}quality-vs-time.svg)\n");
        if means.len() > 1 {
            let _ = write!(
                doc,
                "\n![the quality-versus-time frontier]({rel}frontier.svg)\n"
            );
        }
        doc.push_str("\n## Views\n");
        doc.push_str(&sections);
        write_text(md, &doc)?;
        eprintln!("wrote {}", md.display());
    }
    if let Some(p) = &a.json {
        write_text(p, &json(&rows, &info))?;
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}
