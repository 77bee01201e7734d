//! Distant environment lighting for screen-space directional occlusion ([`crate::Ssdo`]):
//! a constant sky, a two-colour gradient, or an equirectangular map, and its diffuse
//! irradiance as nine spherical-harmonic coefficients (Ramamoorthi & Hanrahan 2001, "An
//! Efficient Representation for Irradiance Environment Maps": the clamped cosine kernel
//! keeps bands 0–2 with weights π, 2π/3 and π/4, so irradiance from order-2 harmonics errs
//! by about 1% on average). The constant sky and the gradient have no band above 1, so
//! their irradiance is exact.
//!
//! World space is y up. Irradiance here is normalised by π, `E(n) = (1/π) ∫ L(ω) max(n·ω, 0)
//! dω`, so a constant sky L gives E = L and a surface of albedo ρ reflects ρ · E.

pub use crate::passes::constants::SH9_SCALE;
use crate::{Error, Result};

/// Real spherical harmonics of bands 0–2 at unit `d` (x, y, z), in the order (0,0), (1,−1),
/// (1,0), (1,1), (2,−2), (2,−1), (2,0), (2,1), (2,2) (Ramamoorthi & Hanrahan 2001, eq. 3).
pub fn sh9_basis(d: [f32; 3]) -> [f32; 9] {
    let [x, y, z] = d;
    let k = SH9_SCALE;
    [
        k[0],
        k[1] * y,
        k[1] * z,
        k[1] * x,
        k[2] * x * y,
        k[2] * y * z,
        k[3] * (3.0 * z * z - 1.0),
        k[2] * x * z,
        k[4] * (x * x - y * y),
    ]
}

/// The clamped cosine's band weights divided by π: 1, 2/3, 1/4 (bands 0, 1, 2).
const COSINE_BANDS: [f32; 9] = [
    1.0,
    2.0 / 3.0,
    2.0 / 3.0,
    2.0 / 3.0,
    0.25,
    0.25,
    0.25,
    0.25,
    0.25,
];

/// An environment's irradiance (normalised by π) as nine rgb spherical-harmonic
/// coefficients: `E(n) = Σ coefficients[i] · sh9_basis(n)[i]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IrradianceSh {
    pub coefficients: [[f32; 3]; 9],
}

impl IrradianceSh {
    /// Irradiance / π at world-space unit normal `n`, rgb (negative lobes clamped to 0).
    pub fn eval(&self, n: [f32; 3]) -> [f32; 3] {
        let y = sh9_basis(n);
        let mut e = [0.0f32; 3];
        for (c, yi) in self.coefficients.iter().zip(y) {
            for k in 0..3 {
                e[k] += c[k] * yi;
            }
        }
        e.map(|v| v.max(0.0))
    }
}

/// An equirectangular radiance map, linear rgb, row 0 at the zenith (+y): texel (i, j)
/// of a w × h map looks along θ = π (j + ½) / h from +y, φ = 2π (i + ½) / w from +x toward
/// +z: `(sin θ cos φ, cos θ, sin θ sin φ)`. Make it with [`EnvironmentMap::new`]; a map
/// built field by field is checked by [`Environment::validate`], which
/// [`crate::Ssdo`]'s callers and the CLI run before use.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    pub width: u32,
    pub height: u32,
    /// Row-major, `width × height`, finite and ≥ 0.
    pub texels: Vec<[f32; 3]>,
}

impl EnvironmentMap {
    /// Checks the size and the texels.
    pub fn new(width: u32, height: u32, texels: Vec<[f32; 3]>) -> Result<Self> {
        let map = Self {
            width,
            height,
            texels,
        };
        map.validate()?;
        Ok(map)
    }

    /// Checks that the size matches the texels and every texel is finite and ≥ 0.
    pub fn validate(&self) -> Result<()> {
        let (width, height, texels) = (self.width, self.height, &self.texels);
        if width == 0 || height == 0 || texels.len() != (width as usize) * (height as usize) {
            return Err(Error::InvalidSetting {
                field: "environment map",
                value: format!("{width}x{height} with {} texels", texels.len()),
                expected: "a non-empty map with width × height texels",
            });
        }
        if let Some(i) = texels
            .iter()
            .position(|t| t.iter().any(|v| !v.is_finite() || *v < 0.0))
        {
            return Err(Error::InvalidSetting {
                field: "environment map",
                value: format!("texel {i}: {:?}", texels[i]),
                expected: "finite, non-negative radiance",
            });
        }
        Ok(())
    }

    /// Texel (i, j)'s direction (its centre).
    pub fn direction(&self, i: u32, j: u32) -> [f32; 3] {
        let theta = std::f32::consts::PI * (j as f32 + 0.5) / self.height as f32;
        let phi = std::f32::consts::TAU * (i as f32 + 0.5) / self.width as f32;
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = phi.sin_cos();
        [st * cp, ct, st * sp]
    }

    /// The texel along unit `d` (nearest).
    pub fn radiance(&self, d: [f32; 3]) -> [f32; 3] {
        let theta = d[1].clamp(-1.0, 1.0).acos();
        let phi = d[2].atan2(d[0]).rem_euclid(std::f32::consts::TAU);
        let j = ((theta / std::f32::consts::PI * self.height as f32) as u32).min(self.height - 1);
        let i = ((phi / std::f32::consts::TAU * self.width as f32) as u32).min(self.width - 1);
        self.texels[(j * self.width + i) as usize]
    }
}

/// Distant lighting of [`crate::Ssdo`] and of the reference ray tracer.
#[derive(Clone, Debug, PartialEq)]
pub enum Environment {
    /// The same radiance from every direction.
    Constant([f32; 3]),
    /// Radiance linear in the direction's height: `sky` at the zenith, `ground` at the
    /// nadir, their mean at the horizon.
    Gradient { sky: [f32; 3], ground: [f32; 3] },
    /// An equirectangular map.
    Map(EnvironmentMap),
}

impl Environment {
    /// A daylight sky: pale blue above, a dim warm ground below.
    pub const SKY: Environment = Environment::Gradient {
        sky: [0.75, 0.85, 1.0],
        ground: [0.3, 0.27, 0.24],
    };

    /// Checks the colours (finite, ≥ 0) or the map ([`EnvironmentMap::validate`]).
    pub fn validate(&self) -> Result<()> {
        let ok = |c: &[f32; 3]| c.iter().all(|v| v.is_finite() && *v >= 0.0);
        let good = match self {
            Environment::Constant(c) => ok(c),
            Environment::Gradient { sky, ground } => ok(sky) && ok(ground),
            Environment::Map(m) => return m.validate(),
        };
        if good {
            return Ok(());
        }
        Err(Error::InvalidSetting {
            field: "environment",
            value: format!("{self:?}"),
            expected: "finite, non-negative colours",
        })
    }

    /// Radiance arriving from world-space unit direction `d` (travelling toward −d).
    pub fn radiance(&self, d: [f32; 3]) -> [f32; 3] {
        match self {
            Environment::Constant(c) => *c,
            Environment::Gradient { sky, ground } => {
                let t = 0.5 * (1.0 + d[1].clamp(-1.0, 1.0));
                [0, 1, 2].map(|k| ground[k] + (sky[k] - ground[k]) * t)
            }
            Environment::Map(m) => m.radiance(d),
        }
    }

    /// The radiance projected onto bands 0–2: exact for the constant and the gradient, a
    /// sum over the texels, each weighted by its exact solid angle, for a map.
    pub fn radiance_sh(&self) -> [[f32; 3]; 9] {
        let mut c = [[0.0f32; 3]; 9];
        // ∫ Y00 dω = 2√π; ∫ y · Y(1,−1) dω = 0.488603 · 4π/3.
        let y00 = 2.0 * std::f32::consts::PI.sqrt();
        let y1 = SH9_SCALE[1] * 4.0 * std::f32::consts::PI / 3.0;
        match self {
            Environment::Constant(l) => c[0] = l.map(|v| v * y00),
            Environment::Gradient { sky, ground } => {
                // L(d) = a + b · d.y with a the mean and b half the difference.
                for k in 0..3 {
                    c[0][k] = 0.5 * (sky[k] + ground[k]) * y00;
                    c[1][k] = 0.5 * (sky[k] - ground[k]) * y1;
                }
            }
            Environment::Map(m) => {
                let mut acc = [[0.0f64; 3]; 9];
                for j in 0..m.height {
                    // The row's exact solid angle per texel: (2π / w)(cos θ_top − cos θ_bottom).
                    let theta = |k: u32| std::f64::consts::PI * k as f64 / m.height as f64;
                    let w = std::f64::consts::TAU / m.width as f64
                        * (theta(j).cos() - theta(j + 1).cos());
                    for i in 0..m.width {
                        let d = m.direction(i, j);
                        let l = m.texels[(j * m.width + i) as usize];
                        for (a, y) in acc.iter_mut().zip(sh9_basis(d)) {
                            for k in 0..3 {
                                a[k] += w * (y * l[k]) as f64;
                            }
                        }
                    }
                }
                for (ci, a) in c.iter_mut().zip(acc) {
                    *ci = a.map(|v| v as f32);
                }
            }
        }
        c
    }

    /// The diffuse irradiance (normalised by π) as harmonics: [`Environment::radiance_sh`]
    /// convolved with the clamped cosine.
    pub fn irradiance_sh(&self) -> IrradianceSh {
        let mut coefficients = self.radiance_sh();
        for (c, w) in coefficients.iter_mut().zip(COSINE_BANDS) {
            *c = c.map(|v| v * w);
        }
        IrradianceSh { coefficients }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Irradiance / π by brute force: a midpoint sum over the hemisphere around `n`.
    fn brute_irradiance(env: &Environment, n: [f32; 3]) -> [f32; 3] {
        let n = glam::Vec3::from(n).normalize();
        let (mut e, steps) = ([0.0f64; 3], 400);
        for a in 0..steps {
            for b in 0..2 * steps {
                let theta = std::f32::consts::PI * (a as f32 + 0.5) / steps as f32;
                let phi = std::f32::consts::PI * (b as f32 + 0.5) / steps as f32;
                let d = glam::Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                );
                let cos = d.dot(n);
                if cos <= 0.0 {
                    continue;
                }
                let w = (std::f32::consts::PI / steps as f32).powi(2) * theta.sin() * cos;
                let l = env.radiance(d.to_array());
                for k in 0..3 {
                    e[k] += (w * l[k]) as f64;
                }
            }
        }
        e.map(|v| (v / std::f64::consts::PI) as f32)
    }

    #[test]
    fn constant_and_gradient_irradiance_are_exact() {
        let grad = Environment::Gradient {
            sky: [1.0, 0.5, 0.2],
            ground: [0.1, 0.2, 0.3],
        };
        for env in [Environment::Constant([0.3, 0.6, 0.9]), grad] {
            let sh = env.irradiance_sh();
            for n in [
                [0.0, 1.0, 0.0],
                [0.0, -1.0, 0.0],
                [0.6, 0.0, 0.8],
                [0.48, 0.6, 0.64],
            ] {
                let (a, b) = (sh.eval(n), brute_irradiance(&env, n));
                for k in 0..3 {
                    assert!(
                        (a[k] - b[k]).abs() < 2e-3,
                        "{env:?} at {n:?}: {a:?} vs {b:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_map_projects_like_its_closed_form() {
        // The gradient sampled into a map projects onto the gradient's own harmonics.
        let grad = Environment::Gradient {
            sky: [2.0, 1.0, 0.5],
            ground: [0.0, 0.25, 0.5],
        };
        let (w, h) = (64u32, 32u32);
        let mut texels = Vec::new();
        let probe = EnvironmentMap::new(1, 1, vec![[0.0; 3]]).unwrap();
        let probe = EnvironmentMap {
            width: w,
            height: h,
            ..probe
        };
        for j in 0..h {
            for i in 0..w {
                texels.push(grad.radiance(probe.direction(i, j)));
            }
        }
        let map = Environment::Map(EnvironmentMap::new(w, h, texels).unwrap());
        let (a, b) = (map.radiance_sh(), grad.radiance_sh());
        for (x, y) in a.iter().zip(b) {
            for k in 0..3 {
                assert!((x[k] - y[k]).abs() < 5e-3, "{a:?} vs {b:?}");
            }
        }
        // And its texels are found again along their own directions.
        if let Environment::Map(m) = &map {
            for (i, j) in [(0, 0), (17, 9), (63, 31)] {
                assert_eq!(
                    m.radiance(m.direction(i, j)),
                    m.texels[(j * w + i) as usize]
                );
            }
        }
    }

    #[test]
    fn a_constant_map_of_any_size_projects_exactly() {
        // Each row weighted by its exact solid angle: even one row integrates to 4π.
        for (w, h) in [(1, 1), (4, 2), (7, 3)] {
            let map = EnvironmentMap::new(w, h, vec![[0.5, 1.0, 2.0]; (w * h) as usize]).unwrap();
            let want = Environment::Constant([0.5, 1.0, 2.0]).radiance_sh();
            let got = Environment::Map(map).radiance_sh();
            for k in 0..3 {
                assert!((got[0][k] - want[0][k]).abs() < 1e-5, "{w}x{h}: {got:?}");
            }
        }
    }

    #[test]
    fn bad_maps_and_colours_are_refused() {
        assert!(EnvironmentMap::new(0, 1, vec![]).is_err());
        assert!(EnvironmentMap::new(2, 1, vec![[0.0; 3]]).is_err());
        assert!(EnvironmentMap::new(1, 1, vec![[f32::NAN, 0.0, 0.0]]).is_err());
        assert!(EnvironmentMap::new(1, 1, vec![[-1.0, 0.0, 0.0]]).is_err());
        assert!(Environment::Constant([f32::INFINITY, 0.0, 0.0])
            .validate()
            .is_err());
        assert!(Environment::SKY.validate().is_ok());
        // A map built field by field is checked too.
        let broken = EnvironmentMap {
            width: 2,
            height: 0,
            texels: vec![],
        };
        assert!(Environment::Map(broken).validate().is_err());
    }
}
