//! Multisampled depth: its resolve against the CPU mirror, a guard band, and AO that
//! matches single-sampled AO away from edges.

use super::*;

/// The raw depth of every sample of a multisampled depth texture, `[pixel * n + sample]`
/// (multisampled textures cannot be copied out, so a compute pass reads them).
fn read_samples(c: &GpuContext, m: &MsaaDepth) -> Vec<f32> {
    const SRC: &str = r#"
@group(0) @binding(0) var depth_in: texture_depth_multisampled_2d;
@group(0) @binding(1) var<storage, read_write> out: array<f32>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) g: vec3<u32>) {
    let size = textureDimensions(depth_in);
    if any(g.xy >= size) {
        return;
    }
    let n = textureNumSamples(depth_in);
    for (var s = 0u; s < n; s++) {
        out[(g.y * size.x + g.x) * n + s] = textureLoad(depth_in, vec2<i32>(g.xy), i32(s));
    }
}
"#;
    let d = &c.device;
    let bytes = (m.width * m.height * MSAA_SAMPLES * 4) as u64;
    let buffer = |usage| {
        d.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: bytes,
            usage,
            mapped_at_creation: false,
        })
    };
    let out = buffer(wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC);
    let readback = buffer(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST);
    let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: None,
        source: wgpu::ShaderSource::Wgsl(SRC.into()),
    });
    let pipeline = d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: None,
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&m.depth_view),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: out.as_entire_binding(),
            },
        ],
    });
    c.run(|enc| {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(m.width.div_ceil(8), m.height.div_ceil(8), 1);
        drop(pass);
        enc.copy_buffer_to_buffer(&out, 0, &readback, 0, bytes);
        Ok(())
    })
    .unwrap();
    bytemuck::pod_collect_to_vec(&c.map_read(&readback).unwrap())
}

/// Renders the default scene's depth with 4× MSAA at `w` × `h` and runs AO on it with
/// `options`; returns (samples, resolved raw depth, AO, frame uniforms).
fn msaa_ao(
    w: u32,
    h: u32,
    options: AoOptions,
) -> (
    Vec<f32>,
    Vec<f32>,
    Vec<f32>,
    obscura::uniforms::FrameUniforms,
) {
    let c = ctx();
    let cam = default_scene::camera();
    let raster = GBufferRenderer::new(&c.device);
    let gm = raster.upload(c, &default_scene::mesh()).unwrap();
    let ms = raster.render_msaa_depth(c, &gm, &cam, w, h).unwrap();
    let samples = read_samples(c, &ms);
    let mut ao = Ao::new(&c.device, options).unwrap();
    let input = ms.ao_input(&cam);
    let params = AoParams {
        radius: 1.0,
        ..Default::default()
    };
    c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &params))
        .unwrap();
    let f = ao.validate(&input, &params).unwrap();
    (
        samples,
        c.read_f32(ao.resolved_depth().unwrap()).unwrap(),
        c.read_f32(ao.output().unwrap()).unwrap(),
        f,
    )
}

/// MSAA depth with a guard band: the AO of the guarded view is the crop of the AO of the
/// whole widened multisampled frame (the same texture without a band, under the widened
/// projection), within 1e-4, in the default layout and the randomized one with temporal
/// accumulation; and the band changes the AO at the view's edges.
#[test]
fn msaa_depth_takes_a_guard_band() {
    let _g = lock();
    let c = ctx();
    let cam = default_scene::camera();
    let raster = GBufferRenderer::new(&c.device);
    let gm = raster.upload(c, &default_scene::mesh()).unwrap();
    let (w, h, g) = (96u32, 60u32, 16u32);
    let ms = raster
        .render_msaa_depth_guarded(c, &gm, &cam, (w, h), g)
        .unwrap();
    assert_eq!(
        (ms.width, ms.height, ms.guard_band),
        (w + 2 * g, h + 2 * g, g)
    );
    let guarded = ms.ao_input(&cam);
    let whole = obscura::AoInput {
        viewport: None,
        guard_band: 0,
        projection: cam
            .widened(h, g)
            .obscura_projection((w + 2 * g) as f32 / (h + 2 * g) as f32),
        ..guarded
    };
    let bare = obscura::AoInput {
        guard_band: 0,
        ..guarded
    };
    let params = AoParams {
        radius: 1.0,
        ..Default::default()
    };
    let randomized = AoOptions {
        mode: obscura::AoMode::Randomized,
        history: 4,
        ..Default::default()
    };
    for options in [AoOptions::default(), randomized] {
        let run = |input: &obscura::AoInput<'_>| {
            let mut ao = Ao::new(&c.device, options).unwrap();
            c.run(|enc| ao.record(&c.device, &c.queue, enc, input, &params))
                .unwrap();
            c.read_f32(ao.output().unwrap()).unwrap()
        };
        let wide = run(&whole);
        let bw = (w + 2 * g) as usize;
        let want: Vec<f32> = (0..h as usize)
            .flat_map(|y| {
                let row = (y + g as usize) * bw + g as usize;
                wide[row..row + w as usize].to_vec()
            })
            .collect();
        let got = run(&guarded);
        let d = got
            .iter()
            .zip(&want)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f32::max);
        assert!(
            d <= 1e-4,
            "{options:?}: guarded MSAA AO off the crop by {d}"
        );
        let d = run(&bare)
            .iter()
            .zip(&want)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f32::max);
        assert!(d > 0.02, "{options:?}: the band changed the AO by only {d}");
    }
}

/// The MSAA resolve equals its CPU mirror (`reference::resolve_msaa_depth`) on a 4× MSAA
/// G-buffer of the default scene, except where a linear-depth comparison sits on its
/// boundary (at most 0.1% of pixels), and the scene exercises both of its rules.
#[test]
fn msaa_depth_resolves_like_its_cpu_mirror() {
    let _g = lock();
    let (w, h) = (320, 180);
    let (samples, resolved, _, f) = msaa_ao(w, h, AoOptions::default());
    let n = MSAA_SAMPLES as usize;
    let (mut off, mut nearest, mut mean) = (0, 0, 0);
    for (i, &r) in resolved.iter().enumerate() {
        let s = &samples[i * n..(i + 1) * n];
        let want = obscura::reference::resolve_msaa_depth(&f, s);
        if (r - want).abs() > 1e-6 {
            off += 1;
        }
        let avg = s.iter().sum::<f32>() / n as f32;
        if s.iter().any(|&x| x != s[0]) {
            if want == avg {
                mean += 1;
            } else {
                nearest += 1;
            }
        }
    }
    eprintln!(
        "resolve: {off} pixels off the mirror, {nearest} silhouette, {mean} sloped, of {}",
        resolved.len()
    );
    assert!(
        off * 1000 <= resolved.len(),
        "{off} of {} pixels differ from the mirror",
        resolved.len()
    );
    assert!(
        nearest > 50 && mean > 1000,
        "silhouette pixels {nearest}, sloped surface pixels {mean}"
    );
}

/// AO from 4× MSAA depth matches AO from single-sampled depth of the same view away from
/// silhouettes: interior pixels resolve to the pixel-centre depth, so only pixels whose
/// horizon reaches a silhouette can differ. Tolerance: outside 2 px of a silhouette, mean
/// |difference| ≤ 0.005 and at most 1% of pixels beyond 0.05 (the AO's own error against
/// ray-traced truth is about 0.06 RMSE, docs/quality.md).
#[test]
fn msaa_ao_matches_single_sample_ao_away_from_edges() {
    let _g = lock();
    let (w, h) = (320, 180);
    let (samples, _, ms_ao, f) = msaa_ao(w, h, AoOptions::default());
    let cam = default_scene::camera();
    let c = ctx();
    let raster = GBufferRenderer::new(&c.device);
    let gm = raster.upload(c, &default_scene::mesh()).unwrap();
    let g = raster.render(c, &gm, &cam, w, h).unwrap();
    let mut ao = Ao::new(&c.device, AoOptions::default()).unwrap();
    let input = g.ao_input(&cam, false);
    let params = AoParams {
        radius: 1.0,
        ..Default::default()
    };
    c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &params))
        .unwrap();
    let single = c.read_f32(ao.output().unwrap()).unwrap();
    // Silhouettes: a pixel whose samples are not all one surface, dilated by 2 px.
    let lin = f.linearize();
    let n = MSAA_SAMPLES as usize;
    let edge: Vec<bool> = (0..(w * h) as usize)
        .map(|i| {
            let d: Vec<Option<f32>> = samples[i * n..(i + 1) * n]
                .iter()
                .map(|&r| lin.apply(r))
                .collect();
            let near = d.iter().flatten().fold(f32::MAX, |a, &b| a.min(b));
            let far = d.iter().flatten().fold(0.0f32, |a, &b| a.max(b));
            d.iter().any(|x| x.is_some())
                && (d.iter().any(|x| x.is_none()) || far - near > 0.02 * near)
        })
        .collect();
    let (mut count, mut sum, mut big) = (0usize, 0.0f64, 0usize);
    for y in 0..h as i32 {
        for x in 0..w as i32 {
            let near_edge = (-2..=2).any(|dy| {
                (-2..=2).any(|dx| {
                    let (u, v) = (x + dx, y + dy);
                    u >= 0
                        && v >= 0
                        && u < w as i32
                        && v < h as i32
                        && edge[(v * w as i32 + u) as usize]
                })
            });
            if near_edge {
                continue;
            }
            let i = (y * w as i32 + x) as usize;
            let diff = (ms_ao[i] - single[i]).abs();
            count += 1;
            sum += diff as f64;
            big += (diff > 0.05) as usize;
        }
    }
    let mean = sum / count as f64;
    assert!(
        count > (w * h / 2) as usize,
        "only {count} pixels away from edges"
    );
    assert!(
        mean <= 0.005,
        "mean |MSAA − single| = {mean:.4} over {count} pixels"
    );
    assert!(
        big * 100 <= count,
        "{big} of {count} pixels differ by more than 0.05"
    );
    eprintln!(
        "MSAA vs single-sample away from edges: mean {mean:.5}, {big} of {count} beyond 0.05"
    );
}
