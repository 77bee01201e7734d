//! Many-light shading over N×N pixel classes and the geometry-guided merge. The WGSL and
//! the structs it reads are here; the CPU mirror below reads like the WGSL.

use crate::passes::denoise::merge_weight;
use crate::passes::prepare::centre;
use crate::passes::uniforms::FrameUniforms;
use glam::{Vec3, Vec4};

crate::gpu_struct! {
    /// A light as passes/lights/lights_shade.wgsl reads it (built from [`PointLight`]).
    pub struct GpuLight {
        /// View-space position, 1 / range².
        pub position_inv_range2: [f32; 4],
        /// Colour, and the squared distance clamp (`LIGHT_MIN_DISTANCE` × range)².
        pub colour_min_distance2: [f32; 4],
    }
}

crate::gpu_struct! {
    /// Per-frame parameters of the shading pass.
    pub struct LightsUniforms {
        /// Lights in the buffer this frame.
        pub count: u32,
        pub pad0: u32,
        pub pad1: [u32; 2],
    }
}

/// Many-light shading (passes/lights/lights_shade.wgsl): per pixel the unshadowed diffuse
/// irradiance of `lights`, all of them (`period` 1) or, with `period` n, those whose
/// index is congruent to the pixel's layer modulo n², times n². Sky pixels are 0.
pub fn shade_lights(
    f: &FrameUniforms,
    prepared: &[Vec4],
    lights: &[crate::PointLight],
    period: u32,
) -> Vec<Vec3> {
    let (w, h) = (f.size[0] as i32, f.size[1] as i32);
    let stride = (period * period) as usize;
    let mut out = Vec::with_capacity(prepared.len());
    for y in 0..h {
        for x in 0..w {
            let c = prepared[(y * w + x) as usize];
            if c.x.is_nan() || c.x <= 0.0 {
                out.push(Vec3::ZERO);
                continue;
            }
            let pos = f.view_position(centre([x, y]), c.x);
            let n = Vec3::new(c.y, c.z, c.w);
            let first = crate::passes::layers::layer_of(x as u32, y as u32, period) as usize;
            let mut e = Vec3::ZERO;
            for light in lights.iter().skip(first).step_by(stride) {
                let v = Vec3::from(light.position) - pos;
                let d2 = v.length_squared();
                let x = d2 / (light.range * light.range);
                let window = (1.0 - x * x).clamp(0.0, 1.0);
                let cosine = n.dot(v).max(0.0) / d2.max(1e-30).sqrt();
                let min_d = crate::passes::constants::LIGHT_MIN_DISTANCE * light.range;
                e += Vec3::from(light.colour) * (cosine * window * window / d2.max(min_d * min_d));
            }
            out.push(e * stride as f32);
        }
    }
    out
}

/// The merge of interleaved shading (passes/lights/lights_merge.wgsl): along x, then along y,
/// per pixel each class of the `period` lattice interpolated linearly at the pixel from
/// its two lattice neighbours (× geometric weights, taps past the border dropped),
/// classes whose weights sum below `LIGHTS_CLASS_MIN_WEIGHT` left out, the rest
/// averaged; sky passes through.
pub fn merge_lights(f: &FrameUniforms, prepared: &[Vec4], lit: &[Vec3], period: u32) -> Vec<Vec3> {
    let taps: Vec<(Vec4, Vec3)> = prepared.iter().copied().zip(lit.iter().copied()).collect();
    let along_x = merge_lights_axis(f, &taps, period, 0);
    let taps: Vec<(Vec4, Vec3)> = prepared.iter().copied().zip(along_x).collect();
    merge_lights_axis(f, &taps, period, 1)
}

/// [`merge_lights`] as the GPU runs it (passes/lights/lights_merge.wgsl, passes/lights/lit_packed.wgsl):
/// from the packed shading `packed` (the GPU's [`crate::Lights::raw`], or the SSDO bounce's
/// [`crate::Ssdo::bounce_raw`]), the pass along x writing packed texels (each pixel's
/// geometry and its merged irradiance) for the pass along y.
pub fn merge_lights_packed(f: &FrameUniforms, packed: &[[u32; 4]], period: u32) -> Vec<Vec3> {
    let taps: Vec<(Vec4, Vec3)> = packed.iter().map(|t| unpack_lit(*t)).collect();
    let along_x = merge_lights_axis(f, &taps, period, 0);
    let taps: Vec<(Vec4, Vec3)> = taps
        .iter()
        .zip(along_x)
        .map(|(&(g, _), e)| unpack_lit(pack_lit(g, e)))
        .collect();
    merge_lights_axis(f, &taps, period, 1)
}

/// The packed texel of many-light shading (passes/lights/lit_packed.wgsl, `pack_lit`): linear
/// depth's bits, the normal's (v + 1) / 2 rounded to `LIT_NORMAL_MAX` (3 × 10 bits; 0 on
/// sky), the largest irradiance component m's bits, and r / m, g / m, b / m rounded to
/// `LIT_RATIO_MAX` (11, 11, 10 bits).
pub fn pack_lit(g: Vec4, e: Vec3) -> [u32; 4] {
    use crate::passes::constants::{LIT_NORMAL_MAX, LIT_RATIO_MAX};
    let u = (Vec3::new(g.y, g.z, g.w) * 0.5 + 0.5).clamp(Vec3::ZERO, Vec3::ONE);
    let n = (u * LIT_NORMAL_MAX + 0.5).to_array().map(|v| v as u32);
    let normal = if g.x > 0.0 {
        n[0] | n[1] << 10 | n[2] << 20
    } else {
        0
    };
    let c = e.min(Vec3::splat(f32::MAX));
    let m = c.x.max(c.y).max(c.z);
    let r = if m > 0.0 { c / m } else { Vec3::ZERO };
    let q = (r * Vec3::from(LIT_RATIO_MAX) + 0.5)
        .to_array()
        .map(|v| v as u32);
    [
        g.x.to_bits(),
        normal,
        m.to_bits(),
        q[0] | q[1] << 11 | q[2] << 22,
    ]
}

/// The geometry `vec4(linear depth, view normal)` and irradiance of a packed texel
/// (passes/lights/lit_packed.wgsl, `unpack_geometry`, `unpack_irradiance`).
pub fn unpack_lit(t: [u32; 4]) -> (Vec4, Vec3) {
    use crate::passes::constants::{LIT_NORMAL_MAX, LIT_RATIO_MAX};
    let n = Vec3::new(
        (t[1] & 0x3ff) as f32,
        ((t[1] >> 10) & 0x3ff) as f32,
        (t[1] >> 20) as f32,
    ) * (2.0 / LIT_NORMAL_MAX)
        - 1.0;
    let q = Vec3::new(
        (t[3] & 0x7ff) as f32,
        ((t[3] >> 11) & 0x7ff) as f32,
        (t[3] >> 22) as f32,
    );
    (
        Vec4::new(f32::from_bits(t[0]), n.x, n.y, n.z),
        f32::from_bits(t[2]) * (q / Vec3::from(LIT_RATIO_MAX)),
    )
}

/// One axis of the merge over `taps`: each pixel's geometry and irradiance.
fn merge_lights_axis(
    f: &FrameUniforms,
    taps: &[(Vec4, Vec3)],
    period: u32,
    axis: usize,
) -> Vec<Vec3> {
    use crate::passes::constants::LIGHTS_CLASS_MIN_WEIGHT;
    let (w, h) = (f.size[0] as i32, f.size[1] as i32);
    let n = period as i32;
    let at = |q: [i32; 2]| (q[1] * w + q[0]) as usize;
    let extent = [w, h][axis];
    let mut out = Vec::with_capacity(taps.len());
    for y in 0..h {
        for x in 0..w {
            let p = [x, y];
            let (c, own) = taps[at(p)];
            if c.x.is_nan() || c.x <= 0.0 {
                out.push(own);
                continue;
            }
            let pos = f.view_position(centre(p), c.x);
            let normal = Vec3::new(c.y, c.z, c.w);
            let tol = f.plane_tolerance(c.x);
            // The pixel's own class is the pixel alone, and always counts.
            let (mut sum, mut classes) = (own, 1.0f32);
            for k in 0..n {
                let first = -(p[axis] - k).rem_euclid(n);
                if first == 0 {
                    continue;
                }
                let (mut total, mut acc) = (0.0f32, Vec3::ZERO);
                for d in [first, first + n] {
                    let linear = (n - d.abs()) as f32;
                    if linear <= 0.0 || p[axis] + d < 0 || p[axis] + d >= extent {
                        continue;
                    }
                    let mut q = p;
                    q[axis] += d;
                    let (s, e) = taps[at(q)];
                    if s.x.is_nan() || s.x <= 0.0 {
                        continue;
                    }
                    let wgt = linear * merge_weight(f, pos, normal, tol, q, s);
                    total += wgt;
                    acc += wgt * e;
                }
                if total >= LIGHTS_CLASS_MIN_WEIGHT {
                    sum += acc / total;
                    classes += 1.0;
                }
            }
            out.push(sum / classes);
        }
    }
    out
}
