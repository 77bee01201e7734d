//! Interleaved many-light shading (src/shading/lights.rs): the GPU passes against their CPU
//! mirrors, a light over a plane against the closed form, the interleaved-and-merged
//! result against shading every light, typed errors, no per-frame GPU objects.
//! One device per binary.

use crate::{common, ctx, lock};
use glam::{Vec3, Vec4};
use obscura::uniforms::FrameUniforms;
use obscura::{
    reference, Ao, AoInput, AoMode, AoOptions, AoParams, DepthConvention, Error, Lights,
    LightsOptions, PointLight, Projection, Viewport,
};

const W: u32 = 61;
const H: u32 = 43;

/// The tests' camera: 60° vertical field of view, `w` × `h` pixels.
fn perspective(w: u32, h: u32) -> Projection {
    Projection::Perspective {
        fov_y: 60f32.to_radians(),
        aspect: w as f32 / h as f32,
        near: 0.1,
        far: 100.0,
    }
}

fn frame(w: u32, h: u32) -> FrameUniforms {
    FrameUniforms::new(
        &perspective(w, h),
        DepthConvention::LinearView,
        None,
        (Viewport::full(w, h), 0),
        &AoOptions::default(),
        &AoParams::default(),
    )
    .unwrap()
}

/// A plane through `point` with unit normal `n` (facing the camera).
#[derive(Clone, Copy)]
struct Plane {
    point: Vec3,
    n: Vec3,
}

/// The prepared buffer of the nearest of `planes` in front of the camera at each pixel
/// (exact depth and normal; 0 = sky where none is hit).
fn prepared(f: &FrameUniforms, planes: &[Plane]) -> Vec<Vec4> {
    let (w, h) = (f.size[0], f.size[1]);
    let mut out = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            // The view ray through the pixel centre, scaled to linear depth 1.
            let dir = f.view_position([x as f32 + 0.5, y as f32 + 0.5], 1.0);
            let hit = planes
                .iter()
                .filter_map(|p| {
                    let denom = p.n.dot(dir);
                    let d = p.n.dot(p.point) / denom;
                    (denom < 0.0 && d > 0.0).then_some((d, p.n))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0));
            out.push(hit.map_or(Vec4::ZERO, |(d, n)| Vec4::new(d, n.x, n.y, n.z)));
        }
    }
    out
}

fn upload(f: &FrameUniforms, prepared: &[Vec4]) -> wgpu::Texture {
    let data: Vec<[f32; 4]> = prepared.iter().map(|v| v.to_array()).collect();
    ctx().upload_rgba32("test prepared", &data, f.size[0], f.size[1])
}

/// `count` lights in the box `lo..hi`, colours in [0.2, 1.2), range `range`; a fixed LCG.
fn lights(count: usize, lo: Vec3, hi: Vec3, range: f32, seed: u32) -> Vec<PointLight> {
    let mut s = seed.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let mut next = move || {
        s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (s >> 8) as f32 / (1u32 << 24) as f32
    };
    (0..count)
        .map(|_| {
            let t = Vec3::new(next(), next(), next());
            PointLight {
                position: (lo + (hi - lo) * t).to_array(),
                colour: [0.2 + next(), 0.2 + next(), 0.2 + next()],
                range,
            }
        })
        .collect()
}

/// The output and the raw shading of one frame.
fn run(
    f: &FrameUniforms,
    prepared: &wgpu::Texture,
    options: LightsOptions,
    lights: &[PointLight],
) -> (Vec<Vec3>, Vec<Vec3>) {
    let (out, raw, _) = run_packed(f, prepared, options, lights);
    (out, raw)
}

/// The output and the raw shading of one frame, and where the passes merge the raw
/// shading's packed texels (its rgb then decoded from them).
fn run_packed(
    f: &FrameUniforms,
    prepared: &wgpu::Texture,
    options: LightsOptions,
    lights: &[PointLight],
) -> (Vec<Vec3>, Vec<Vec3>, Option<Vec<[u32; 4]>>) {
    let c = ctx();
    let mut l = Lights::new(&c.device, options).unwrap();
    c.run(|enc| l.record(&c.device, &c.queue, enc, prepared, f, lights))
        .unwrap();
    let out = read_rgb(l.output().unwrap());
    let raw = l.raw().unwrap();
    if raw.format() == obscura::shader::LIT_PACKED_FORMAT {
        let packed: Vec<[u32; 4]> = bytemuck::pod_collect_to_vec(&c.read_texture(raw).unwrap());
        let rgb = packed.iter().map(|t| reference::unpack_lit(*t).1).collect();
        (out, rgb, Some(packed))
    } else {
        (out, read_rgb(raw), None)
    }
}

/// The rgb of an `Rgba32Float` texture.
fn read_rgb(t: &wgpu::Texture) -> Vec<Vec3> {
    ctx()
        .read_f32(t)
        .unwrap()
        .chunks(4)
        .map(|v| Vec3::new(v[0], v[1], v[2]))
        .collect()
}

/// Largest per-pixel difference over the mean magnitude of `want` (lit pixels).
fn relative_max(got: &[Vec3], want: &[Vec3]) -> f32 {
    let mean = want.iter().map(|v| v.length()).sum::<f32>() / want.len() as f32;
    got.iter()
        .zip(want)
        .map(|(g, w)| (*g - *w).length())
        .fold(0.0, f32::max)
        / mean
}

/// Root-mean-square difference over the mean magnitude of `want`, over `mask`ed pixels.
fn relative_rms(got: &[Vec3], want: &[Vec3], mask: &[bool]) -> f32 {
    let (mut se, mut sum, mut n) = (0.0f64, 0.0f64, 0.0f64);
    for ((g, w), m) in got.iter().zip(want).zip(mask) {
        if *m {
            se += (*g - *w).length_squared() as f64;
            sum += w.length() as f64;
            n += 1.0;
        }
    }
    ((se / n).sqrt() / (sum / n)) as f32
}

/// A floor, a back wall and a box's front face.
fn planes() -> [Plane; 3] {
    [
        Plane {
            point: Vec3::new(0.0, -1.0, 0.0),
            n: Vec3::Y,
        },
        Plane {
            point: Vec3::new(0.0, 0.0, -8.0),
            n: Vec3::Z,
        },
        Plane {
            point: Vec3::new(0.0, 0.0, -4.0),
            n: Vec3::new(0.3, 0.2, 1.0).normalize(),
        },
    ]
}

/// planes(), sky in the top corners.
fn scene(f: &FrameUniforms) -> Vec<Vec4> {
    prepared(f, &planes())
        .into_iter()
        .enumerate()
        .map(|(i, v)| {
            let (x, y) = (i as u32 % f.size[0], i as u32 / f.size[0]);
            let corner = y < 4 && !(8..f.size[0] - 8).contains(&x);
            if corner || v.x > 6.0 && v.z > 0.9 && x < 10 {
                Vec4::ZERO
            } else {
                v
            }
        })
        .collect()
}

#[test]
fn shading_and_merge_match_cpu_reference_for_every_period() {
    let _g = lock();
    let f = frame(W, H);
    let p = scene(&f);
    let tex = upload(&f, &p);
    let ls = lights(
        150,
        Vec3::new(-4.0, -0.8, -9.0),
        Vec3::new(4.0, 3.0, -1.0),
        6.0,
        1,
    );
    for (period, layered) in [
        (1, false),
        (2, false),
        (2, true),
        (4, false),
        (4, true),
        (8, false),
        (8, true),
    ] {
        let options = LightsOptions {
            period,
            layered,
            merge: true,
        };
        let (out, raw, packed) = run_packed(&f, &tex, options, &ls);
        let want_raw = reference::shade_lights(&f, &p, &ls, period);
        match &packed {
            None => {
                let e = relative_max(&raw, &want_raw);
                assert!(
                    e < 1e-4,
                    "period {period}: shading differs by {e} of the mean"
                );
            }
            // Packed for the merge: each pixel's geometry and its shading within one
            // step of the encoding (passes/lights/lit_packed.wgsl) beyond rounding.
            Some(packed) => check_packed(packed, &p, &want_raw, period),
        }
        if let Some(packed) = &packed {
            // The merge of the GPU's own shading, so shading rounding does not enter.
            let want = reference::merge_lights_packed(&f, packed, period);
            common::assert_packed_merge(&out, &want, &format!("period {period}"));
        } else {
            assert_eq!(out, raw, "period 1 has no merge");
        }
    }
}

/// A guard band of `G` pixels: the passes shade and merge the processed rectangle (the
/// viewport and the band) and store the viewport alone. The output is exactly the crop of
/// the same frame without a band, that is, with the same uniforms but the whole rectangle
/// as the output, for every period and layout, so the merge near the viewport's edges
/// reads the band's shading. A frame run without its band (the viewport's own prepared
/// buffer and projection; a band of 8, a multiple of every period, keeps each pixel's
/// class) agrees with it farther than a period from the edges (1e-4 of the mean, the
/// two projections' rounding) and differs within a period of them when the passes merge.
#[test]
fn a_guard_band_is_shaded_merged_and_cropped() {
    let _g = lock();
    const G: u32 = 8;
    let (banded, whole) =
        common::banded_frames(&perspective(W, H), &AoParams::default(), (W, H, G));
    // Geometry alone (scene()'s sky corners sit at pixel positions, which the band moves).
    let tex = upload(&banded, &prepared(&banded, &planes()));
    let ls = lights(
        150,
        Vec3::new(-4.0, -0.8, -9.0),
        Vec3::new(4.0, 3.0, -1.0),
        6.0,
        3,
    );
    let crop = |v: &[Vec3]| -> Vec<Vec3> {
        let bw = banded.size[0] as usize;
        (0..H as usize)
            .flat_map(|y| (0..W as usize).map(move |x| (x, y)))
            .map(|(x, y)| v[(y + G as usize) * bw + x + G as usize])
            .collect()
    };
    for (period, layered) in [(1, false), (2, false), (4, true), (8, false)] {
        let options = LightsOptions {
            period,
            layered,
            merge: true,
        };
        let (out, _) = run(&banded, &tex, options, &ls);
        assert_eq!(out.len(), (W * H) as usize, "period {period}: the viewport");
        let (want, _) = run(&whole, &tex, options, &ls);
        assert!(
            out == crop(&want),
            "period {period}, layered {layered}: not the crop of the whole rectangle"
        );
        if period > 1 {
            // Without the band the merge near the edges has only the viewport's taps.
            let own = frame(W, H);
            let own_tex = upload(&own, &prepared(&own, &planes()));
            let (alone, _) = run(&own, &own_tex, options, &ls);
            let n = period as usize;
            let edge = |i: usize| {
                let (x, y) = (i % W as usize, i / W as usize);
                x < n || y < n || x + n >= W as usize || y + n >= H as usize
            };
            let part = |at_edge: bool| -> (Vec<Vec3>, Vec<Vec3>) {
                (0..out.len())
                    .filter(|&i| edge(i) == at_edge)
                    .map(|i| (alone[i], out[i]))
                    .unzip()
            };
            let (a, b) = part(false);
            let inner = relative_max(&a, &b);
            assert!(
                inner < 1e-4,
                "period {period}: inner pixels differ by {inner}"
            );
            let (a, b) = part(true);
            let at_edges = relative_max(&a, &b);
            assert!(
                at_edges > 1e-3,
                "period {period}: the band changed nothing at the edges ({at_edges})"
            );
        }
    }
}

/// The packed shading against the prepared buffer and the CPU's shading: depth exact, the
/// normal within half a step of its 10-bit components (and rounding), each irradiance
/// component within half a step of its ratio to the largest (1/4094 or 1/2046 of it), plus
/// the shading's own rounding (1e-4 of the mean, as unpacked).
fn check_packed(packed: &[[u32; 4]], prepared: &[Vec4], want: &[Vec3], period: u32) {
    let mean = want.iter().map(|v| v.length()).sum::<f32>() / want.len() as f32;
    for (i, ((t, p), w)) in packed.iter().zip(prepared).zip(want).enumerate() {
        let (g, e) = reference::unpack_lit(*t);
        assert_eq!(
            g.x.to_bits(),
            p.x.to_bits(),
            "period {period}, pixel {i}: depth"
        );
        if p.x > 0.0 {
            let dn = (Vec3::new(g.y, g.z, g.w) - Vec3::new(p.y, p.z, p.w))
                .abs()
                .max_element();
            assert!(
                dn < 1.0 / 1023.0 + 1e-6,
                "period {period}, pixel {i}: normal off by {dn}"
            );
        }
        let step = w.max_element() * Vec3::new(0.5 / 2047.0, 0.5 / 2047.0, 0.5 / 1023.0);
        let d = (e - *w).abs();
        assert!(
            d.cmple(step + 1e-4 * mean).all(),
            "period {period}, pixel {i}: irradiance {e} against {w}"
        );
    }
}

/// One light at height h over a plane facing the camera: E = cos θ (1 − (d/r)⁴)² / d²
/// with d² = h² + ρ², cos θ = h / d, ρ the distance from the light's foot.
#[test]
fn one_light_over_a_plane_matches_the_closed_form() {
    let _g = lock();
    let f = frame(W, H);
    let depth = 5.0;
    let p = prepared(
        &f,
        &[Plane {
            point: Vec3::new(0.0, 0.0, -depth),
            n: Vec3::Z,
        }],
    );
    let tex = upload(&f, &p);
    let (foot, height, range) = (Vec3::new(0.4, -0.3, -depth), 0.7, 2.5);
    let light = PointLight {
        position: (foot + Vec3::Z * height).to_array(),
        colour: [1.0, 0.5, 0.25],
        range,
    };
    let options = LightsOptions {
        period: 1,
        ..Default::default()
    };
    let (out, _) = run(&f, &tex, options, &[light]);
    let mut lit = 0;
    for (i, got) in out.iter().enumerate() {
        let (x, y) = (i as u32 % W, i as u32 / W);
        let point = f.view_position([x as f32 + 0.5, y as f32 + 0.5], depth);
        let rho2 = (point - foot).length_squared();
        let d2 = height * height + rho2;
        let window = (1.0 - (d2 / (range * range)).powi(2)).max(0.0).powi(2);
        let e = (height / d2.sqrt()) * window / d2;
        let want = Vec3::new(1.0, 0.5, 0.25) * e;
        assert!(
            (*got - want).length() <= 1e-5 + 1e-4 * want.length(),
            "pixel ({x}, {y}): {got} against {want}"
        );
        lit += (e > 0.0) as usize;
    }
    assert!(
        lit > 100 && lit < out.len(),
        "{lit} pixels lit: the range should cut"
    );
}

/// Lights a few metres from a plane vary little over one 4 × 4 tile: each pixel's subset
/// is far from the whole (raw error large), and the merge reconstructs every light's sum.
#[test]
fn interleaved_and_merged_lights_match_every_light_on_a_plane() {
    let _g = lock();
    let f = frame(W, H);
    let plane = [Plane {
        point: Vec3::new(0.0, 0.0, -5.0),
        n: Vec3::new(0.0, 0.2, 1.0).normalize(),
    }];
    let p = prepared(&f, &plane);
    let tex = upload(&f, &p);
    let ls = lights(
        256,
        Vec3::new(-6.0, -4.0, -3.0),
        Vec3::new(6.0, 4.0, 1.0),
        30.0,
        7,
    );
    let all = LightsOptions {
        period: 1,
        ..Default::default()
    };
    let (reference, _) = run(&f, &tex, all, &ls);
    let mask = vec![true; reference.len()];
    for period in [2, 4] {
        let options = LightsOptions { period, ..all };
        let (merged, raw) = run(&f, &tex, options, &ls);
        let raw_err = relative_rms(&raw, &reference, &mask);
        let merged_err = relative_rms(&merged, &reference, &mask);
        eprintln!("period {period}: raw {raw_err:.4}, merged {merged_err:.4}");
        assert!(raw_err > 0.05, "period {period}: raw {raw_err}");
        assert!(
            merged_err < 0.01,
            "period {period}: merged {merged_err} (raw {raw_err})"
        );
    }
}

/// Two planes at depths 3 and 6, side by side, lit by lights close to the near one: the
/// merge must not average across the step (a plain box over the tile does, by far).
#[test]
fn the_merge_does_not_mix_surfaces_across_a_depth_step() {
    let _g = lock();
    let f = frame(W, H);
    let mut p = prepared(
        &f,
        &[Plane {
            point: Vec3::new(0.0, 0.0, -3.0),
            n: Vec3::Z,
        }],
    );
    let far = prepared(
        &f,
        &[Plane {
            point: Vec3::new(0.0, 0.0, -6.0),
            n: Vec3::Z,
        }],
    );
    for (i, v) in p.iter_mut().enumerate() {
        if i as u32 % W >= W / 2 {
            *v = far[i];
        }
    }
    let tex = upload(&f, &p);
    let ls = lights(
        64,
        Vec3::new(-3.0, -2.0, -2.5),
        Vec3::new(0.0, 2.0, -1.5),
        20.0,
        3,
    );
    let all = LightsOptions {
        period: 1,
        ..Default::default()
    };
    let (reference, _) = run(&f, &tex, all, &ls);
    // Pixels within two columns of the step, on both sides.
    let band: Vec<bool> = (0..p.len())
        .map(|i| (i as u32 % W).abs_diff(W / 2) <= 2)
        .collect();
    let options = LightsOptions { period: 4, ..all };
    let (merged, raw) = run(&f, &tex, options, &ls);
    let merged_err = relative_rms(&merged, &reference, &band);
    // The same tile averaged without geometry weights (1-2-2-2-1 box), on the CPU.
    let boxed: Vec<Vec3> = (0..p.len() as i32)
        .map(|i| {
            let (x, y) = (i % W as i32, i / W as i32);
            let (mut sum, mut total) = (Vec3::ZERO, 0.0);
            for dy in -2..=2i32 {
                for dx in -2..=2i32 {
                    let (qx, qy) = (x + dx, y + dy);
                    if qx < 0 || qy < 0 || qx >= W as i32 || qy >= H as i32 {
                        continue;
                    }
                    let wgt = if dx.abs() == 2 { 1.0 } else { 2.0 }
                        * if dy.abs() == 2 { 1.0 } else { 2.0 };
                    sum += wgt * raw[(qy * W as i32 + qx) as usize];
                    total += wgt;
                }
            }
            sum / total
        })
        .collect();
    let box_err = relative_rms(&boxed, &reference, &band);
    eprintln!("step band: merged {merged_err:.4}, plain box {box_err:.4}");
    assert!(
        box_err > 0.2,
        "the scene must separate the two: box {box_err}"
    );
    // Lights 0.5 to 1.5 units from the near plane, pixels 0.08 units apart: the classes
    // cut by the step fall back to their lattice pixels on this side, up to 3 pixels off.
    assert!(
        merged_err < box_err / 4.0,
        "merged {merged_err} beside the step (plain box {box_err})"
    );
}

#[test]
fn bad_lights_and_inputs_are_typed_errors() {
    let _g = lock();
    let c = ctx();
    let f = frame(W, H);
    let tex = upload(&f, &prepared(&f, &[]));
    for period in [0, 3, 16] {
        let options = LightsOptions {
            period,
            ..Default::default()
        };
        assert!(matches!(
            Lights::new(&c.device, options),
            Err(Error::InvalidSetting {
                field: "period",
                ..
            })
        ));
    }
    let options = LightsOptions {
        period: 2,
        ..Default::default()
    };
    let mut l = Lights::new(&c.device, options).unwrap();
    let good = PointLight {
        position: [0.0, 0.0, -1.0],
        colour: [1.0; 3],
        range: 1.0,
    };
    let bad = [
        PointLight {
            position: [f32::NAN, 0.0, 0.0],
            ..good
        },
        PointLight {
            colour: [-1.0, 0.0, 0.0],
            ..good
        },
        PointLight { range: 0.0, ..good },
        PointLight {
            range: f32::INFINITY,
            ..good
        },
    ];
    let mut enc = c.device.create_command_encoder(&Default::default());
    for b in bad {
        let e = l.record(&c.device, &c.queue, &mut enc, &tex, &f, &[good, b]);
        assert!(
            matches!(
                e,
                Err(Error::InvalidSetting {
                    field: "lights",
                    ..
                })
            ),
            "{b:?}: {e:?}"
        );
    }
    let e = l.record(&c.device, &c.queue, &mut enc, &tex, &f, &[good; 2049]);
    assert!(matches!(
        e,
        Err(Error::InvalidSetting {
            field: "lights",
            ..
        })
    ));
    let small = frame(W - 1, H);
    let e = l.record(&c.device, &c.queue, &mut enc, &tex, &small, &[good]);
    assert!(
        matches!(
            e,
            Err(Error::InvalidTexture {
                what: "prepared",
                ..
            })
        ),
        "{e:?}"
    );
    let r32 = common::upload_r32(c, &vec![1.0; (W * H) as usize], W, H);
    let e = l.record(&c.device, &c.queue, &mut enc, &r32, &f, &[good]);
    assert!(
        matches!(
            e,
            Err(Error::InvalidTexture {
                what: "prepared",
                ..
            })
        ),
        "{e:?}"
    );
    // No light at all is a valid frame: black.
    l.record(&c.device, &c.queue, &mut enc, &tex, &f, &[])
        .unwrap();
    c.queue.submit([enc.finish()]);
    c.take_errors().unwrap();
}

/// The AO's own prepared buffer feeds the shading, and 60 frames create no GPU object
/// after the first.
#[test]
fn shading_the_aos_prepared_buffer_creates_nothing_per_frame() {
    let _g = lock();
    let c = ctx();
    let f = frame(W, H);
    let depth: Vec<f32> = prepared(
        &f,
        &[Plane {
            point: Vec3::new(0.0, -1.0, 0.0),
            n: Vec3::Y,
        }],
    )
    .iter()
    .map(|v| v.x)
    .collect();
    let depth_tex = common::upload_r32(c, &depth, W, H);
    let view = depth_tex.create_view(&Default::default());
    let projection = perspective(W, H);
    let options = AoOptions {
        mode: AoMode::Randomized,
        ..Default::default()
    };
    let mut ao = Ao::new(&c.device, options).unwrap();
    let params = AoParams::default();
    let input: AoInput = common::linear_input(&view, projection);
    let mut l = Lights::new(&c.device, LightsOptions::default()).unwrap();
    let ls = lights(
        100,
        Vec3::new(-3.0, -0.5, -8.0),
        Vec3::new(3.0, 1.0, -2.0),
        4.0,
        5,
    );
    let mut counts = Vec::new();
    for _ in 0..60 {
        let frame = ao.validate(&input, &params).unwrap();
        c.run(|enc| {
            ao.record(&c.device, &c.queue, enc, &input, &params)?;
            let prepared = ao
                .prepared()
                .expect("a randomized full-resolution plan has one");
            l.record(&c.device, &c.queue, enc, prepared, &frame, &ls)
        })
        .unwrap();
        counts.push(l.resource_creations());
    }
    assert!(counts.iter().all(|&n| n == counts[0]), "{counts:?}");
    // The floor's normals reconstructed from depth give the same light as exact ones.
    let got = read_rgb(l.output().unwrap());
    let exact = prepared(
        &f,
        &[Plane {
            point: Vec3::new(0.0, -1.0, 0.0),
            n: Vec3::Y,
        }],
    );
    let want = reference::merge_lights(&f, &exact, &reference::shade_lights(&f, &exact, &ls, 4), 4);
    let mask: Vec<bool> = exact.iter().map(|v| v.x > 0.0).collect();
    let e = relative_rms(&got, &want, &mask);
    assert!(e < 0.02, "AO-prepared floor against exact normals: {e}");
}

/// The default AO plan (fused 2×2 deinterleaving) keeps its prepared buffer as layers; the
/// shading reads them there and gives what it gives from the randomized plan's single
/// texture (the same depth and normals, bit for bit), for every period; wrong layer sets
/// are typed errors.
#[test]
fn shading_from_the_aos_layers_matches_shading_from_its_full_buffer() {
    let _g = lock();
    let c = ctx();
    let f = frame(W, H);
    let depth: Vec<f32> = scene(&f).iter().map(|v| v.x).collect();
    let depth_tex = common::upload_r32(c, &depth, W, H);
    let view = depth_tex.create_view(&Default::default());
    let projection = perspective(W, H);
    let input: AoInput = common::linear_input(&view, projection);
    let params = AoParams::default();
    let ls = lights(
        120,
        Vec3::new(-4.0, -0.8, -9.0),
        Vec3::new(4.0, 3.0, -1.0),
        6.0,
        9,
    );
    for mode in [AoMode::Deinterleaved2, AoMode::Deinterleaved4] {
        let mut full_ao = Ao::new(
            &c.device,
            AoOptions {
                mode: AoMode::Randomized,
                ..Default::default()
            },
        )
        .unwrap();
        let mut layered_ao = Ao::new(
            &c.device,
            AoOptions {
                mode,
                ..Default::default()
            },
        )
        .unwrap();
        let frame = full_ao.validate(&input, &params).unwrap();
        for period in [1, 2, 4] {
            let options = LightsOptions {
                period,
                ..Default::default()
            };
            let mut out = Vec::new();
            for ao in [&mut full_ao, &mut layered_ao] {
                let mut l = Lights::new(&c.device, options).unwrap();
                c.run(|enc| {
                    ao.record(&c.device, &c.queue, enc, &input, &params)?;
                    let source = ao.prepared_source().expect("full resolution");
                    l.record(&c.device, &c.queue, enc, source, &frame, &ls)
                })
                .unwrap();
                out.push(c.read_f32(l.output().unwrap()).unwrap());
            }
            assert!(
                matches!(
                    layered_ao.prepared_source(),
                    Some(obscura::Prepared::Layers { .. })
                ),
                "{mode:?} keeps layers"
            );
            assert_eq!(out[0], out[1], "{mode:?} period {period}");
        }
        // The layers as a single texture, or with the wrong split: typed errors.
        let Some(obscura::Prepared::Layers { texture, split }) = layered_ao.prepared_source()
        else {
            unreachable!()
        };
        let mut l = Lights::new(&c.device, LightsOptions::default()).unwrap();
        let mut enc = c.device.create_command_encoder(&Default::default());
        for bad in [
            obscura::Prepared::Full(texture),
            obscura::Prepared::Layers {
                texture,
                split: 6 - split,
            },
            obscura::Prepared::Layers { texture, split: 3 },
        ] {
            let e = l.record(&c.device, &c.queue, &mut enc, bad, &frame, &ls);
            assert!(
                matches!(
                    e,
                    Err(Error::InvalidTexture {
                        what: "prepared",
                        ..
                    }) | Err(Error::InvalidSetting { field: "split", .. })
                ),
                "{bad:?}: {e:?}"
            );
        }
        drop(enc);
        c.take_errors().unwrap();
    }
}
