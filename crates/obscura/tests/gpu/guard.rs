//! The guard band ([`obscura::AoInput::guard_band`]): the AO of a viewport with a band of
//! `G` pixels around it equals the crop of the AO of the whole widened frame (the band
//! included, through a projection widened by hand here), in every layout and resolution
//! (so the AO pass's skipping of the band beyond `GUARD_AO_MARGIN` leaves what the later
//! passes read);
//! without the band the viewport's edges differ; a band that leaves the depth texture is
//! refused; repeated frames create nothing; `Lights` take a banded frame.

use super::{caller_output, crop, ctx, lock, persp, randomized, test_scene, upload_r32, H, W};
use obscura::{
    Ao, AoInput, AoMode, AoOptions, AoParams, Denoise, Error, Estimator, Projection, Resolution,
    Viewport,
};

const G: u32 = 12;

/// `p` (a `w` × `h` viewport's) widened to the viewport and `g` pixels around it, from the
/// field of view (not from obscura's own rule).
fn widened(p: Projection, w: u32, h: u32, g: u32) -> Projection {
    let (fw, fh) = ((w + 2 * g) as f32 / w as f32, (h + 2 * g) as f32 / h as f32);
    match p {
        Projection::Perspective {
            fov_y,
            aspect,
            near,
            far,
        } => Projection::Perspective {
            fov_y: 2.0 * ((fov_y / 2.0).tan() * fh).atan(),
            aspect: aspect * fw / fh,
            near,
            far,
        },
        Projection::Orthographic {
            half_width,
            half_height,
            near,
            far,
        } => Projection::Orthographic {
            half_width: half_width * fw,
            half_height: half_height * fh,
            near,
            far,
        },
        _ => unreachable!("the two projections"),
    }
}

fn guarded_input<'a>(view: &'a wgpu::TextureView, p: Projection, g: u32) -> AoInput<'a> {
    AoInput {
        viewport: Some(Viewport {
            x: G,
            y: G,
            width: W,
            height: H,
        }),
        guard_band: g,
        second_layer: None,
        ..super::linear_input(view, p)
    }
}

/// The AO of the viewport (own output), and the `Ao` that made it.
fn run(options: AoOptions, input: &AoInput<'_>, params: &AoParams) -> (Vec<f32>, Ao) {
    let c = ctx();
    let mut ao = Ao::new(&c.device, options).unwrap();
    c.run(|enc| ao.record(&c.device, &c.queue, enc, input, params))
        .unwrap();
    let out = c.read_f32(ao.output().unwrap()).unwrap();
    (out, ao)
}

fn max_diff(a: &[f32], b: &[f32]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f32::max)
}

/// The widened frame's uniforms differ from the guarded frame's by rounding (its projection
/// goes through `tan(atan(·))`), so the two AOs agree to 1e-4, not bit for bit.
#[test]
fn guard_band_is_the_crop_of_the_widened_frame() {
    let _g = lock();
    let c = ctx();
    let (bw, bh) = (W + 2 * G, H + 2 * G);
    let projections = [
        persp(W, H),
        Projection::Orthographic {
            half_width: 3.0 * W as f32 / H as f32,
            half_height: 3.0,
            near: 0.1,
            far: 20.0,
        },
    ];
    let params = AoParams {
        radius: 1.5,
        ..Default::default()
    };
    let option_sets = [
        AoOptions::default(),
        randomized(),
        AoOptions {
            estimator: Estimator::Bitmask,
            ..randomized()
        },
        AoOptions {
            mode: AoMode::Deinterleaved4,
            fused: false,
            ..Default::default()
        },
        AoOptions {
            resolution: Resolution::Half,
            ..Default::default()
        },
        AoOptions {
            resolution: Resolution::Quarter,
            denoise: Denoise::Tent,
            ..Default::default()
        },
        AoOptions {
            resolution: Resolution::Scaled,
            ..Default::default()
        },
        AoOptions {
            denoise: Denoise::Spatial,
            history: 4,
            ..randomized()
        },
        // The output written by the AO pass (layers merged in it, or the single pass), by
        // the unfused merge, and by the temporal pass: each stores the viewport alone.
        AoOptions {
            denoise: Denoise::None,
            ..Default::default()
        },
        AoOptions {
            denoise: Denoise::None,
            ..randomized()
        },
        AoOptions {
            denoise: Denoise::None,
            fused: false,
            ..Default::default()
        },
        AoOptions {
            denoise: Denoise::None,
            history: 4,
            ..Default::default()
        },
    ];
    for p in projections {
        let wide = widened(p, W, H, G);
        let raw = test_scene(&wide, bw, bh);
        let depth = upload_r32(&raw, bw, bh);
        let view = depth.create_view(&Default::default());
        for options in option_sets {
            let what = format!("{p:?} {options:?}");
            let params = AoParams {
                scale: if options.resolution == Resolution::Scaled {
                    0.6
                } else {
                    1.0
                },
                ..params
            };
            let params = &params;
            let (whole, _) = run(options, &super::linear_input(&view, wide), params);
            let want: Vec<f32> = crop(&whole[(G * bw + G) as usize..], bw, [W, H]);
            let (got, mut ao) = run(options, &guarded_input(&view, p, G), params);
            let d = max_diff(&got, &want);
            // The bitmask's sectors are a step function: a rounding-level difference in
            // the uniforms can move one sample across a sector's edge, which changes that
            // pixel by one sector of one slice (at most 0.08 of a slice's integral, 0.027
            // of the AO with 3 slices; 1 pixel of 3,015 by 0.0085 measured with 3 × 5
            // crowded steps). Such pixels may be 0.2% of them.
            let off = got
                .iter()
                .zip(&want)
                .filter(|(g, w)| (*g - *w).abs() > 1e-4);
            let (count, limit) = if options.estimator == Estimator::Bitmask {
                (off.count(), 1.0 / 32.0)
            } else {
                (0, 1e-4)
            };
            assert!(
                d <= limit && count * 500 <= got.len(),
                "{what}: guarded AO off the widened frame's by {d} ({count} pixels above 1e-4)"
            );
            // A second frame creates no GPU object.
            let before = ao.resource_creations();
            let input = guarded_input(&view, p, G);
            c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, params))
                .unwrap();
            assert_eq!(ao.resource_creations(), before, "{what}");
            // Without the band the edges lose the occluders beyond them (the floor's
            // crease runs off the perspective view's sides).
            let (bare, bare_ao) = run(options, &guarded_input(&view, p, 0), params);
            let d = max_diff(&bare, &want);
            // The output pass drops the band itself: no texture to crop from.
            assert_eq!(
                ao.resource_creations().textures,
                bare_ao.resource_creations().textures,
                "{what}: a guard band made a texture more"
            );
            eprintln!("{what}: band changes the AO by up to {d}");
            if p.is_perspective() {
                assert!(d > 0.02, "{what}: the band changed the AO by only {d}");
            }
        }
    }
    // A caller's output receives the same AO as the library's own.
    let p = persp(W, H);
    let raw = test_scene(&widened(p, W, H, G), bw, bh);
    let depth = upload_r32(&raw, bw, bh);
    let view = depth.create_view(&Default::default());
    let target = caller_output(W, H);
    let target_view = target.create_view(&Default::default());
    let (own, _) = run(AoOptions::default(), &guarded_input(&view, p, G), &params);
    let mut ao = Ao::new(&c.device, AoOptions::default()).unwrap();
    let input = AoInput {
        output: Some(&target_view),
        ..guarded_input(&view, p, G)
    };
    c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &params))
        .unwrap();
    assert_eq!(c.read_f32(&target).unwrap(), own);
}

/// A band wider than the margin around the viewport, on any side, is refused before GPU
/// work; a guarded frame given to `Lights` is taken, and they output the viewport alone.
#[test]
fn guard_band_must_fit_the_depth_texture() {
    let _g = lock();
    let c = ctx();
    let (bw, bh) = (W + 2 * G, H + 2 * G);
    let raw = vec![2.0f32; (bw * bh) as usize];
    let depth = upload_r32(&raw, bw, bh);
    let view = depth.create_view(&Default::default());
    let ao = Ao::new(&c.device, AoOptions::default()).unwrap();
    let p = persp(W, H);
    let params = AoParams::default();
    ao.validate(&guarded_input(&view, p, G), &params).unwrap();
    assert!(matches!(
        ao.validate(&guarded_input(&view, p, G + 1), &params),
        Err(Error::InvalidViewport(_))
    ));
    let shifted = AoInput {
        viewport: Some(Viewport {
            x: G + 1,
            y: G,
            width: W,
            height: H,
        }),
        ..guarded_input(&view, p, G)
    };
    assert!(matches!(
        ao.validate(&shifted, &params),
        Err(Error::InvalidViewport(_))
    ));
    let huge = guarded_input(&view, p, u32::MAX);
    assert!(matches!(
        ao.validate(&huge, &params),
        Err(Error::InvalidViewport(_))
    ));
    // Lights take the guarded frame from the AO's prepared buffer and output the viewport
    // (tests/gpu/lights.rs checks what they store).
    let (_, ao) = run(randomized(), &guarded_input(&view, p, G), &params);
    let frame = ao.validate(&guarded_input(&view, p, G), &params).unwrap();
    let mut lights = obscura::Lights::new(&c.device, Default::default()).unwrap();
    let prepared = ao.prepared().unwrap();
    c.run(|enc| lights.record(&c.device, &c.queue, enc, prepared, &frame, &[]))
        .unwrap();
    let out = lights.output().unwrap();
    assert_eq!((out.width(), out.height()), (W, H));
}
