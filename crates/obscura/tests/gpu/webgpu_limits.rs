//! Every option combination runs on a device limited to WebGPU's default limits (what a
//! browser grants without asking), with no validation error. It makes its own device, with
//! those limits.

use obscura::lights::LIGHTS_MAX;
use obscura::{
    Ao, AoMode, AoOptions, AoParams, Denoise, DepthDownsample, Estimator, Lights, LightsOptions,
    PointLight, Projection, Resolution, Upsampler,
};

use crate::common;

#[test]
fn every_option_runs_within_webgpu_default_limits() {
    // Its own device, but GPU objects all the same: not while another test counts them.
    let _g = crate::lock();
    let limits = wgpu::Limits::default();
    let c = common::context(Some(limits.clone()));
    assert_eq!(
        c.device.limits().max_storage_textures_per_shader_stage,
        limits.max_storage_textures_per_shader_stage
    );
    let (w, h) = (37u32, 23u32);
    // A slanted floor with a box on it, as linear view depth.
    let depth: Vec<f32> = (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            if (12..20).contains(&x) && (8..16).contains(&y) {
                3.0
            } else {
                3.5 + y as f32 * 0.05
            }
        })
        .collect();
    let tex = common::upload_r32(&c, &depth, w, h);
    let view = tex.create_view(&Default::default());
    let input = common::linear_input(
        &view,
        Projection::Perspective {
            fov_y: 1.0,
            aspect: w as f32 / h as f32,
            near: 0.1,
            far: 50.0,
        },
    );
    let params = AoParams {
        radius: 0.5,
        ..Default::default()
    };
    // Every pass variant at least once: every estimator in every layout (fused or not) at
    // full resolution; every resolution, upsampler and denoise choice; every estimator at
    // half resolution.
    let mut all = Vec::new();
    for estimator in Estimator::ALL {
        for mode in AoMode::ALL {
            for fused in [true, false] {
                all.push(AoOptions {
                    estimator,
                    mode,
                    fused,
                    ..Default::default()
                });
            }
        }
        all.push(AoOptions {
            estimator,
            resolution: Resolution::Half,
            ..Default::default()
        });
        all.push(AoOptions {
            estimator,
            upsample: Upsampler::Classified,
            resolution: Resolution::Half,
            pyramid: obscura::PyramidBuild::FourLevelsPerPass,
            ..Default::default()
        });
        if !estimator.uses_pyramid() && !estimator.uses_moments() {
            for mode in [AoMode::Randomized, AoMode::Deinterleaved4] {
                all.push(AoOptions {
                    estimator,
                    mode,
                    resolution: Resolution::Scaled,
                    history: 8,
                    ..Default::default()
                });
            }
        }
    }
    for resolution in Resolution::ALL {
        for upsample in Upsampler::ALL {
            for denoise in Denoise::ALL {
                for downsample in [
                    DepthDownsample::Checkerboard,
                    DepthDownsample::Representative,
                ] {
                    if resolution == Resolution::Full && !denoise.downsamples() {
                        continue;
                    }
                    all.push(AoOptions {
                        resolution,
                        upsample,
                        denoise,
                        downsample,
                        ..Default::default()
                    });
                }
            }
        }
    }
    // Two threads share the device, half the options each (wgpu's error scopes are per
    // thread; a panic in either fails the test when the scope ends).
    std::thread::scope(|s| {
        for half in all.chunks(all.len().div_ceil(2)) {
            let (c, input, params) = (&c, &input, &params);
            s.spawn(move || {
                for options in half {
                    let mut ao =
                        Ao::new(&c.device, *options).unwrap_or_else(|e| panic!("{options:?}: {e}"));
                    c.run(|enc| ao.record(&c.device, &c.queue, enc, input, params))
                        .unwrap_or_else(|e| panic!("{options:?}: {e}"));
                    let out = c.read_f32(ao.output().unwrap()).unwrap();
                    assert!(
                        out.iter().all(|a| (0.0..=1.0).contains(a)),
                        "{options:?}: AO outside [0, 1]"
                    );
                }
            });
        }
    });
    assert!(all.len() > 80, "{} combinations", all.len());

    // Many-light shading from the randomized plan's prepared buffer: its 2048-light uniform
    // array is exactly the default 64 KiB uniform binding.
    let options = AoOptions {
        mode: AoMode::Randomized,
        ..Default::default()
    };
    let mut ao = Ao::new(&c.device, options).unwrap();
    let frame = ao.validate(&input, &params).unwrap();
    let lights: Vec<PointLight> = (0..LIGHTS_MAX)
        .map(|i| PointLight {
            position: [(i % 7) as f32 - 3.0, 1.0, -3.0],
            colour: [1.0; 3],
            range: 4.0,
        })
        .collect();
    for period in [1, 2, 4, 8] {
        for layered in [false, true] {
            let options = LightsOptions {
                period,
                layered,
                merge: true,
            };
            let mut l = Lights::new(&c.device, options).unwrap();
            c.run(|enc| {
                ao.record(&c.device, &c.queue, enc, &input, &params)?;
                l.record(
                    &c.device,
                    &c.queue,
                    enc,
                    ao.prepared().unwrap(),
                    &frame,
                    &lights,
                )
            })
            .unwrap_or_else(|e| panic!("{options:?}: {e}"));
            let out = c.read_f32(l.output().unwrap()).unwrap();
            assert!(
                out.iter().all(|v| v.is_finite() && *v >= 0.0),
                "{options:?}"
            );
        }
    }
}
