//! Loading: every shared mesh loads and renders, the default scene's AO has real occlusion,
//! bad files are typed errors, the fuzzed loader never panics, albedo reaches the G-buffer.

use super::*;

#[test]
fn every_shared_mesh_loads_and_renders() {
    let _g = lock();
    let mut files: Vec<PathBuf> = std::fs::read_dir(shared_scenes())
        .unwrap()
        .flat_map(|d| std::fs::read_dir(d.unwrap().path()).into_iter().flatten())
        .map(|e| e.unwrap().path())
        .filter(|p| {
            matches!(
                p.extension().and_then(|e| e.to_str()),
                Some("glb" | "gltf" | "obj")
            )
        })
        .collect();
    files.sort();
    assert!(
        files.len() >= 10,
        "expected the shared meshes, found {files:?}"
    );
    for f in &files {
        let mesh = Mesh::load(f).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        let b = mesh.bounds().unwrap();
        let cam = Camera::framing(&b, CameraProjection::Perspective { fov_y_deg: 50.0 });
        let (depth, ao) = render(&mesh, &cam, 96, 64, 0.03 * b.diagonal());
        let covered = depth.iter().filter(|&&d| d > SKY_DEPTH).count();
        assert!(
            covered > 96 * 64 / 20,
            "{}: only {covered} pixels covered",
            f.display()
        );
        assert!(
            ao.iter().all(|a| (0.0..=1.0).contains(a)),
            "{}: AO out of range",
            f.display()
        );
        ctx()
            .take_errors()
            .unwrap_or_else(|e| panic!("{}: {e}", f.display()));
    }
}

#[test]
fn default_scene_has_real_occlusion() {
    let _g = lock();
    let mesh = default_scene::mesh();
    let (depth, ao) = render(&mesh, &default_scene::camera(), 320, 180, 1.0);
    assert!(depth.contains(&SKY_DEPTH), "some sky is visible");
    let n = ao.len() as f32;
    let mean = ao.iter().sum::<f32>() / n;
    let var = ao.iter().map(|a| (a - mean).powi(2)).sum::<f32>() / n;
    let dark = ao.iter().filter(|&&a| a < 0.7).count();
    assert!(
        mean < 0.99 && var.sqrt() > 0.02,
        "AO nearly constant: mean {mean}, sd {}",
        var.sqrt()
    );
    assert!(dark > 20, "only {dark} pixels below 0.7");
}

#[test]
fn bad_scene_files_are_typed_errors() {
    let dir = scratch("bad");
    assert!(matches!(
        Mesh::load(&dir.join("missing.glb")),
        Err(SceneError::Io { .. })
    ));
    let stl = dir.join("model.stl");
    std::fs::write(&stl, b"solid x").unwrap();
    assert!(matches!(
        Mesh::load(&stl),
        Err(SceneError::UnsupportedExtension(_))
    ));
    // A real .glb cut short.
    let full = std::fs::read(shared_scenes().join("cornell_box/cornell_box.glb")).unwrap();
    for cut in [0, 12, 100, full.len() / 2, full.len() - 1] {
        let t = dir.join(format!("truncated{cut}.glb"));
        std::fs::write(&t, &full[..cut]).unwrap();
        assert!(
            matches!(Mesh::load(&t), Err(SceneError::Gltf { .. })),
            "cut at {cut}"
        );
    }
    // OBJ whose faces reference vertices that do not exist.
    let obj = dir.join("dangling.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nf 1 2 7\n").unwrap();
    assert!(Mesh::load(&obj).is_err());
    let empty = dir.join("empty.obj");
    std::fs::write(&empty, "# nothing\n").unwrap();
    assert!(matches!(Mesh::load(&empty), Err(SceneError::Empty(_))));
    std::fs::remove_dir_all(dir).unwrap();
}

/// Mutated scene files (byte flips, truncation, duplication, insertion of the shared Cornell
/// box .glb and .obj) never panic the loader: each is a mesh or a typed error. 400 cases per
/// format or 10 s in CI ([`obscura::fuzz::Budget`] for a long run by hand).
#[test]
fn fuzz_mesh_loader() {
    let dir = scratch("fuzz");
    let mut state = 0x1234_5678_9abc_def1u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for name in ["cornell_box.glb", "cornell_box.obj"] {
        let valid = std::fs::read(shared_scenes().join("cornell_box").join(name)).unwrap();
        let path = dir.join(name);
        let (mut ok, mut err) = (0, 0);
        let budget = obscura::fuzz::Budget::from_env(400, 10);
        for case in (0..).take_while(|&c| budget.more(c)) {
            let mut v = valid.clone();
            for _ in 0..1 + next() % 4 {
                let i = (next() as usize) % (v.len() + 1);
                match next() % 4 {
                    0 if i < v.len() => v[i] ^= 1 << (next() % 8),
                    1 => v.truncate(i),
                    2 => {
                        let j = (i + (next() as usize % 64)).min(v.len());
                        let chunk = v[i..j].to_vec();
                        v.splice(i..i, chunk);
                    }
                    _ => v.insert(i, next() as u8),
                }
            }
            std::fs::write(&path, &v).unwrap();
            match std::panic::catch_unwind(|| Mesh::load(&path)) {
                Ok(Ok(_)) => ok += 1,
                Ok(Err(_)) => err += 1,
                Err(_) => panic!(
                    "{name}: case {case} panicked the loader ({} bytes)",
                    v.len()
                ),
            }
        }
        eprintln!("fuzz {name}: {ok} loaded, {err} refused, no panic");
        assert!(ok > 0 && err > 0, "{name}: {ok} loaded, {err} refused");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// Albedo comes from glTF base colour factors and OBJ `Kd` (white without a material or
/// with a missing library), and the G-buffer's albedo target holds it per pixel.
#[test]
fn albedo_comes_from_materials_and_reaches_the_gbuffer() {
    let _g = lock();
    let dir = scratch("albedo");
    // One large triangle in z = 0, material base colour (0.2, 0.4, 0.6).
    let pos: [[f32; 3]; 3] = [[-10.0, -10.0, 0.0], [10.0, -10.0, 0.0], [0.0, 10.0, 0.0]];
    std::fs::write(dir.join("tri.bin"), bytemuck::cast_slice(&pos)).unwrap();
    let gltf = r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
        "nodes":[{"mesh":0}],
        "meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],
        "materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.2,0.4,0.6,1.0]}}],
        "buffers":[{"byteLength":36,"uri":"tri.bin"}],
        "bufferViews":[{"buffer":0,"byteLength":36}],
        "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",
            "min":[-10,-10,0],"max":[10,10,0]}]}"#;
    std::fs::write(dir.join("tri.gltf"), gltf).unwrap();
    let mesh = Mesh::load(&dir.join("tri.gltf")).unwrap();
    assert_eq!(mesh.triangle_colours(), vec![[0.2, 0.4, 0.6]]);

    // OBJ with a material library beside it, and one whose library is missing.
    std::fs::write(dir.join("m.mtl"), "newmtl rust\nKd 0.9 0.1 0.2\n").unwrap();
    let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl rust\nf 1 2 3\n";
    std::fs::write(dir.join("m.obj"), obj).unwrap();
    assert_eq!(
        Mesh::load(&dir.join("m.obj")).unwrap().triangle_colours(),
        vec![[0.9, 0.1, 0.2]]
    );
    std::fs::write(dir.join("lost.obj"), obj.replace("m.mtl", "lost.mtl")).unwrap();
    assert_eq!(
        Mesh::load(&dir.join("lost.obj"))
            .unwrap()
            .triangle_colours(),
        vec![obscura_scene::DEFAULT_ALBEDO]
    );
    // The shared Cornell box: red and green walls.
    let cornell = Mesh::load(&shared_scenes().join("cornell_box/cornell_box.obj")).unwrap();
    let colours = cornell.triangle_colours();
    assert!(colours.contains(&[1.0, 0.0, 0.0]) && colours.contains(&[0.0, 1.0, 0.0]));

    // The G-buffer: the triangle's albedo in the middle, alpha 0 (sky) in a corner.
    let c = ctx();
    let raster = GBufferRenderer::new(&c.device);
    let gm = raster.upload(c, &mesh).unwrap();
    let cam = Camera {
        eye: glam::Vec3::new(0.0, 0.0, 5.0),
        target: glam::Vec3::ZERO,
        up: glam::Vec3::Y,
        projection: CameraProjection::Perspective { fov_y_deg: 90.0 },
        near: 0.1,
        far: 100.0,
    };
    let (w, h) = (32, 24);
    let g = raster.render(c, &gm, &cam, w, h).unwrap();
    let bytes = c.read_texture(&g.albedo).unwrap();
    let at = |x: u32, y: u32| {
        let i = ((y * w + x) * 4) as usize;
        [bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]
    };
    let mid = at(w / 2, h / 2);
    for (got, want) in mid.iter().zip([51u8, 102, 153, 255]) {
        assert!(got.abs_diff(want) <= 1, "albedo {mid:?}");
    }
    assert_eq!(at(0, 0)[3], 0, "sky albedo {:?}", at(0, 0));
    std::fs::remove_dir_all(dir).unwrap();
}
