//! The prepare pass and the depth it reads: every convention, projection and format against
//! the CPU reference, given normals, depth outside its range, recentred levels, MSAA depth.

use super::*;

#[test]
fn prepare_matches_cpu_reference_for_every_convention() {
    let _g = lock();
    for projection in test_projections() {
        let lin = test_scene(&projection, W, H);
        assert!(lin.contains(&0.0), "the scene must include sky");
        for conv in [
            DepthConvention::Standard,
            DepthConvention::ReversedZ,
            DepthConvention::ReversedZInfinite,
            DepthConvention::LinearView,
        ] {
            if conv == DepthConvention::ReversedZInfinite && !projection.is_perspective() {
                continue;
            }
            let raw = encode(&projection, conv, &lin);
            let r = run_ao(
                &raw,
                W,
                H,
                projection,
                conv,
                None,
                randomized(),
                &AoParams::default(),
            );
            let cpu = reference::prepare(&r.frame, &raw, W);
            for (i, (g, c)) in r.prepared.iter().zip(&cpu).enumerate() {
                // Tolerance: depth 1e-5 relative (f32 reciprocal of a reconstructed z);
                // normals 2e-3 per component (GPU FMA and inverseSqrt vs CPU).
                let rel = (g.x - c.x).abs() / c.x.max(1e-6);
                assert!(
                    rel < 1e-5 || (g.x == 0.0 && c.x == 0.0),
                    "{conv:?} px {i}: depth {} vs {}",
                    g.x,
                    c.x
                );
                assert!(
                    (g.yzw() - c.yzw()).abs().max_element() < 2e-3,
                    "{conv:?} px {i}: {g} vs {c}"
                );
                // The prepared depth equals the analytic depth, whatever the convention.
                let truth = lin[i];
                assert!(
                    (g.x - truth).abs() <= 2e-4 * truth.max(1.0),
                    "{conv:?} px {i}: {} vs truth {truth}",
                    g.x
                );
            }
        }
    }
}

#[test]
fn given_normals_are_decoded_and_normalized() {
    let _g = lock();
    let c = ctx();
    let (w, h) = (16u32, 12u32);
    let depth = upload_r32(&vec![4.0; (w * h) as usize], w, h);
    let depth_view = depth.create_view(&Default::default());
    let n = Vec3::new(0.3, -0.4, 0.8);
    let expected = n.normalize();
    let make = |format: wgpu::TextureFormat, texel: &[u8]| {
        let data: Vec<u8> = texel
            .iter()
            .copied()
            .cycle()
            .take(texel.len() * (w * h) as usize)
            .collect();
        c.upload("test normals", &data, w, h, format)
    };
    let signed = make(
        wgpu::TextureFormat::Rgba32Float,
        bytemuck::cast_slice(&[n.x, n.y, n.z, 0.0]),
    );
    let unorm_texel = [n.x, n.y, n.z, 0.0].map(|v| ((v * 0.5 + 0.5) * 255.0).round() as u8);
    let unorm = make(wgpu::TextureFormat::Rgba8Unorm, &unorm_texel);
    // World space: the texture holds R⁻¹ n for a view rotation R (40° about a tilted axis),
    // and the prepare pass must rotate it back to n.
    let r = glam::Mat3::from_axis_angle(Vec3::new(1.0, 2.0, -0.5).normalize(), 0.7);
    let wn = r.transpose() * n;
    let world_signed = make(
        wgpu::TextureFormat::Rgba32Float,
        bytemuck::cast_slice(&[wn.x, wn.y, wn.z, 0.0]),
    );
    let world_unorm_texel =
        [wn.x, wn.y, wn.z, 0.0].map(|v| ((v * 0.5 + 0.5) * 255.0).round() as u8);
    let world_unorm = make(wgpu::TextureFormat::Rgba8Unorm, &world_unorm_texel);
    let view_from_world = r.to_cols_array_2d();
    // Tolerances: float input exact to 1e-5; 8-bit unorm input to one quantization step.
    for (tex, encoding, tol) in [
        (&signed, obscura::NormalEncoding::ViewSigned, 1e-5),
        (&unorm, obscura::NormalEncoding::ViewUnorm, 2.0 / 255.0),
        (
            &world_signed,
            obscura::NormalEncoding::WorldSigned { view_from_world },
            1e-5,
        ),
        (
            &world_unorm,
            obscura::NormalEncoding::WorldUnorm { view_from_world },
            2.0 / 255.0,
        ),
    ] {
        let view = tex.create_view(&Default::default());
        let mut ao = Ao::new(&c.device, randomized()).unwrap();
        let input = AoInput {
            normals: Some((&view, encoding)),
            ..linear_input(&depth_view, persp(w, h))
        };
        c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &AoParams::default()))
            .unwrap();
        let prepared = c.read_f32(ao.prepared_view().unwrap().texture()).unwrap();
        for p in prepared.chunks_exact(4) {
            let got = Vec3::new(p[1], p[2], p[3]);
            assert!(
                (got - expected).abs().max_element() <= tol,
                "{encoding:?}: {got} vs {expected}"
            );
            assert_eq!(p[0], 4.0);
        }
    }
}

/// Recentring puts each low-resolution depth on the surface at the texel centre: on a
/// tilted plane the half and quarter levels equal the plane's analytic depth at the texel
/// centres (the pixel centres of a half- and quarter-size image), while the raw picks do
/// not (they sit up to a pixel's slope off).
#[test]
fn recentred_levels_lie_on_the_surface() {
    let _g = lock();
    let (w, h) = (64, 40);
    let p = persp(w, h);
    let plane = [(
        Vec3::new(0.0, 0.0, -5.0),
        Vec3::new(0.0, 50f32.to_radians().sin(), 50f32.to_radians().cos()),
    )];
    let raw = ray_cast(&p, w, h, &plane, &[]);
    for recentre in [true, false] {
        let options = AoOptions {
            resolution: Resolution::Quarter,
            recentre,
            mode: AoMode::Randomized,
            ..Default::default()
        };
        let r = run_ao(
            &raw,
            w,
            h,
            p,
            DepthConvention::LinearView,
            None,
            options,
            &AoParams::default(),
        );
        for (k, level) in r.levels.iter().enumerate() {
            let f = 2u32 << k;
            let (lw, lh) = (w / f, h / f);
            let truth = ray_cast(&p, lw, lh, &plane, &[]);
            // Interior texels (border normals fall back to one-sided differences).
            let worst = (1..lh - 1)
                .flat_map(|y| (1..lw - 1).map(move |x| (y * lw + x) as usize))
                .filter(|&i| truth[i] > 0.0)
                .map(|i| (level[i].x - truth[i]).abs() / truth[i])
                .fold(0.0, f32::max);
            if recentre {
                assert!(worst < 1e-4, "level {}: relative error {worst}", k + 1);
            } else {
                assert!(
                    worst > 1e-3,
                    "level {}: raw picks should be off the centre ({worst})",
                    k + 1
                );
            }
        }
    }
}

/// Raw depth outside the convention's [0, 1] range lies in front of the near plane: it is
/// missing data, never a near occluder (Standard: z < 0; reversed: z > 1), on a plane seen
/// in perspective, for every estimator.
#[test]
fn raw_depth_outside_its_range_is_missing() {
    let _g = lock();
    let (w, h) = (48, 32);
    let p = persp(w, h);
    let params = AoParams {
        radius: 3.0,
        strength: 4.0,
        ..Default::default()
    };
    for (convention, bad) in [
        (DepthConvention::Standard, -0.5f32),
        (DepthConvention::ReversedZ, 1.5),
        (DepthConvention::ReversedZInfinite, 1.5),
    ] {
        let solid = vec![p.encode_depth(convention, 4.0); (w * h) as usize];
        let mut holed = solid.clone();
        for (i, z) in holed.iter_mut().enumerate() {
            if i % 7 == 0 {
                *z = bad;
            }
        }
        for estimator in Estimator::ALL {
            let options = AoOptions {
                estimator,
                ..randomized()
            };
            let run = |raw: &[f32]| run_ao(raw, w, h, p, convention, None, options, &params);
            let (with, without) = (run(&holed), run(&solid));
            for (i, (a, b)) in with.ao.iter().zip(&without.ao).enumerate() {
                // Tolerance 1e-4: float noise only.
                assert!(
                    a + 1e-4 >= *b,
                    "{convention:?} {estimator:?} pixel {i}: {a} with raw {bad} < {b} without"
                );
            }
            for (i, v) in holed.iter().enumerate() {
                if *v == bad {
                    assert_eq!(
                        with.prepared[i].x, 0.0,
                        "{convention:?}: raw {bad} must be missing"
                    );
                }
            }
        }
    }
}

/// A `Depth32Float` texture holding `raw`: written by a fragment shader through
/// `frag_depth`, since depth textures cannot be filled by copies.
fn upload_depth32(raw: &[f32], w: u32, h: u32) -> wgpu::Texture {
    let c = ctx();
    let src = upload_r32(raw, w, h);
    let src_view = src.create_view(&Default::default());
    let depth = c.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("test depth32"),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Depth32Float,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    let module = c.device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("write depth"),
        source: wgpu::ShaderSource::Wgsl(
            "@group(0) @binding(0) var src: texture_2d<f32>;
             @vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
                 let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
                 return vec4<f32>(uv * 2.0 - 1.0, 0.5, 1.0);
             }
             struct Out { @builtin(frag_depth) depth: f32 }
             @fragment fn fs(@builtin(position) p: vec4<f32>) -> Out {
                 return Out(textureLoad(src, vec2<i32>(p.xy), 0).x);
             }"
            .into(),
        ),
    });
    let pipeline = c
        .device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("write depth"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                buffers: &[],
                compilation_options: Default::default(),
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                targets: &[],
                compilation_options: Default::default(),
            }),
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: wgpu::TextureFormat::Depth32Float,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            multiview_mask: None,
            cache: None,
        });
    let bind = c.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: wgpu::BindingResource::TextureView(&src_view),
        }],
    });
    let depth_view = depth.create_view(&Default::default());
    c.run(|enc| {
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("write depth"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            ..Default::default()
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.draw(0..3, 0..1);
        Ok(())
    })
    .unwrap();
    depth
}

/// The same scene gives the same AO whatever encodes its depth: every convention, the
/// projection given by parameters or read from the matrix that encoded the depth (glam's
/// D3D-style matrices: an encoding independent of `Projection::encode_depth`), and depth
/// in a float (`R32Float`) or a depth (`Depth32Float`) texture, in perspective and
/// orthographic views. Reference: linear view depth with the parameter projection.
#[test]
fn every_convention_projection_and_format_gives_the_same_ao() {
    use glam::camera::rh::proj::directx as dx;
    let _g = lock();
    let c = ctx();
    let (w, h) = (128, 80);
    let params = AoParams {
        radius: 2.0,
        ..Default::default()
    };
    let options = AoOptions::default();
    let ao_of = |view: &wgpu::TextureView, projection: Projection, convention| {
        let mut ao = Ao::new(&c.device, options).unwrap();
        let input = AoInput {
            convention,
            ..linear_input(view, projection)
        };
        c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &params))
            .unwrap();
        c.read_f32(ao.output().unwrap()).unwrap()
    };
    let aspect = w as f32 / h as f32;
    let (fov, near, far) = (60f32.to_radians(), 0.1, 100.0);
    let (hh, o_near, o_far) = (4.0, 0.1, 20.0);
    let hw = hh * aspect;
    use DepthConvention as C;
    let cases = [
        (
            persp(w, h),
            vec![
                (C::Standard, dx::perspective(fov, aspect, near, far), 1.0),
                (C::ReversedZ, dx::perspective(fov, aspect, far, near), 0.0),
                (
                    C::ReversedZInfinite,
                    dx::perspective_infinite_reverse(fov, aspect, near),
                    0.0,
                ),
            ],
        ),
        (
            ortho(w, h),
            vec![
                (
                    C::Standard,
                    dx::orthographic(-hw, hw, -hh, hh, o_near, o_far),
                    1.0,
                ),
                (
                    C::ReversedZ,
                    dx::orthographic(-hw, hw, -hh, hh, o_far, o_near),
                    0.0,
                ),
            ],
        ),
    ];
    for (projection, encodings) in cases {
        let lin = test_scene(&projection, w, h);
        let lin_tex = upload_r32(&lin, w, h);
        let reference = ao_of(
            &lin_tex.create_view(&Default::default()),
            projection,
            C::LinearView,
        );
        let occluded = reference.iter().filter(|&&a| a < 0.9).count();
        assert!(
            occluded * 100 > reference.len(),
            "the scene must be occluded somewhere ({occluded} of {} pixels)",
            reference.len()
        );
        for (convention, m, sky) in encodings {
            let raw: Vec<f32> = lin
                .iter()
                .map(|&d| {
                    if d > 0.0 {
                        let clip = m * Vec4::new(0.0, 0.0, -d, 1.0);
                        clip.z / clip.w
                    } else {
                        sky
                    }
                })
                .collect();
            let from_matrix = Projection::from_matrix(m.to_cols_array_2d(), convention).unwrap();
            for (how, p) in [("parameters", projection), ("matrix", from_matrix)] {
                for format in ["R32Float", "Depth32Float"] {
                    let tex = if format == "R32Float" {
                        upload_r32(&raw, w, h)
                    } else {
                        upload_depth32(&raw, w, h)
                    };
                    let got = ao_of(&tex.create_view(&Default::default()), p, convention);
                    let what = format!("{projection:?} {convention:?} by {how}, {format}");
                    // Tolerance: depth encodings round differently, which can flip a
                    // sample at the radius boundary: mean difference 1e-3, and 99% of
                    // pixels within 0.01.
                    let diff: Vec<f32> = got
                        .iter()
                        .zip(&reference)
                        .map(|(a, b)| (a - b).abs())
                        .collect();
                    let mean = diff.iter().sum::<f32>() / diff.len() as f32;
                    let close = diff.iter().filter(|&&d| d <= 0.01).count();
                    assert!(mean <= 1e-3, "{what}: mean difference {mean}");
                    assert!(close * 100 >= diff.len() * 99, "{what}: {close} close");
                }
            }
        }
    }
}

/// A multisampled depth-format input is resolved before the prepare pass: a constant depth
/// (a plane facing the camera) resolves to itself and is unoccluded; the resolve texture
/// and its bind group are created on the first frame only; a multisampled float input is
/// a typed error. (The resolve rule against its CPU mirror, and MSAA AO against
/// single-sampled AO, are tested on a rasterised scene in obscura-scene's tests.)
#[test]
fn msaa_depth_is_resolved_once_per_size_and_float_msaa_is_refused() {
    let _g = lock();
    let c = ctx();
    let make = |format, w, h| {
        c.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("msaa test input"),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 4,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
    };
    let depth = make(wgpu::TextureFormat::Depth32Float, W, H);
    let view = depth.create_view(&Default::default());
    c.run(|enc| {
        enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("clear to a plane"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.5),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        Ok(())
    })
    .unwrap();
    let mut ao = Ao::new(&c.device, AoOptions::default()).unwrap();
    let input = AoInput {
        depth: &view,
        convention: DepthConvention::Standard,
        projection: persp(W, H),
        normals: None,
        viewport: None,
        second_layer: None,
        guard_band: 0,
        output: None,
    };
    let params = AoParams {
        radius: 1.0,
        ..Default::default()
    };
    c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &params))
        .unwrap();
    let first = ao.resource_creations();
    for _ in 0..3 {
        c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &params))
            .unwrap();
    }
    assert_eq!(
        ao.resource_creations(),
        first,
        "MSAA frames create nothing after the first"
    );
    let resolved = c.read_f32(ao.resolved_depth().unwrap()).unwrap();
    assert!(
        resolved.iter().all(|&d| d == 0.5),
        "a constant depth resolves to itself"
    );
    let out = c.read_f32(ao.output().unwrap()).unwrap();
    assert!(
        out.iter().all(|&a| a > 0.99),
        "a plane facing the camera is unoccluded"
    );
    // A larger depth texture: a new resolve texture, once.
    let big = make(wgpu::TextureFormat::Depth32Float, W + 8, H + 8);
    let big_view = big.create_view(&Default::default());
    let big_input = AoInput {
        depth: &big_view,
        projection: persp(W + 8, H + 8),
        ..input
    };
    c.run(|enc| ao.record(&c.device, &c.queue, enc, &big_input, &params))
        .unwrap();
    assert_eq!(ao.resolved_depth().unwrap().width(), W + 8);
    let float = make(wgpu::TextureFormat::R16Float, W, H);
    let float_view = float.create_view(&Default::default());
    let err = ao
        .validate(
            &AoInput {
                depth: &float_view,
                ..input
            },
            &params,
        )
        .unwrap_err();
    assert!(
        matches!(
            err,
            Error::UnsupportedFormat {
                what: "multisampled depth",
                ..
            }
        ),
        "{err}"
    );
}
