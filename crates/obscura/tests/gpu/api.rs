//! The library's contract: typed errors before GPU work, timed passes in order, no GPU
//! objects made per frame, the caller's output texture, the depth-map renderer.

use super::*;

#[test]
fn bad_inputs_are_typed_errors_before_gpu_work() {
    let _g = lock();
    let c = ctx();
    let tex = upload_r32(&vec![2.0; (W * H) as usize], W, H);
    let view = tex.create_view(&Default::default());
    let ao = Ao::new(&c.device, AoOptions::default()).unwrap();
    let good = linear_input(&view, persp(W, H));
    let p = AoParams::default();
    ao.validate(&good, &p).unwrap();
    let outside = AoInput {
        viewport: Some(Viewport {
            x: 10,
            y: 0,
            width: W,
            height: H,
        }),
        ..good
    };
    assert!(matches!(
        ao.validate(&outside, &p),
        Err(Error::InvalidViewport(_))
    ));
    let empty = AoInput {
        viewport: Some(Viewport {
            x: 0,
            y: 0,
            width: 0,
            height: 5,
        }),
        ..good
    };
    assert!(matches!(
        ao.validate(&empty, &p),
        Err(Error::InvalidViewport(_))
    ));
    let nan = AoInput {
        projection: Projection::Perspective {
            fov_y: f32::NAN,
            aspect: 1.0,
            near: 0.1,
            far: 10.0,
        },
        ..good
    };
    assert!(matches!(
        ao.validate(&nan, &p),
        Err(Error::InvalidProjection(_))
    ));
    let bad_params = AoParams { radius: -1.0, ..p };
    assert!(matches!(
        ao.validate(&good, &bad_params),
        Err(Error::InvalidSetting {
            field: "radius",
            ..
        })
    ));
    assert!(matches!(
        Ao::new(
            &c.device,
            AoOptions {
                directions: 0,
                ..Default::default()
            }
        ),
        Err(Error::InvalidSetting {
            field: "directions",
            ..
        })
    ));
    // A colour texture as depth, and normals of another size.
    let rgba = c.device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d {
            width: 8,
            height: 8,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8Unorm,
        usage: wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    let rgba_view = rgba.create_view(&Default::default());
    let wrong_format = AoInput {
        depth: &rgba_view,
        ..good
    };
    assert!(matches!(
        ao.validate(&wrong_format, &p),
        Err(Error::UnsupportedFormat { .. })
    ));
    let wrong_normals = AoInput {
        normals: Some((&rgba_view, obscura::NormalEncoding::ViewUnorm)),
        ..good
    };
    assert!(matches!(
        ao.validate(&wrong_normals, &p),
        Err(Error::InvalidTexture { what: "normal", .. })
    ));
    // World-space normals with a mirrored or non-finite rotation.
    let tex_normals = upload_r32(&vec![0.0; (W * H) as usize], W, H);
    let tex_normals_view = tex_normals.create_view(&Default::default());
    for m in [
        [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        [[f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        [[0.0; 3]; 3],
    ] {
        let world = AoInput {
            normals: Some((
                &tex_normals_view,
                obscura::NormalEncoding::WorldSigned { view_from_world: m },
            )),
            ..good
        };
        assert!(
            matches!(
                ao.validate(&world, &p),
                Err(Error::InvalidSetting {
                    field: "NormalEncoding::view_from_world",
                    ..
                })
            ),
            "{m:?}"
        );
    }
    // Caller outputs: wrong format, size, usage.
    let storage = |format, w, h, usage| {
        c.device
            .create_texture(&wgpu::TextureDescriptor {
                label: None,
                size: wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
            .create_view(&Default::default())
    };
    use wgpu::TextureFormat as F;
    use wgpu::TextureUsages as U;
    let cases = [
        (storage(F::Rgba8Unorm, W, H, U::STORAGE_BINDING), "format"),
        (storage(F::R32Float, W + 1, H, U::STORAGE_BINDING), "size"),
        (storage(F::R32Float, W, H, U::TEXTURE_BINDING), "usage"),
    ];
    for (out, what) in &cases {
        let bad_output = AoInput {
            output: Some(out),
            ..good
        };
        let e = ao.validate(&bad_output, &p);
        assert!(
            matches!(
                (what, &e),
                (
                    &"format",
                    Err(Error::UnsupportedFormat { what: "output", .. })
                ) | (_, Err(Error::InvalidTexture { what: "output", .. }))
            ),
            "{what}: {e:?}"
        );
    }
    // Nothing above reached the GPU, so nothing was reported there either.
    c.take_errors().unwrap();
}

#[test]
fn timed_runs_report_every_pass_in_order() {
    let _g = lock();
    let c = ctx();
    let p = persp(W, H);
    let raw = test_scene(&p, W, H);
    let tex = upload_r32(&raw, W, H);
    let view = tex.create_view(&Default::default());
    let input = linear_input(&view, p);
    let expected: [(AoOptions, &[&str]); 4] = [
        (
            AoOptions {
                estimator: Estimator::Hbao,
                ..randomized()
            },
            &["prepare_float", "hbao"],
        ),
        (
            AoOptions::default(),
            &["prepare_float_split", "gtao_layers_packed", "denoise"],
        ),
        (
            AoOptions {
                history: 8,
                ..Default::default()
            },
            &[
                "prepare_float_split",
                "gtao_layers_merge",
                "temporal_from_layers_packed",
                "denoise",
            ],
        ),
        (
            AoOptions {
                fused: false,
                denoise: Denoise::None,
                ..Default::default()
            },
            &["prepare_float", "deinterleave", "gtao_layers", "interleave"],
        ),
    ];
    for (options, labels) in expected {
        let mut ao = Ao::new(&c.device, options).unwrap();
        let wall = ao
            .run_timed(c, &input, &AoParams::default(), Timing::WallClock)
            .unwrap();
        let got: Vec<&str> = wall.iter().map(|t| t.0).collect();
        assert_eq!(got, labels);
        assert!(wall.iter().all(|t| t.1.is_finite() && t.1 >= 0.0));
        // The timestamp path runs wherever the feature exists (lavapipe reports it, though
        // its values do not bracket dispatches); without it, a typed error.
        let ts = ao.run_timed(c, &input, &AoParams::default(), Timing::Timestamps);
        if c.device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY)
        {
            let ts = ts.unwrap();
            assert_eq!(ts.iter().map(|t| t.0).collect::<Vec<_>>(), labels);
            assert!(ts.iter().all(|t| t.1.is_finite() && t.1 >= 0.0));
        } else {
            assert!(matches!(ts, Err(Error::Gpu(_))));
        }
    }
}

/// Per-frame work creates no GPU object: 100 frames at one size with the same input views
/// cost nothing after the first; a resize recreates only size-dependent objects (the same
/// number as the first frame's); a new depth view costs exactly one bind group. Counted by
/// the library itself (every creation site) and cross-checked with wgpu's live-object
/// counters where the `counters` feature is on (dev builds of this test).
#[test]
fn frames_create_no_gpu_objects() {
    let _g = lock_alone();
    let c = ctx();
    for options in [
        AoOptions::default(),
        AoOptions {
            estimator: Estimator::Sao,
            resolution: Resolution::Half,
            denoise: Denoise::Spatial,
            history: 8,
            ..Default::default()
        },
        AoOptions {
            denoise: Denoise::Spatial,
            history: 16,
            bent_normals: true,
            ..Default::default()
        },
        AoOptions {
            resolution: Resolution::Quarter,
            denoise: Denoise::Tent,
            mode: AoMode::Deinterleaved4,
            fused: false,
            ..Default::default()
        },
    ] {
        let mut ao = Ao::new(&c.device, options).unwrap();
        let at_creation = ao.resource_creations();
        let frame = |ao: &mut Ao, view: &wgpu::TextureView| {
            let input = linear_input(view, persp(W, H));
            c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &AoParams::default()))
                .unwrap();
        };
        let p = persp(W, H);
        let tex = upload_r32(&test_scene(&p, W, H), W, H);
        let view = tex.create_view(&Default::default());
        frame(&mut ao, &view);
        let after_first = ao.resource_creations();
        assert!(after_first.textures > at_creation.textures, "{options:?}");
        let live = c.device.get_internal_counters().hal;
        let live_before = (
            live.textures.read(),
            live.texture_views.read(),
            live.bind_groups.read(),
            live.buffers.read(),
        );
        for _ in 0..100 {
            frame(&mut ao, &view);
        }
        assert_eq!(
            ao.resource_creations(),
            after_first,
            "{options:?}: frames created objects"
        );
        let live = c.device.get_internal_counters().hal;
        let live_after = (
            live.textures.read(),
            live.texture_views.read(),
            live.bind_groups.read(),
            live.buffers.read(),
        );
        assert_eq!(
            live_before, live_after,
            "{options:?}: live wgpu objects changed over 100 frames"
        );
        // A new view of the same texture: one bind group, nothing else.
        let view2 = tex.create_view(&Default::default());
        frame(&mut ao, &view2);
        let d = ao.resource_creations();
        assert_eq!(
            (d.textures, d.texture_views, d.buffers, d.bind_groups),
            (
                after_first.textures,
                after_first.texture_views,
                after_first.buffers,
                after_first.bind_groups + 1
            ),
            "{options:?}: new input view"
        );
        // A resize recreates the size-dependent set once (same counts as the first frame).
        let (w2, h2) = (W + 10, H + 6);
        let p2 = persp(w2, h2);
        let tex2 = upload_r32(&test_scene(&p2, w2, h2), w2, h2);
        let view3 = tex2.create_view(&Default::default());
        let per_size = |a: ResourceCount, b: ResourceCount| {
            (
                a.textures - b.textures,
                a.texture_views - b.texture_views,
                a.bind_groups - b.bind_groups,
                a.buffers - b.buffers,
            )
        };
        let before_resize = ao.resource_creations();
        for _ in 0..3 {
            let input = linear_input(&view3, p2);
            c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &AoParams::default()))
                .unwrap();
        }
        assert_eq!(
            per_size(ao.resource_creations(), before_resize),
            per_size(after_first, at_creation),
            "{options:?}: a resize recreates exactly the size-dependent objects, once"
        );
    }
}

/// A caller-provided output receives exactly the AO the library writes to its own
/// texture, in every layout and resolution, and then the library creates no output of its
/// own.
#[test]
fn caller_output_receives_the_same_ao() {
    let _g = lock();
    let c = ctx();
    let p = persp(W, H);
    let raw = test_scene(&p, W, H);
    let depth = upload_r32(&raw, W, H);
    let depth_view = depth.create_view(&Default::default());
    let params = AoParams {
        radius: 1.5,
        ..Default::default()
    };
    let target = caller_output(W, H);
    let target_view = target.create_view(&Default::default());
    for options in [
        randomized(),
        AoOptions::default(),
        AoOptions {
            fused: false,
            ..Default::default()
        },
        AoOptions {
            resolution: Resolution::Half,
            ..Default::default()
        },
        AoOptions {
            denoise: Denoise::Spatial,
            ..randomized()
        },
        AoOptions {
            history: 4,
            ..Default::default()
        },
    ] {
        let own = {
            let mut ao = Ao::new(&c.device, options).unwrap();
            let input = linear_input(&depth_view, p);
            c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &params))
                .unwrap();
            c.read_f32(ao.output().unwrap()).unwrap()
        };
        let mut ao = Ao::new(&c.device, options).unwrap();
        let input = AoInput {
            output: Some(&target_view),
            ..linear_input(&depth_view, p)
        };
        c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &params))
            .unwrap();
        assert_eq!(c.read_f32(&target).unwrap(), own, "{options:?}");
        assert!(ao.output().is_none(), "{options:?}: no library output made");
    }
}

/// The library's depth-map path on the GPU (`obscura::depth_map::Renderer`, what the
/// Python package runs): an off-centre principal point is padded and cropped back, a
/// fronto-parallel wall is unoccluded, a 90° valley darkens at its crease, and the input
/// texture kept between maps of one size is refilled, never stale.
#[test]
fn depth_map_renderer_pads_crops_and_refills() {
    use obscura::depth_map::{DepthMap, Intrinsics, Renderer};
    let _g = lock();
    let (w, h) = (48u32, 36u32);
    let k = Intrinsics {
        fx: 48.0,
        fy: 48.0,
        cx: 20.3,
        cy: 14.8,
        width: w,
        height: h,
    };
    // View depth d = 3 - |X|, X = (u - cx) / fx · d: walls at 45° meeting at u = cx.
    let valley: Vec<f32> = (0..w * h)
        .map(|i| 3.0 / (1.0 + ((i % w) as f32 - k.cx).abs() / k.fx))
        .collect();
    let frame = |depth: Vec<f32>| {
        DepthMap::from_float(w, h, depth)
            .unwrap()
            .frame(&k)
            .unwrap()
    };
    let (wall, valley) = (frame(vec![2.0; (w * h) as usize]), frame(valley));
    assert_ne!(wall.pad, [0; 4], "the principal point is off-centre");
    let mut r = Renderer::new(ctx(), AoOptions::default()).unwrap();
    let params = AoParams {
        radius: 0.3,
        ..Default::default()
    };
    let at = |ao: &[f32], u: u32| {
        (4..h - 4).map(|y| ao[(y * w + u) as usize]).sum::<f32>() / (h - 8) as f32
    };
    let first = r.render(ctx(), &valley, None, &params, 1).unwrap();
    assert_eq!(first.len(), (w * h) as usize);
    let crease = at(&first, 20);
    let walls = (at(&first, 3) + at(&first, 44)) / 2.0;
    assert!(
        crease < walls - 0.1,
        "crease {crease} against walls {walls}"
    );
    let flat = r.render(ctx(), &wall, None, &params, 1).unwrap();
    assert!(
        flat.iter().all(|&a| a > 0.98),
        "{:?}",
        flat.iter().cloned().fold(1.0, f32::min)
    );
    let again = r.render(ctx(), &valley, None, &params, 1).unwrap();
    assert_eq!(first, again);
}
