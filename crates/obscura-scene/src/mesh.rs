//! Triangle meshes: loading every mesh of a glTF 2.0 or OBJ file with node transforms
//! applied, flattened into one indexed position list, with a diffuse albedo per vertex
//! (glTF's base colour factor, OBJ's `Kd`; white where the file names none).

use crate::SceneError;
use glam::{Mat4, Vec3};
#[cfg(not(target_arch = "wasm32"))]
use std::path::Path;

/// An indexed triangle mesh in world space.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub positions: Vec<[f32; 3]>,
    /// Three indices per triangle, each `< positions.len()`.
    pub indices: Vec<u32>,
    /// Linear diffuse albedo per vertex, aligned with `positions` (vertices missing here
    /// are white, [`Mesh::vertex_colours`]). A vertex belongs to one primitive, so one
    /// material: a triangle's albedo is its first vertex's ([`Mesh::triangle_colours`]).
    pub colours: Vec<[f32; 3]>,
}

/// The albedo of a surface whose file names none: glTF's default base colour factor.
pub const DEFAULT_ALBEDO: [f32; 3] = [1.0; 3];

/// An axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }
    pub fn diagonal(&self) -> f32 {
        (self.max - self.min).length()
    }
}

impl Mesh {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Bounds of the referenced vertices, `None` for an empty mesh.
    pub fn bounds(&self) -> Option<Aabb> {
        let mut it = self
            .indices
            .iter()
            .map(|&i| Vec3::from(self.positions[i as usize]));
        let first = it.next()?;
        let (min, max) = it.fold((first, first), |(a, b), p| (a.min(p), b.max(p)));
        Some(Aabb { min, max })
    }

    /// Albedo per vertex, one per position ([`DEFAULT_ALBEDO`] past `colours`).
    pub fn vertex_colours(&self) -> Vec<[f32; 3]> {
        (0..self.positions.len())
            .map(|i| self.colours.get(i).copied().unwrap_or(DEFAULT_ALBEDO))
            .collect()
    }

    /// Albedo per triangle: its first vertex's.
    pub fn triangle_colours(&self) -> Vec<[f32; 3]> {
        self.indices
            .chunks_exact(3)
            .map(|t| {
                self.colours
                    .get(t[0] as usize)
                    .copied()
                    .unwrap_or(DEFAULT_ALBEDO)
            })
            .collect()
    }

    /// Appends `positions` (transformed by `m`) and triangles `indices` (local to them),
    /// skipping triangles with an out-of-range index or a non-finite vertex; white.
    pub fn append(&mut self, m: Mat4, positions: &[[f32; 3]], indices: &[u32]) {
        self.append_coloured(m, positions, indices, DEFAULT_ALBEDO);
    }

    /// [`Mesh::append`] with albedo `colour` (clamped to [0, 1]; NaN is 0).
    pub fn append_coloured(
        &mut self,
        m: Mat4,
        positions: &[[f32; 3]],
        indices: &[u32],
        colour: [f32; 3],
    ) {
        let colour = colour.map(|c| if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) });
        // Earlier vertices appended without colours are white.
        let n = self.positions.len();
        self.colours.resize(n, DEFAULT_ALBEDO);
        self.colours.resize(n + positions.len(), colour);
        let base = self.positions.len() as u32;
        self.positions.extend(
            positions
                .iter()
                .map(|&p| m.transform_point3(Vec3::from(p)).to_array()),
        );
        for t in indices.chunks_exact(3) {
            let ok = t.iter().all(|&i| {
                (i as usize) < positions.len()
                    && self.positions[(base + i) as usize]
                        .iter()
                        .all(|c| c.is_finite())
            });
            if ok {
                self.indices.extend(t.iter().map(|&i| base + i));
            }
        }
    }

    /// The mesh of a binary glTF (`.glb`) held in memory, `name` in messages: a browser's
    /// fetched scene.
    pub fn from_glb(name: &str, bytes: &[u8]) -> Result<Mesh, SceneError> {
        let mesh = crate::load::glb_mesh(std::path::Path::new(name), bytes)?;
        if mesh.indices.is_empty() {
            return Err(SceneError::Empty(name.into()));
        }
        Ok(mesh)
    }

    /// Loads a `.glb`, `.gltf` or `.obj` file. Native only (a browser has no files; the
    /// demo page builds its scene in code).
    #[cfg(not(target_arch = "wasm32"))]
    pub fn load(path: &Path) -> Result<Mesh, SceneError> {
        use crate::load::{load_gltf, load_obj};
        let name = path.display().to_string();
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .unwrap_or_default();
        let mesh = match ext.as_str() {
            "glb" | "gltf" => load_gltf(path)?,
            "obj" => load_obj(path)?,
            _ => return Err(SceneError::UnsupportedExtension(ext)),
        };
        if mesh.indices.is_empty() {
            return Err(SceneError::Empty(name));
        }
        Ok(mesh)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn append_drops_bad_triangles_and_applies_transform() {
        let mut m = Mesh::default();
        let pos = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, f32::NAN, 0.0],
            [0.0, 1.0, 0.0],
        ];
        m.append(
            Mat4::from_translation(Vec3::new(0.0, 0.0, 5.0)),
            &pos,
            &[0, 1, 3, 0, 1, 2, 0, 1, 9],
        );
        assert_eq!(m.indices, vec![0, 1, 3]);
        assert_eq!(m.positions[1], [1.0, 0.0, 5.0]);
        let b = m.bounds().unwrap();
        assert_eq!(b.min, Vec3::new(0.0, 0.0, 5.0));
        assert_eq!(b.max, Vec3::new(1.0, 1.0, 5.0));
    }
}
