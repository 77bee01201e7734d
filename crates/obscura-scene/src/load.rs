//! Scene files: glTF 2.0 and OBJ into a [`Mesh`]. Files and OBJ are native only; a GLB's
//! bytes parse anywhere (the demo page fetches Sponza's).

use crate::{Mesh, SceneError};
use glam::Mat4;
use std::path::Path;

#[cfg(not(target_arch = "wasm32"))]
fn io_err(path: &Path, source: std::io::Error) -> SceneError {
    SceneError::Io {
        path: path.display().to_string(),
        source,
    }
}

#[cfg(not(target_arch = "wasm32"))]
pub(crate) fn load_gltf(path: &Path) -> Result<Mesh, SceneError> {
    let bytes = std::fs::read(path).map_err(|e| io_err(path, e))?;
    glb_mesh(path, &bytes)
}

/// A glTF's mesh from its bytes (`path` names it and holds its external buffers, if any).
pub(crate) fn glb_mesh(path: &Path, bytes: &[u8]) -> Result<Mesh, SceneError> {
    // The gltf crate asserts and panics on some malformed files (fuzz_mesh_loader found an
    // accessor stride check); a panic anywhere in parsing or reading is a typed error
    // (natively: a browser's wasm aborts on a panic).
    #[cfg(target_arch = "wasm32")]
    return gltf_mesh(path, bytes);
    #[cfg(not(target_arch = "wasm32"))]
    std::panic::catch_unwind(|| gltf_mesh(path, bytes)).unwrap_or_else(|_| {
        Err(SceneError::Gltf {
            path: path.display().to_string(),
            reason: "the glTF parser failed on malformed input".into(),
        })
    })
}

fn gltf_mesh(path: &Path, bytes: &[u8]) -> Result<Mesh, SceneError> {
    let err = |reason: String| SceneError::Gltf {
        path: path.display().to_string(),
        reason,
    };
    // Checked first, so they fail without a panic message: two malformed inputs on which
    // the gltf crate panics (found by fuzz_mesh_loader): a GLB header length below 12 (an
    // unsigned underflow) and an out-of-range POSITION accessor (its validator indexes
    // before checking).
    if bytes.len() >= 12 && bytes.starts_with(b"glTF") {
        let length = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]);
        if length < 12 {
            return Err(err(format!("GLB header length {length} is below 12")));
        }
    }
    let unchecked =
        gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| err(e.to_string()))?;
    check_accessors(unchecked.document.as_json()).map_err(err)?;
    let gltf = gltf::Gltf::from_slice(bytes).map_err(|e| err(e.to_string()))?;
    let buffers = gltf::import_buffers(&gltf.document, path.parent(), gltf.blob.clone())
        .map_err(|e| err(e.to_string()))?;
    let mut mesh = Mesh::default();
    let doc = &gltf.document;
    // The default scene, else every scene; each node's world transform applied.
    let roots: Vec<gltf::Node> = match doc.default_scene() {
        Some(s) => s.nodes().collect(),
        None => doc.scenes().flat_map(|s| s.nodes()).collect(),
    };
    let mut stack: Vec<(gltf::Node, Mat4, u32)> =
        roots.into_iter().map(|n| (n, Mat4::IDENTITY, 0)).collect();
    while let Some((node, parent, depth)) = stack.pop() {
        if depth > 256 {
            return Err(err("node hierarchy deeper than 256 levels (cycle?)".into()));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(m) = node.mesh() {
            for prim in m.primitives() {
                let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
                let Some(pos) = reader.read_positions() else {
                    continue;
                };
                let pos: Vec<[f32; 3]> = pos.collect();
                let idx: Vec<u32> = match reader.read_indices() {
                    Some(i) => i.into_u32().collect(),
                    None => (0..pos.len() as u32).collect(),
                };
                let tris = match prim.mode() {
                    gltf::mesh::Mode::Triangles => idx,
                    gltf::mesh::Mode::TriangleStrip => (2..idx.len())
                        .flat_map(|i| {
                            if i % 2 == 0 {
                                [idx[i - 2], idx[i - 1], idx[i]]
                            } else {
                                [idx[i - 1], idx[i - 2], idx[i]]
                            }
                        })
                        .collect(),
                    gltf::mesh::Mode::TriangleFan => (2..idx.len())
                        .flat_map(|i| [idx[0], idx[i - 1], idx[i]])
                        .collect(),
                    _ => continue, // points and lines occlude nothing
                };
                let [r, g, b, _] = prim.material().pbr_metallic_roughness().base_color_factor();
                mesh.append_coloured(world, &pos, &tris, [r, g, b]);
            }
        }
        stack.extend(node.children().map(|c| (c, world, depth + 1)));
    }
    Ok(mesh)
}

/// Every accessor a mesh primitive names exists, and those the reader decodes are what it
/// assumes, so the gltf crate's assertions never fire (a long fuzz run hit three: a
/// POSITION accessor that is not VEC3 of f32, indices of a float type, and a zero count):
/// POSITION is VEC3 f32, indices are SCALAR u8/u16/u32, counts are at least 1, strides at
/// least an element, and the data lies inside its buffer view.
fn check_accessors(root: &gltf::json::Root) -> Result<(), String> {
    use gltf::json::accessor::{ComponentType as C, GenericComponentType, Type};
    use gltf::json::mesh::Semantic;
    use gltf::json::validation::Checked;
    let n = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for p in &mesh.primitives {
            let named = p.attributes.values().chain(p.indices.as_ref());
            if let Some(bad) = named.map(|i| i.value()).find(|&i| i >= n) {
                return Err(format!("mesh {m} names accessor {bad} of {n}"));
            }
            let position = p
                .attributes
                .iter()
                .filter(|(s, _)| **s == Checked::Valid(Semantic::Positions))
                .map(|(_, i)| (i.value(), true));
            let indices = p.indices.iter().map(|i| (i.value(), false));
            for (i, is_position) in position.chain(indices) {
                let a = &root.accessors[i];
                let component = match a.component_type {
                    Checked::Valid(GenericComponentType(c)) => Some(c),
                    Checked::Invalid => None,
                };
                let elem: u64 = match (is_position, a.type_, component) {
                    (true, Checked::Valid(Type::Vec3), Some(C::F32)) => 12,
                    (false, Checked::Valid(Type::Scalar), Some(C::U8)) => 1,
                    (false, Checked::Valid(Type::Scalar), Some(C::U16)) => 2,
                    (false, Checked::Valid(Type::Scalar), Some(C::U32)) => 4,
                    (true, t, c) => {
                        return Err(format!(
                            "mesh {m}: POSITION accessor {i} is {t:?} of {c:?}, not VEC3 of f32"
                        ))
                    }
                    (false, t, c) => {
                        return Err(format!(
                            "mesh {m}: index accessor {i} is {t:?} of {c:?}, not SCALAR u8/u16/u32"
                        ))
                    }
                };
                let count = a.count.0;
                if count == 0 {
                    return Err(format!("mesh {m}: accessor {i} has count 0"));
                }
                let (Some(v), None) = (a.buffer_view, &a.sparse) else {
                    continue;
                };
                let view = root
                    .buffer_views
                    .get(v.value())
                    .ok_or_else(|| format!("accessor {i} names buffer view {}", v.value()))?;
                let stride = view.byte_stride.map_or(elem, |s| s.0 as u64);
                let end = (stride >= elem)
                    .then(|| stride.checked_mul(count - 1))
                    .flatten()
                    .and_then(|e| e.checked_add(elem))
                    .and_then(|e| e.checked_add(a.byte_offset.map_or(0, |o| o.0)));
                if end.is_none_or(|e| e > view.byte_length.0) {
                    return Err(format!(
                        "mesh {m}: accessor {i} ({count} elements, stride {stride}) does not \
                         fit its {}-byte buffer view",
                        view.byte_length.0
                    ));
                }
            }
        }
    }
    Ok(())
}

#[cfg(not(target_arch = "wasm32"))]
pub(crate) fn load_obj(path: &Path) -> Result<Mesh, SceneError> {
    // Read the file ourselves so a missing file is an I/O error, not a parse error.
    let text = std::fs::read(path).map_err(|e| io_err(path, e))?;
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    // Materials give the albedo (`Kd`). The library is read only from the OBJ's own folder,
    // by file name, and a missing or malformed one leaves the surfaces white: AO needs
    // no material, so a material problem never fails the load.
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let (models, materials) =
        tobj::load_obj_buf(&mut std::io::Cursor::new(text), &opts, |mtl: &Path| {
            let Some(name) = mtl.file_name() else {
                return Ok((Vec::new(), Default::default()));
            };
            let Ok(bytes) = std::fs::read(dir.join(name)) else {
                return Ok((Vec::new(), Default::default()));
            };
            tobj::load_mtl_buf(&mut std::io::Cursor::new(bytes))
                .or_else(|_| Ok((Vec::new(), Default::default())))
        })
        .map_err(|e| SceneError::Obj {
            path: path.display().to_string(),
            reason: e.to_string(),
        })?;
    let materials = materials.unwrap_or_default();
    let mut mesh = Mesh::default();
    for m in models {
        let pos: Vec<[f32; 3]> = m
            .mesh
            .positions
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        let colour = m
            .mesh
            .material_id
            .and_then(|i| materials.get(i))
            .and_then(|mat| mat.diffuse)
            .unwrap_or(crate::DEFAULT_ALBEDO);
        mesh.append_coloured(Mat4::IDENTITY, &pos, &m.mesh.indices, colour);
    }
    Ok(mesh)
}
