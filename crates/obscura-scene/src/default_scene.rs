//! The built-in default scene, generated in code so `obscura render` needs no download:
//! a courtyard with a colonnade of arches, a flight of steps, objects resting on the
//! floor and a narrow gap between two blocks — every classic AO situation (creases,
//! contact shadows, concave corners, thin gaps, curved occluders). Units: metres, +Y up.

use crate::Mesh;
#[cfg(feature = "gpu")]
use crate::{Camera, CameraProjection};
use glam::{Mat4, Vec3};
use std::f32::consts::PI;

#[derive(Default)]
struct Builder {
    mesh: Mesh,
}

impl Builder {
    fn quad(&mut self, a: Vec3, b: Vec3, c: Vec3, d: Vec3) {
        let pos = [a.to_array(), b.to_array(), c.to_array(), d.to_array()];
        self.mesh.append(Mat4::IDENTITY, &pos, &[0, 1, 2, 0, 2, 3]);
    }

    /// An axis-aligned box from `min` to `max`.
    fn cuboid(&mut self, min: Vec3, max: Vec3) {
        let v = |x: bool, y: bool, z: bool| {
            Vec3::new(
                if x { max.x } else { min.x },
                if y { max.y } else { min.y },
                if z { max.z } else { min.z },
            )
        };
        let (f, t) = (false, true);
        self.quad(v(f, f, f), v(t, f, f), v(t, t, f), v(f, t, f));
        self.quad(v(f, f, t), v(t, f, t), v(t, t, t), v(f, t, t));
        self.quad(v(f, f, f), v(f, t, f), v(f, t, t), v(f, f, t));
        self.quad(v(t, f, f), v(t, t, f), v(t, t, t), v(t, f, t));
        self.quad(v(f, f, f), v(t, f, f), v(t, f, t), v(f, f, t));
        self.quad(v(f, t, f), v(t, t, f), v(t, t, t), v(f, t, t));
    }

    /// A vertical cylinder (with caps) standing on `base`.
    fn cylinder(&mut self, base: Vec3, radius: f32, height: f32, segments: u32) {
        let p = |i: u32, y: f32| {
            let a = i as f32 / segments as f32 * 2.0 * PI;
            base + Vec3::new(radius * a.cos(), y, radius * a.sin())
        };
        for i in 0..segments {
            self.quad(p(i, 0.0), p(i + 1, 0.0), p(i + 1, height), p(i, height));
            let top = base + Vec3::Y * height;
            self.quad(top, p(i, height), p(i + 1, height), top);
        }
    }

    /// A UV sphere.
    fn sphere(&mut self, center: Vec3, radius: f32, rings: u32, segments: u32) {
        let p = |r: u32, s: u32| {
            let th = r as f32 / rings as f32 * PI;
            let ph = s as f32 / segments as f32 * 2.0 * PI;
            center + radius * Vec3::new(th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin())
        };
        for r in 0..rings {
            for s in 0..segments {
                self.quad(p(r, s), p(r, s + 1), p(r + 1, s + 1), p(r + 1, s));
            }
        }
    }

    /// A semicircular arch in the XY plane spanning `x.0..x.1` with its springing line at
    /// height `y`, `depth` thick in z around `z`, and `ring` wide radially.
    fn arch(&mut self, x: (f32, f32), y: f32, z: f32, depth: f32, ring: f32, segments: u32) {
        let c = Vec3::new(0.5 * (x.0 + x.1), y, z);
        let r_in = 0.5 * (x.1 - x.0);
        let r_out = r_in + ring;
        let at = |r: f32, i: u32, dz: f32| {
            let a = i as f32 / segments as f32 * PI;
            c + Vec3::new(r * a.cos(), r * a.sin(), dz)
        };
        let (zf, zb) = (0.5 * depth, -0.5 * depth);
        for i in 0..segments {
            let j = i + 1;
            self.quad(
                at(r_in, i, zf),
                at(r_in, j, zf),
                at(r_in, j, zb),
                at(r_in, i, zb),
            );
            self.quad(
                at(r_out, i, zf),
                at(r_out, j, zf),
                at(r_out, j, zb),
                at(r_out, i, zb),
            );
            self.quad(
                at(r_in, i, zf),
                at(r_out, i, zf),
                at(r_out, j, zf),
                at(r_in, j, zf),
            );
            self.quad(
                at(r_in, i, zb),
                at(r_out, i, zb),
                at(r_out, j, zb),
                at(r_in, j, zb),
            );
        }
    }
}

/// The default scene's geometry.
pub fn mesh() -> Mesh {
    let mut b = Builder::default();
    // Floor and two enclosing walls.
    b.cuboid(Vec3::new(-10.0, -0.2, -10.0), Vec3::new(10.0, 0.0, 10.0));
    b.cuboid(Vec3::new(-10.0, 0.0, -10.0), Vec3::new(10.0, 6.0, -9.5));
    b.cuboid(Vec3::new(-10.0, 0.0, -9.5), Vec3::new(-9.5, 6.0, 10.0));
    // Colonnade: columns on plinths, arches between them, an entablature on top.
    let xs = [-8.0f32, -5.0, -2.0, 1.0, 4.0];
    let (z, col_r, col_h) = (-5.5f32, 0.35f32, 3.5f32);
    for &x in &xs {
        b.cuboid(
            Vec3::new(x - 0.5, 0.0, z - 0.5),
            Vec3::new(x + 0.5, 0.3, z + 0.5),
        );
        b.cylinder(Vec3::new(x, 0.3, z), col_r, col_h, 24);
        b.cuboid(
            Vec3::new(x - 0.45, 3.8, z - 0.45),
            Vec3::new(x + 0.45, 4.0, z + 0.45),
        );
    }
    for w in xs.windows(2) {
        b.arch((w[0] + 0.45, w[1] - 0.45), 4.0, z, 0.9, 0.35, 16);
    }
    b.cuboid(Vec3::new(-8.6, 5.45, z - 0.5), Vec3::new(4.6, 6.0, z + 0.5));
    // Steps against the right side, rising towards +x.
    for i in 0..5 {
        let h = 0.2 * (i + 1) as f32;
        let x0 = 5.0 + 0.45 * i as f32;
        b.cuboid(Vec3::new(x0, 0.0, -3.0), Vec3::new(7.5, h, 1.0));
    }
    // Two blocks separated by a narrow (8 cm) gap.
    b.cuboid(Vec3::new(-3.0, 0.0, 0.5), Vec3::new(-1.54, 1.6, 2.5));
    b.cuboid(Vec3::new(-1.46, 0.0, 0.5), Vec3::new(0.0, 1.6, 2.5));
    // Objects resting on the floor: a sphere, a cube, a stack of crates, a fallen drum.
    b.sphere(Vec3::new(2.2, 0.7, 2.0), 0.7, 24, 48);
    b.cuboid(Vec3::new(-6.5, 0.0, 0.0), Vec3::new(-5.5, 1.0, 1.0));
    b.cuboid(Vec3::new(-6.3, 1.0, 0.2), Vec3::new(-5.7, 1.6, 0.8));
    b.cuboid(Vec3::new(-5.3, 0.0, 0.3), Vec3::new(-4.7, 0.6, 0.9));
    let drum = Mat4::from_translation(Vec3::new(0.8, 0.4, -1.8))
        * Mat4::from_rotation_z(PI / 2.0)
        * Mat4::from_translation(Vec3::new(0.0, -0.7, 0.0));
    let mut d = Builder::default();
    d.cylinder(Vec3::ZERO, 0.4, 1.4, 24);
    b.mesh.append(drum, &d.mesh.positions, &d.mesh.indices);
    b.mesh
}

/// The default scene's camera: from the front right, looking into the courtyard.
#[cfg(feature = "gpu")]
pub fn camera() -> Camera {
    Camera {
        eye: Vec3::new(6.5, 3.4, 8.0),
        target: Vec3::new(-1.5, 1.2, -3.5),
        up: Vec3::Y,
        projection: CameraProjection::Perspective { fov_y_deg: 60.0 },
        near: 0.05,
        far: 40.0,
    }
}
