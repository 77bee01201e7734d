//! Screen-space directional occlusion (src/shading/ssdo.rs): the GPU passes against their CPU
//! mirrors for every period, an open plane against the environment's closed-form
//! irradiance, a coloured wall's bounce against the infinite wall's form factor, typed
//! errors, no per-frame GPU objects. One device per binary.

use crate::{common, ctx, lock};
use glam::{Mat3, Vec3, Vec4};
use obscura::uniforms::FrameUniforms;
use obscura::{
    reference, AoOptions, AoParams, DepthConvention, Environment, Error, Projection, Ssdo,
    SsdoInputs, SsdoLighting, SsdoOptions, Viewport,
};

const W: u32 = 61;
const H: u32 = 43;

fn frame(w: u32, h: u32, radius: f32) -> FrameUniforms {
    let projection = Projection::Perspective {
        fov_y: 60f32.to_radians(),
        aspect: w as f32 / h as f32,
        near: 0.1,
        far: 100.0,
    };
    let params = AoParams {
        radius,
        ..AoParams::default()
    };
    FrameUniforms::new(
        &projection,
        DepthConvention::LinearView,
        None,
        (Viewport::full(w, h), 0),
        &AoOptions::default(),
        &params,
    )
    .unwrap()
}

/// A plane through `point` with unit normal `n` and an albedo.
#[derive(Clone, Copy)]
struct Plane {
    point: Vec3,
    n: Vec3,
    albedo: Vec3,
}

/// Prepared buffer and albedo of the nearest plane at each pixel (0 on sky).
fn scene(f: &FrameUniforms, planes: &[Plane]) -> (Vec<Vec4>, Vec<Vec3>) {
    let (w, h) = (f.size[0], f.size[1]);
    let mut prepared = Vec::new();
    let mut albedo = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let dir = f.view_position([x as f32 + 0.5, y as f32 + 0.5], 1.0);
            let hit = planes
                .iter()
                .filter_map(|p| {
                    let denom = p.n.dot(dir);
                    let d = p.n.dot(p.point) / denom;
                    (denom < 0.0 && d > 0.0).then_some((d, p))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0));
            match hit {
                Some((d, p)) => {
                    prepared.push(Vec4::new(d, p.n.x, p.n.y, p.n.z));
                    albedo.push(p.albedo);
                }
                None => {
                    prepared.push(Vec4::ZERO);
                    albedo.push(Vec3::ZERO);
                }
            }
        }
    }
    (prepared, albedo)
}

fn rgba(v: &[Vec3]) -> Vec<[f32; 4]> {
    v.iter().map(|c| [c.x, c.y, c.z, 1.0]).collect()
}

fn read_rgb(t: &wgpu::Texture) -> Vec<Vec3> {
    ctx()
        .read_f32(t)
        .unwrap()
        .chunks(4)
        .map(|v| Vec3::new(v[0], v[1], v[2]))
        .collect()
}

/// A camera turned 30° about y and tilted 10° down, in a gradient sky.
fn lighting(env: &Environment) -> SsdoLighting {
    let m = Mat3::from_rotation_y(0.5) * Mat3::from_rotation_x(-0.17);
    SsdoLighting {
        irradiance: env.irradiance_sh(),
        view_to_world: m.to_cols_array_2d(),
    }
}

struct Run {
    output: Vec<Vec3>,
    bounce: Vec<Vec3>,
    raw: Vec<Vec3>,
    /// The raw bounce's packed texels, where it merges.
    packed: Option<Vec<[u32; 4]>>,
}

/// One frame of `options` over the scene, with `ao` and `bent` as the AO's outputs.
fn run(
    f: &FrameUniforms,
    prepared: &[Vec4],
    albedo: &[Vec3],
    ao: &[f32],
    bent: Option<&[Vec3]>,
    options: SsdoOptions,
    lighting: &SsdoLighting,
) -> Run {
    let c = ctx();
    let (w, h) = (f.size[0], f.size[1]);
    let data: Vec<[f32; 4]> = prepared.iter().map(|v| v.to_array()).collect();
    let prepared_tex = c.upload_rgba32("test prepared", &data, w, h);
    let albedo_tex = c.upload_rgba32("test albedo", &rgba(albedo), w, h);
    // The AO is the output's size (the viewport's, inside a guard band).
    let ao_tex = common::upload_r32(c, ao, f.output_size[0], f.output_size[1]);
    let bent_tex = bent.map(|b| c.upload_rgba32("test bent", &rgba(b), w, h));
    let mut s = Ssdo::new(&c.device, options).unwrap();
    let inputs = SsdoInputs {
        prepared: (&prepared_tex).into(),
        albedo: &albedo_tex,
        ao: &ao_tex,
        bent: bent_tex.as_ref(),
    };
    c.run(|enc| s.record(&c.device, &c.queue, enc, inputs, f, lighting))
        .unwrap();
    Run {
        output: read_rgb(s.output().unwrap()),
        // No bounce texture is offered without the bounce.
        bounce: s.bounce().map(read_rgb).unwrap_or_default(),
        raw: s.bounce_raw().map(read_lit).unwrap_or_default(),
        packed: s
            .bounce_raw()
            .filter(|t| t.format() == obscura::shader::LIT_PACKED_FORMAT)
            .map(|t| common::read_packed(c, t)),
    }
}

/// The rgb of a lit texture, packed (decoded) or not.
fn read_lit(t: &wgpu::Texture) -> Vec<Vec3> {
    if t.format() == obscura::shader::LIT_PACKED_FORMAT {
        let packed = common::read_packed(ctx(), t);
        packed.iter().map(|p| reference::unpack_lit(*p).1).collect()
    } else {
        read_rgb(t)
    }
}

fn max_diff(a: &[Vec3], b: &[Vec3]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (*x - *y).abs().max_element())
        .fold(0.0, f32::max)
}

/// A floor, a back wall and a tilted box face in three colours, sky in a corner.
fn coloured_scene(f: &FrameUniforms) -> (Vec<Vec4>, Vec<Vec3>) {
    let (mut p, mut a) = scene(
        f,
        &[
            Plane {
                point: Vec3::new(0.0, -1.0, 0.0),
                n: Vec3::Y,
                albedo: Vec3::new(0.8, 0.8, 0.8),
            },
            Plane {
                point: Vec3::new(0.0, 0.0, -6.0),
                n: Vec3::Z,
                albedo: Vec3::new(0.9, 0.2, 0.1),
            },
            Plane {
                point: Vec3::new(1.0, 0.0, -4.0),
                n: Vec3::new(-0.6, 0.1, 0.8).normalize(),
                albedo: Vec3::new(0.1, 0.6, 0.2),
            },
        ],
    );
    for i in 0..6 {
        p[i] = Vec4::ZERO;
        a[i] = Vec3::ZERO;
    }
    (p, a)
}

/// A guard band of `G` pixels: the bounce and its merge cover the processed rectangle (the
/// viewport and the band) and the combine reads the AO at the output's size and the rest
/// at the output pixel plus the band. The radiance is exactly the crop of the same frame
/// without a band (the same uniforms, the whole rectangle as the output, the AO over it),
/// and the bounce is the same texture, for every period.
#[test]
fn a_guard_band_is_bounced_and_cropped() {
    let _g = lock();
    const G: u32 = 8;
    let params = AoParams {
        radius: 1.5,
        ..AoParams::default()
    };
    let projection = Projection::Perspective {
        fov_y: 60f32.to_radians(),
        aspect: W as f32 / H as f32,
        near: 0.1,
        far: 100.0,
    };
    let (banded, whole) = common::banded_frames(&projection, &params, (W, H, G));
    let (p, albedo) = coloured_scene(&banded);
    let light = lighting(&Environment::Gradient {
        sky: [1.0, 0.9, 0.7],
        ground: [0.2, 0.3, 0.4],
    });
    let ao: Vec<f32> = (0..p.len())
        .map(|i| 0.3 + 0.7 * ((i * 37) % 11) as f32 / 10.0)
        .collect();
    let bw = banded.size[0] as usize;
    let crop = |i: usize| (i / W as usize + G as usize) * bw + i % W as usize + G as usize;
    let ao_view: Vec<f32> = (0..(W * H) as usize).map(|i| ao[crop(i)]).collect();
    for period in [1, 2, 4] {
        let options = SsdoOptions {
            bounce: true,
            period,
            directions: 2,
            steps: 4,
        };
        let got = run(&banded, &p, &albedo, &ao_view, None, options, &light);
        let want = run(&whole, &p, &albedo, &ao, None, options, &light);
        assert_eq!(got.output.len(), (W * H) as usize, "period {period}");
        assert!(got.bounce == want.bounce, "period {period}: the bounce");
        let cropped: Vec<Vec3> = (0..(W * H) as usize)
            .map(|i| want.output[crop(i)])
            .collect();
        assert!(
            got.output == cropped,
            "period {period}: not the crop of the whole rectangle"
        );
        let lit = got.bounce.iter().filter(|b| b.max_element() > 0.01).count();
        assert!(
            lit > 50,
            "period {period}: only {lit} pixels receive a bounce"
        );
    }
}

#[test]
fn passes_match_cpu_reference_for_every_period() {
    let _g = lock();
    let f = frame(W, H, 1.5);
    let (p, albedo) = coloured_scene(&f);
    let env = Environment::Gradient {
        sky: [1.0, 0.9, 0.7],
        ground: [0.2, 0.3, 0.4],
    };
    let light = lighting(&env);
    // Any AO and bent normals will do: the combine only reads them.
    let ao: Vec<f32> = (0..p.len())
        .map(|i| 0.3 + 0.7 * ((i * 37) % 11) as f32 / 10.0)
        .collect();
    let bent: Vec<Vec3> = p
        .iter()
        .enumerate()
        .map(|(i, v)| {
            (Vec3::new(v.y, v.z, v.w) + 0.3 * Vec3::new(((i % 5) as f32 - 2.0) / 2.0, 0.2, 0.0))
                .normalize_or_zero()
        })
        .collect();
    for (period, directions, steps) in [(1, 2, 4), (2, 3, 4), (4, 2, 6)] {
        let options = SsdoOptions {
            bounce: true,
            period,
            directions,
            steps,
        };
        let r = run(&f, &p, &albedo, &ao, Some(&bent), options, &light);
        let want_raw = reference::ssdo_bounce(&f, &p, &albedo, &light, &options);
        // Packed for the merge (period > 1): within half a step of each component's ratio
        // to the pixel's largest (1/4094 or 1/2046 of it) beyond rounding.
        let quantised = r.packed.is_some();
        for (i, (g, w)) in r.raw.iter().zip(&want_raw).enumerate() {
            let step = if quantised {
                w.max_element() * Vec3::new(0.5 / 2047.0, 0.5 / 2047.0, 0.5 / 1023.0)
            } else {
                Vec3::ZERO
            };
            assert!(
                (*g - *w).abs().cmple(step + 1e-4).all(),
                "period {period}, pixel {i}: bounce {g} against {w}"
            );
        }
        let lit = want_raw.iter().filter(|b| b.max_element() > 0.01).count();
        assert!(
            lit > 50,
            "period {period}: only {lit} pixels receive a bounce"
        );
        match &r.packed {
            // The merge of the GPU's own bounce, so bounce rounding does not enter.
            Some(packed) => common::assert_packed_merge(
                &r.bounce,
                &reference::merge_lights_packed(&f, packed, period),
                &format!("period {period}"),
            ),
            None => assert_eq!(r.bounce, r.raw, "period {period}: no merge"),
        }
        let want = reference::ssdo_combine(&p, &albedo, &ao, Some(&bent), Some(&r.bounce), &light);
        let e = max_diff(&r.output, &want);
        assert!(e < 1e-4, "period {period}: combine differs by {e}");
    }
    // Without bent normals or a bounce: the normal, and the environment alone.
    let options = SsdoOptions {
        bounce: false,
        ..Default::default()
    };
    let r = run(&f, &p, &albedo, &ao, None, options, &light);
    assert!(
        r.bounce.is_empty() && r.raw.is_empty(),
        "a bounce without the bounce"
    );
    let want = reference::ssdo_combine(&p, &albedo, &ao, None, None, &light);
    let e = max_diff(&r.output, &want);
    assert!(
        e < 1e-4,
        "no bounce, no bent normals: combine differs by {e}"
    );
}

/// An open plane under a gradient sky L(d) = a + b · d_y: no occluder, so no bounce, and
/// with AO 1 and the bent normal equal to the normal the radiance is albedo · (a + ⅔ b n_y)
/// (the cosine-weighted mean of d_y over the hemisphere around n is ⅔ n_y).
#[test]
fn an_open_plane_reflects_the_closed_form_irradiance() {
    let _g = lock();
    let f = frame(W, H, 1.0);
    let n = Vec3::new(0.2, 0.5, 1.0).normalize();
    let albedo = Vec3::new(0.7, 0.5, 0.3);
    let (p, a) = scene(
        &f,
        &[Plane {
            point: Vec3::new(0.0, 0.0, -5.0),
            n,
            albedo,
        }],
    );
    let (sky, ground) = (Vec3::new(1.0, 0.8, 0.6), Vec3::new(0.1, 0.2, 0.3));
    let env = Environment::Gradient {
        sky: sky.to_array(),
        ground: ground.to_array(),
    };
    let light = lighting(&env);
    let normals: Vec<Vec3> = p.iter().map(|v| Vec3::new(v.y, v.z, v.w)).collect();
    let ao = vec![1.0; p.len()];
    let r = run(
        &f,
        &p,
        &a,
        &ao,
        Some(&normals),
        SsdoOptions::default(),
        &light,
    );
    let world_n = Mat3::from_cols_array_2d(&light.view_to_world) * n;
    let (mean, half) = ((sky + ground) / 2.0, (sky - ground) / 2.0);
    let want = albedo * (mean + half * (2.0 / 3.0) * world_n.y);
    for (i, (got, b)) in r.output.iter().zip(&r.bounce).enumerate() {
        assert!(
            b.max_element().abs() < 1e-6,
            "pixel {i}: bounce {b} on an open plane"
        );
        assert!(
            (*got - want).abs().max_element() < 2e-4,
            "pixel {i}: {got} against {want}"
        );
    }
}

/// A red wall standing on a white floor, lit by a constant white sky, with a radius far
/// beyond the view. A floor point sees the infinite wall over the directions toward it:
/// exactly half its cosine-weighted hemisphere, lit with the wall's radiance, red. So the
/// floor's bounce is red only (green and blue 0), at most ½, and the most near the wall;
/// the wall's bounce from the white floor is grey, also at most ½.
#[test]
fn a_red_wall_bounces_red_onto_the_floor_within_its_form_factor() {
    let _g = lock();
    let f = frame(W, H, 50.0);
    let red = Vec3::new(1.0, 0.0, 0.0);
    let (p, a) = scene(
        &f,
        &[
            Plane {
                point: Vec3::new(0.0, -1.0, 0.0),
                n: Vec3::Y,
                albedo: Vec3::ONE,
            },
            Plane {
                point: Vec3::new(0.0, 0.0, -5.0),
                n: Vec3::Z,
                albedo: red,
            },
        ],
    );
    let light = lighting(&Environment::Constant([1.0; 3]));
    let ao = vec![1.0; p.len()];
    let options = SsdoOptions {
        period: 1,
        directions: 4,
        steps: 8,
        ..Default::default()
    };
    let r = run(&f, &p, &a, &ao, None, options, &light);
    // ½, and the quadrature error of 4 slices whose weights make an open plane exactly 1
    // but a half-covered one only close to ½ (measured up to 0.52).
    const BOUND: f32 = 0.575;
    let (mut floor_near, mut floor_far, mut wall_bounce) = (0.0f32, f32::MAX, 0.0f32);
    for (i, b) in r.bounce.iter().enumerate() {
        let (x, d) = (i as u32 % W, p[i].x);
        if !(8..W - 8).contains(&x) {
            continue; // away from the image's sides, where the march leaves the image
        }
        if p[i].z > 0.9 {
            // Floor: red only, within the infinite wall's ½.
            assert!(b.y.abs() < 1e-6 && b.z.abs() < 1e-6, "floor pixel {i}: {b}");
            assert!(b.x <= BOUND, "floor pixel {i}: {b} above the form factor ½");
            if d > 4.5 {
                floor_near = floor_near.max(b.x);
            } else if d < 3.0 {
                floor_far = floor_far.min(b.x);
            }
        } else {
            assert!(
                (b.x - b.y).abs() < 1e-5 && (b.y - b.z).abs() < 1e-5,
                "wall pixel {i}: {b} should be grey"
            );
            assert!(b.x <= BOUND, "wall pixel {i}: {b} above the form factor ½");
            wall_bounce = wall_bounce.max(b.x);
        }
    }
    eprintln!("floor near the wall {floor_near}, far {floor_far}; wall {wall_bounce}");
    assert!(
        floor_near > 0.3,
        "the floor beside the wall gets {floor_near}"
    );
    assert!(
        floor_far < floor_near,
        "farther floor {floor_far} ≥ nearer {floor_near}"
    );
    assert!(wall_bounce > 0.1, "the wall's foot gets {wall_bounce}");
}

#[test]
fn bad_options_and_inputs_are_typed_errors_and_frames_allocate_nothing() {
    let _g = lock();
    let c = ctx();
    for options in [
        SsdoOptions {
            period: 3,
            ..Default::default()
        },
        SsdoOptions {
            directions: 0,
            ..Default::default()
        },
        SsdoOptions {
            steps: 17,
            ..Default::default()
        },
    ] {
        assert!(matches!(
            Ssdo::new(&c.device, options),
            Err(Error::InvalidSetting { .. })
        ));
    }
    let f = frame(W, H, 1.0);
    let (p, a) = coloured_scene(&f);
    let data: Vec<[f32; 4]> = p.iter().map(|v| v.to_array()).collect();
    let prepared = c.upload_rgba32("test prepared", &data, W, H);
    let albedo = c.upload_rgba32("test albedo", &rgba(&a), W, H);
    let small = c.upload_rgba32("test albedo", &rgba(&a[..(W * (H - 1)) as usize]), W, H - 1);
    let ao = common::upload_r32(c, &vec![1.0; p.len()], W, H);
    let light = lighting(&Environment::SKY);
    let mut s = Ssdo::new(&c.device, SsdoOptions::default()).unwrap();
    let inputs = |albedo| SsdoInputs {
        prepared: (&prepared).into(),
        albedo,
        ao: &ao,
        bent: None,
    };
    let mut enc = c.device.create_command_encoder(&Default::default());
    let e = s.record(&c.device, &c.queue, &mut enc, inputs(&small), &f, &light);
    assert!(
        matches!(e, Err(Error::InvalidTexture { what: "albedo", .. })),
        "{e:?}"
    );
    // The AO where bent normals belong: the wrong format.
    let bad_bent = SsdoInputs {
        bent: Some(&ao),
        ..inputs(&albedo)
    };
    let e = s.record(&c.device, &c.queue, &mut enc, bad_bent, &f, &light);
    assert!(matches!(e, Err(Error::InvalidTexture { .. })), "{e:?}");
    let mut nan = light;
    nan.irradiance.coefficients[0][1] = f32::NAN;
    let e = s.record(&c.device, &c.queue, &mut enc, inputs(&albedo), &f, &nan);
    assert!(matches!(e, Err(Error::InvalidSetting { .. })), "{e:?}");
    drop(enc);
    let mut counts = Vec::new();
    for _ in 0..3 {
        c.run(|enc| s.record(&c.device, &c.queue, enc, inputs(&albedo), &f, &light))
            .unwrap();
        counts.push(s.resource_creations());
    }
    assert!(
        counts.windows(2).all(|w| w[0] == w[1]),
        "created per frame: {counts:?}"
    );
}

/// The default AO plan (fused 2×2) keeps its depth and normals as layers: SSDO reading them
/// in place gives exactly what it gives from the randomized plan's single texture (the
/// same AO and bent normals passed to both), for every period; and it runs after a real
/// AO frame with bent normals.
#[test]
fn ssdo_from_the_aos_layers_matches_ssdo_from_its_full_buffer() {
    use obscura::{Ao, AoMode};
    let _g = lock();
    let c = ctx();
    let f = frame(W, H, 1.5);
    let (p, albedo) = coloured_scene(&f);
    let depth: Vec<f32> = p.iter().map(|v| v.x).collect();
    let depth_tex = common::upload_r32(c, &depth, W, H);
    let view = depth_tex.create_view(&Default::default());
    let projection = Projection::Perspective {
        fov_y: 60f32.to_radians(),
        aspect: W as f32 / H as f32,
        near: 0.1,
        far: 100.0,
    };
    let input = common::linear_input(&view, projection);
    let params = AoParams {
        radius: 1.5,
        ..AoParams::default()
    };
    let albedo_tex = c.upload_rgba32("test albedo", &rgba(&albedo), W, H);
    let light = lighting(&Environment::SKY);
    let make = |mode| {
        let o = AoOptions {
            mode,
            bent_normals: true,
            ..Default::default()
        };
        Ao::new(&c.device, o).unwrap()
    };
    let (mut full, mut layered) = (make(AoMode::Randomized), make(AoMode::Deinterleaved2));
    let frame = full.validate(&input, &params).unwrap();
    for ao in [&mut full, &mut layered] {
        c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &params))
            .unwrap();
    }
    assert!(matches!(
        layered.prepared_source(),
        Some(obscura::Prepared::Layers { split: 2, .. })
    ));
    for period in [1, 2, 4] {
        let options = SsdoOptions {
            period,
            ..Default::default()
        };
        let mut out = Vec::new();
        for ao in [&full, &layered] {
            let mut s = Ssdo::new(&c.device, options).unwrap();
            let inputs = SsdoInputs {
                prepared: ao.prepared_source().unwrap(),
                albedo: &albedo_tex,
                ao: full.output().unwrap(),
                bent: full.bent_normals(),
            };
            c.run(|enc| s.record(&c.device, &c.queue, enc, inputs, &frame, &light))
                .unwrap();
            out.push(c.read_f32(s.output().unwrap()).unwrap());
        }
        assert_eq!(out[0], out[1], "period {period}");
        let lit = out[0]
            .chunks(4)
            .filter(|v| v[3] > 0.0 && v[0] > 0.01)
            .count();
        assert!(
            lit > (W * H / 2) as usize,
            "period {period}: {lit} lit pixels"
        );
    }
}
