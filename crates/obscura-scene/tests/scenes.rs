//! Every shared mesh loads and rasterizes without a wgpu error; the default scene's AO
//! has real occlusion; bad scene files give typed errors. Needs `../shared/scenes`
//! beside the repository (as on every developer machine and in CI) and fails without it.

use obscura::{
    Ao, AoInput, AoMode, AoOptions, AoParams, Denoise, Estimator, GpuContext, NormalEncoding,
    Preset,
};
use obscura_scene::gbuffer::MSAA_SAMPLES;
use obscura_scene::{
    default_scene, Camera, CameraProjection, GBufferRenderer, Mesh, MsaaDepth, SceneError,
    DEPTH_CONVENTION, SKY_DEPTH,
};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};

fn ctx() -> &'static GpuContext {
    static CTX: OnceLock<GpuContext> = OnceLock::new();
    CTX.get_or_init(|| GpuContext::new().unwrap_or_else(|e| panic!("needs a Vulkan adapter: {e}")))
}

fn lock() -> std::sync::MutexGuard<'static, ()> {
    static LOCK: Mutex<()> = Mutex::new(());
    LOCK.lock().unwrap_or_else(|p| p.into_inner())
}

fn shared_scenes() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes");
    assert!(
        dir.is_dir(),
        "shared scenes not found at {} (clone the repo beside shared/)",
        dir.display()
    );
    dir
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("obscura-scene-test-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Renders `mesh` and computes AO in the default mode; returns (depth, ao) read back.
fn render(mesh: &Mesh, cam: &Camera, w: u32, h: u32, radius: f32) -> (Vec<f32>, Vec<f32>) {
    render_with(mesh, cam, w, h, radius, AoOptions::default())
}

fn render_with(
    mesh: &Mesh,
    cam: &Camera,
    w: u32,
    h: u32,
    radius: f32,
    options: AoOptions,
) -> (Vec<f32>, Vec<f32>) {
    let c = ctx();
    let raster = GBufferRenderer::new(&c.device);
    let gm = raster.upload(c, mesh).unwrap();
    let g = raster.render(c, &gm, cam, w, h).unwrap();
    let mut ao = Ao::new(&c.device, options).unwrap();
    let input = AoInput {
        depth: &g.depth_view,
        convention: DEPTH_CONVENTION,
        projection: cam.obscura_projection(w as f32 / h as f32),
        normals: Some((&g.normals_view, NormalEncoding::ViewSigned)),
        viewport: None,
        guard_band: 0,
        second_layer: None,
        output: None,
    };
    let params = AoParams {
        radius,
        ..Default::default()
    };
    c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &params))
        .unwrap();
    (
        c.read_f32(&g.depth).unwrap(),
        c.read_f32(ao.output().unwrap()).unwrap(),
    )
}

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

/// An orthographic camera rasterizes where obscura's projection says: a plane tilted in
/// both axes, seen obliquely, has every covered pixel's depth, unprojected through
/// `Camera::obscura_projection` (pixel centre to NDC, times the half extents, at the
/// linearized depth) and the inverse view, on the plane within 1e-3 of the view's height
/// (Depth32Float reversed-Z keeps about 2⁻²⁴ of the depth range; a half extent wrong by
/// 1% moves points off the plane by about 0.01 of it). And the default scene renders with
/// occlusion.
#[test]
fn orthographic_camera_renders_and_matches_obscura_projection() {
    let _g = lock();
    let (w, h, height) = (96u32, 64u32, 6.0f32);
    let on_plane = |x: f32, z: f32| [x, 0.3 * x + 0.2 * z, z];
    let mut mesh = Mesh::default();
    let corners = [(-20.0, -20.0), (20.0, -20.0), (20.0, 20.0), (-20.0, 20.0)];
    mesh.append(
        glam::Mat4::IDENTITY,
        &corners.map(|(x, z)| on_plane(x, z)),
        &[0, 2, 1, 0, 3, 2],
    );
    let cam = Camera {
        eye: glam::Vec3::new(3.0, 8.0, 6.0),
        target: glam::Vec3::ZERO,
        up: glam::Vec3::Y,
        projection: CameraProjection::Orthographic { height },
        near: 0.1,
        far: 100.0,
    };
    let (depth, _) = render(&mesh, &cam, w, h, 1.0);
    let projection = cam.obscura_projection(w as f32 / h as f32);
    let lin = projection.linearize(DEPTH_CONVENTION).unwrap();
    let [sx, sy] = projection.ndc_to_view_scale();
    let world_from_view = cam.view_matrix().inverse();
    let mut covered = 0;
    for y in 0..h {
        for x in 0..w {
            let Some(d) = lin.apply(depth[(y * w + x) as usize]) else {
                continue;
            };
            let ndc = (
                2.0 * (x as f32 + 0.5) / w as f32 - 1.0,
                1.0 - 2.0 * (y as f32 + 0.5) / h as f32,
            );
            let p = world_from_view.transform_point3(glam::Vec3::new(ndc.0 * sx, ndc.1 * sy, -d));
            let off = p.y - (0.3 * p.x + 0.2 * p.z);
            assert!(
                off.abs() < 1e-3 * height,
                "pixel ({x}, {y}): {p} lies {off} off the plane"
            );
            covered += 1;
        }
    }
    assert_eq!(covered, w * h, "the plane fills the view");
    let mut scene_cam = default_scene::camera();
    scene_cam.projection = CameraProjection::Orthographic { height: 12.0 };
    let (_, ao) = render(&default_scene::mesh(), &scene_cam, 192, 128, 1.0);
    assert!(ao.iter().any(|&a| a < 0.8));
}

/// A G-buffer rendered with a guard band holds the plain render's depth in its middle:
/// the widened camera keeps the pixel size and centres (a wrong field of view shifts every
/// pixel; a band grown by 1.9 g instead of 2 g fails on 80% of them). Pixels whose centre
/// lies on a triangle edge may flip with rounding: at most 0.5% of them may differ by more
/// than 1e-5 of their linear depth (reversed-Z Depth32Float keeps about 2⁻²⁴ of it; the
/// standard convention, near = far / 10⁴, differed by 1e-5 between the two projection
/// matrices). Its AO input is the view inside the band.
#[test]
fn guard_band_render_holds_the_plain_view_in_its_middle() {
    let _g = lock();
    let c = ctx();
    let mesh = default_scene::mesh();
    let raster = GBufferRenderer::new(&c.device);
    let gm = raster.upload(c, &mesh).unwrap();
    let (w, h, g) = (160u32, 90u32, 24u32);
    let mut ortho = default_scene::camera();
    ortho.projection = CameraProjection::Orthographic { height: 12.0 };
    for cam in [default_scene::camera(), ortho] {
        let plain = c
            .read_f32(&raster.render(c, &gm, &cam, w, h).unwrap().depth)
            .unwrap();
        let banded = raster.render_guarded(c, &gm, &cam, (w, h), g).unwrap();
        assert_eq!((banded.width, banded.height), (w + 2 * g, h + 2 * g));
        let input = banded.ao_input(&cam, false);
        assert_eq!(input.guard_band, g);
        assert_eq!(
            input.projection,
            cam.obscura_projection(w as f32 / h as f32)
        );
        let depth = c.read_f32(&banded.depth).unwrap();
        let lin = input.projection.linearize(DEPTH_CONVENTION).unwrap();
        let bw = (w + 2 * g) as usize;
        let off = (0..h as usize)
            .flat_map(|y| (0..w as usize).map(move |x| (x, y)))
            .filter(|&(x, y)| {
                let a = lin.apply(plain[y * w as usize + x]);
                let b = lin.apply(depth[(y + g as usize) * bw + x + g as usize]);
                match (a, b) {
                    (Some(a), Some(b)) => (a - b).abs() > 1e-5 * a,
                    (a, b) => a.is_some() != b.is_some(),
                }
            })
            .count();
        assert!(
            off * 200 <= (w * h) as usize,
            "{:?}: {off} of {} pixels differ",
            cam.projection,
            w * h
        );
    }
}

/// The depth peel on stacked quads seen orthographically from z = 10: front faces at
/// linear depths 5 (everywhere), 6 (left half) and 7 (everywhere), and a back face at 5.5
/// (wound the other way). The second layer is the nearest front face at least the
/// separation behind the first: 6 on the left and 7 on the right with separation 0.5 (never
/// the back face), 7 with 1.5, none with 2.5 (tolerance 1e-4 of the depth; the two columns
/// beside the middle are skipped). A guard band peels the same layer around the view, and
/// a separation that is not positive is refused.
#[test]
fn peel_finds_the_nearest_front_face_behind_the_separation() {
    let _g = lock();
    let c = ctx();
    let mut mesh = Mesh::default();
    let quad = |z: f32| {
        [
            [-9.0, -9.0, z],
            [9.0, -9.0, z],
            [9.0, 9.0, z],
            [-9.0, 9.0, z],
        ]
    };
    let front = [0, 1, 2, 0, 2, 3];
    let back = [0, 2, 1, 0, 3, 2];
    mesh.append(glam::Mat4::IDENTITY, &quad(5.0), &front);
    mesh.append(glam::Mat4::IDENTITY, &quad(4.5), &back);
    mesh.append(glam::Mat4::IDENTITY, &quad(3.0), &front);
    let left_only = [
        [-9.0, -9.0, 4.0],
        [0.0, -9.0, 4.0],
        [0.0, 9.0, 4.0],
        [-9.0, 9.0, 4.0],
    ];
    mesh.append(glam::Mat4::IDENTITY, &left_only, &front);
    let cam = Camera {
        eye: glam::Vec3::new(0.0, 0.0, 10.0),
        target: glam::Vec3::ZERO,
        up: glam::Vec3::Y,
        projection: CameraProjection::Orthographic { height: 6.0 },
        near: 0.1,
        far: 50.0,
    };
    let raster = GBufferRenderer::new(&c.device);
    let gm = raster.upload(c, &mesh).unwrap();
    let (w, h) = (64u32, 32u32);
    for guard in [0u32, 8] {
        let gb = raster.render_guarded(c, &gm, &cam, (w, h), guard).unwrap();
        let lin = cam
            .obscura_projection(w as f32 / h as f32)
            .linearize(DEPTH_CONVENTION)
            .unwrap();
        for (separation, left, right) in [
            (0.5, Some(6.0), Some(7.0)),
            (1.5, Some(7.0), Some(7.0)),
            (2.5, None, None),
        ] {
            let second = raster.peel(c, &gm, &cam, &gb, separation).unwrap();
            assert_eq!(
                (second.texture.width(), second.texture.height()),
                (gb.width, gb.height)
            );
            let depth = c.read_f32(&second.texture).unwrap();
            let bw = gb.width as usize;
            for y in 0..gb.height as usize {
                for x in 0..bw {
                    let xv = x as i64 - guard as i64;
                    if (w as i64 / 2 - 1..=w as i64 / 2).contains(&xv) {
                        continue;
                    }
                    let want = if xv < w as i64 / 2 { left } else { right };
                    let got = lin.apply(depth[y * bw + x]);
                    let ok = match (got, want) {
                        (Some(g), Some(e)) => (g - e).abs() <= 1e-4 * e,
                        (g, e) => g.is_none() && e.is_none(),
                    };
                    assert!(ok, "guard {guard}, separation {separation}, pixel ({x}, {y}): {got:?}, want {want:?}");
                }
            }
        }
        for bad in [0.0, -1.0, f32::NAN] {
            assert!(matches!(
                raster.peel(c, &gm, &cam, &gb, bad),
                Err(SceneError::Camera(_))
            ));
        }
    }
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

#[test]
fn deinterleaved_ao_matches_randomized_on_the_default_scene() {
    // The speed-up must not come from doing different work: the same estimator with the
    // same patterns, only with offsets snapped to the N-pixel lattice.
    let _g = lock();
    let mesh = default_scene::mesh();
    let cam = default_scene::camera();
    let (w, h) = (640, 360);
    for estimator in Estimator::ALL {
        let run = |mode| {
            let o = AoOptions {
                mode,
                ..AoOptions::preset(estimator, Preset::High)
            };
            render_with(&mesh, &cam, w, h, 1.0, o).1
        };
        let base = run(AoMode::Randomized);
        // Stated tolerances (AO units): HBAO RMSE ≤ 0.03, |bias| ≤ 0.005 (measured
        // 0.009 / 0.014 RMSE); GTAO at High RMSE ≤ 0.045, |bias| ≤ 0.01 (measured
        // 0.024 / 0.033 with 4 × 4 even steps, before High became 3 × 5 crowded).
        let (max_rmse, max_bias) = match estimator {
            Estimator::Hbao => (0.03, 0.005),
            _ => (0.045, 0.01),
        };
        for mode in [AoMode::Deinterleaved2, AoMode::Deinterleaved4] {
            let ao = run(mode);
            let n = ao.len() as f32;
            let bias = ao.iter().zip(&base).map(|(a, b)| a - b).sum::<f32>() / n;
            let rmse = (ao
                .iter()
                .zip(&base)
                .map(|(a, b)| (a - b).powi(2))
                .sum::<f32>()
                / n)
                .sqrt();
            eprintln!("{estimator:?} {mode:?}: RMSE {rmse:.4}, bias {bias:.4} against randomized");
            assert!(
                rmse <= max_rmse && bias.abs() <= max_bias,
                "{estimator:?} {mode:?}: RMSE {rmse}, bias {bias}"
            );
        }
    }
}

fn rmse(a: &[f32], b: &[f32]) -> f32 {
    (a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f32>() / a.len() as f32).sqrt()
}

#[test]
fn every_estimator_converges_to_its_screen_space_reference() {
    // The screen-space reference is the estimator's own integral (64 × 64 samples, no
    // jitter); more samples per pixel must bring each estimator closer to it.
    let _g = lock();
    let mesh = default_scene::mesh();
    let cam = default_scene::camera();
    let (w, h) = (192, 108);
    for estimator in Estimator::ALL {
        let reference = render_with(
            &mesh,
            &cam,
            w,
            h,
            1.0,
            AoOptions::screen_reference(estimator),
        )
        .1;
        assert!(
            reference.iter().any(|&a| a < 0.7),
            "{estimator:?}: the reference has occlusion"
        );
        // Raw samples, as the reference: no denoiser between them.
        let errors: Vec<f32> = Preset::ALL
            .into_iter()
            .map(|preset| AoOptions {
                mode: AoMode::Randomized,
                denoise: Denoise::None,
                ..AoOptions::preset(estimator, preset)
            })
            .chain([AoOptions {
                directions: 32,
                steps: 32,
                mode: AoMode::Randomized,
                denoise: Denoise::None,
                ..AoOptions::preset(estimator, Preset::Ultra)
            }])
            .map(|o| rmse(&render_with(&mesh, &cam, w, h, 1.0, o).1, &reference))
            .collect();
        eprintln!("{estimator:?}: RMSE vs screen-space reference, low..ultra, 32×32: {errors:?}");
        // Stated tolerance: each step up may not raise the error by more than 5% (noise
        // between neighbouring presets), and 32 × 32 jittered samples end within a quarter
        // of the low preset's error and 0.01 AO units of the reference (measured: every
        // step lowers it; 32 × 32 is at 3–7% of low, 0.0014–0.0049).
        for pair in errors.windows(2) {
            assert!(pair[1] <= pair[0] * 1.05, "{estimator:?}: {errors:?}");
        }
        let last = *errors.last().unwrap();
        assert!(
            last <= 0.25 * errors[0] && last <= 0.01,
            "{estimator:?}: {errors:?}"
        );
    }
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

/// The raw depth of every sample of a multisampled depth texture, `[pixel * n + sample]`
/// (multisampled textures cannot be copied out, so a compute pass reads them).
fn read_samples(c: &GpuContext, m: &MsaaDepth) -> Vec<f32> {
    const SRC: &str = r#"
@group(0) @binding(0) var depth_in: texture_depth_multisampled_2d;
@group(0) @binding(1) var<storage, read_write> out: array<f32>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) g: vec3<u32>) {
    let size = textureDimensions(depth_in);
    if any(g.xy >= size) {
        return;
    }
    let n = textureNumSamples(depth_in);
    for (var s = 0u; s < n; s++) {
        out[(g.y * size.x + g.x) * n + s] = textureLoad(depth_in, vec2<i32>(g.xy), i32(s));
    }
}
"#;
    let d = &c.device;
    let bytes = (m.width * m.height * MSAA_SAMPLES * 4) as u64;
    let buffer = |usage| {
        d.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: bytes,
            usage,
            mapped_at_creation: false,
        })
    };
    let out = buffer(wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC);
    let readback = buffer(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST);
    let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: None,
        source: wgpu::ShaderSource::Wgsl(SRC.into()),
    });
    let pipeline = d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: None,
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&m.depth_view),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: out.as_entire_binding(),
            },
        ],
    });
    c.run(|enc| {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(m.width.div_ceil(8), m.height.div_ceil(8), 1);
        drop(pass);
        enc.copy_buffer_to_buffer(&out, 0, &readback, 0, bytes);
        Ok(())
    })
    .unwrap();
    bytemuck::pod_collect_to_vec(&c.map_read(&readback).unwrap())
}

/// Renders the default scene's depth with 4× MSAA at `w` × `h` and runs AO on it with
/// `options`; returns (samples, resolved raw depth, AO, frame uniforms).
fn msaa_ao(
    w: u32,
    h: u32,
    options: AoOptions,
) -> (
    Vec<f32>,
    Vec<f32>,
    Vec<f32>,
    obscura::uniforms::FrameUniforms,
) {
    let c = ctx();
    let cam = default_scene::camera();
    let raster = GBufferRenderer::new(&c.device);
    let gm = raster.upload(c, &default_scene::mesh()).unwrap();
    let ms = raster.render_msaa_depth(c, &gm, &cam, w, h).unwrap();
    let samples = read_samples(c, &ms);
    let mut ao = Ao::new(&c.device, options).unwrap();
    let input = ms.ao_input(&cam);
    let params = AoParams {
        radius: 1.0,
        ..Default::default()
    };
    c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &params))
        .unwrap();
    let f = ao.validate(&input, &params).unwrap();
    (
        samples,
        c.read_f32(ao.resolved_depth().unwrap()).unwrap(),
        c.read_f32(ao.output().unwrap()).unwrap(),
        f,
    )
}

/// MSAA depth with a guard band: the AO of the guarded view is the crop of the AO of the
/// whole widened multisampled frame (the same texture without a band, under the widened
/// projection), within 1e-4, in the default layout and the randomized one with temporal
/// accumulation; and the band changes the AO at the view's edges.
#[test]
fn msaa_depth_takes_a_guard_band() {
    let _g = lock();
    let c = ctx();
    let cam = default_scene::camera();
    let raster = GBufferRenderer::new(&c.device);
    let gm = raster.upload(c, &default_scene::mesh()).unwrap();
    let (w, h, g) = (96u32, 60u32, 16u32);
    let ms = raster
        .render_msaa_depth_guarded(c, &gm, &cam, (w, h), g)
        .unwrap();
    assert_eq!(
        (ms.width, ms.height, ms.guard_band),
        (w + 2 * g, h + 2 * g, g)
    );
    let guarded = ms.ao_input(&cam);
    let whole = obscura::AoInput {
        viewport: None,
        guard_band: 0,
        projection: cam
            .widened(h, g)
            .obscura_projection((w + 2 * g) as f32 / (h + 2 * g) as f32),
        ..guarded
    };
    let bare = obscura::AoInput {
        guard_band: 0,
        ..guarded
    };
    let params = AoParams {
        radius: 1.0,
        ..Default::default()
    };
    let randomized = AoOptions {
        mode: obscura::AoMode::Randomized,
        history: 4,
        ..Default::default()
    };
    for options in [AoOptions::default(), randomized] {
        let run = |input: &obscura::AoInput<'_>| {
            let mut ao = Ao::new(&c.device, options).unwrap();
            c.run(|enc| ao.record(&c.device, &c.queue, enc, input, &params))
                .unwrap();
            c.read_f32(ao.output().unwrap()).unwrap()
        };
        let wide = run(&whole);
        let bw = (w + 2 * g) as usize;
        let want: Vec<f32> = (0..h as usize)
            .flat_map(|y| {
                let row = (y + g as usize) * bw + g as usize;
                wide[row..row + w as usize].to_vec()
            })
            .collect();
        let got = run(&guarded);
        let d = got
            .iter()
            .zip(&want)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f32::max);
        assert!(
            d <= 1e-4,
            "{options:?}: guarded MSAA AO off the crop by {d}"
        );
        let d = run(&bare)
            .iter()
            .zip(&want)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f32::max);
        assert!(d > 0.02, "{options:?}: the band changed the AO by only {d}");
    }
}

/// The MSAA resolve equals its CPU mirror (`reference::resolve_msaa_depth`) on a 4× MSAA
/// G-buffer of the default scene, except where a linear-depth comparison sits on its
/// boundary (at most 0.1% of pixels), and the scene exercises both of its rules.
#[test]
fn msaa_depth_resolves_like_its_cpu_mirror() {
    let _g = lock();
    let (w, h) = (320, 180);
    let (samples, resolved, _, f) = msaa_ao(w, h, AoOptions::default());
    let n = MSAA_SAMPLES as usize;
    let (mut off, mut nearest, mut mean) = (0, 0, 0);
    for (i, &r) in resolved.iter().enumerate() {
        let s = &samples[i * n..(i + 1) * n];
        let want = obscura::reference::resolve_msaa_depth(&f, s);
        if (r - want).abs() > 1e-6 {
            off += 1;
        }
        let avg = s.iter().sum::<f32>() / n as f32;
        if s.iter().any(|&x| x != s[0]) {
            if want == avg {
                mean += 1;
            } else {
                nearest += 1;
            }
        }
    }
    eprintln!(
        "resolve: {off} pixels off the mirror, {nearest} silhouette, {mean} sloped, of {}",
        resolved.len()
    );
    assert!(
        off * 1000 <= resolved.len(),
        "{off} of {} pixels differ from the mirror",
        resolved.len()
    );
    assert!(
        nearest > 50 && mean > 1000,
        "silhouette pixels {nearest}, sloped surface pixels {mean}"
    );
}

/// AO from 4× MSAA depth matches AO from single-sampled depth of the same view away from
/// silhouettes: interior pixels resolve to the pixel-centre depth, so only pixels whose
/// horizon reaches a silhouette can differ. Tolerance: outside 2 px of a silhouette, mean
/// |difference| ≤ 0.005 and at most 1% of pixels beyond 0.05 (the AO's own error against
/// ray-traced truth is about 0.06 RMSE, docs/quality.md).
#[test]
fn msaa_ao_matches_single_sample_ao_away_from_edges() {
    let _g = lock();
    let (w, h) = (320, 180);
    let (samples, _, ms_ao, f) = msaa_ao(w, h, AoOptions::default());
    let cam = default_scene::camera();
    let c = ctx();
    let raster = GBufferRenderer::new(&c.device);
    let gm = raster.upload(c, &default_scene::mesh()).unwrap();
    let g = raster.render(c, &gm, &cam, w, h).unwrap();
    let mut ao = Ao::new(&c.device, AoOptions::default()).unwrap();
    let input = g.ao_input(&cam, false);
    let params = AoParams {
        radius: 1.0,
        ..Default::default()
    };
    c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &params))
        .unwrap();
    let single = c.read_f32(ao.output().unwrap()).unwrap();
    // Silhouettes: a pixel whose samples are not all one surface, dilated by 2 px.
    let lin = f.linearize();
    let n = MSAA_SAMPLES as usize;
    let edge: Vec<bool> = (0..(w * h) as usize)
        .map(|i| {
            let d: Vec<Option<f32>> = samples[i * n..(i + 1) * n]
                .iter()
                .map(|&r| lin.apply(r))
                .collect();
            let near = d.iter().flatten().fold(f32::MAX, |a, &b| a.min(b));
            let far = d.iter().flatten().fold(0.0f32, |a, &b| a.max(b));
            d.iter().any(|x| x.is_some())
                && (d.iter().any(|x| x.is_none()) || far - near > 0.02 * near)
        })
        .collect();
    let (mut count, mut sum, mut big) = (0usize, 0.0f64, 0usize);
    for y in 0..h as i32 {
        for x in 0..w as i32 {
            let near_edge = (-2..=2).any(|dy| {
                (-2..=2).any(|dx| {
                    let (u, v) = (x + dx, y + dy);
                    u >= 0
                        && v >= 0
                        && u < w as i32
                        && v < h as i32
                        && edge[(v * w as i32 + u) as usize]
                })
            });
            if near_edge {
                continue;
            }
            let i = (y * w as i32 + x) as usize;
            let diff = (ms_ao[i] - single[i]).abs();
            count += 1;
            sum += diff as f64;
            big += (diff > 0.05) as usize;
        }
    }
    let mean = sum / count as f64;
    assert!(
        count > (w * h / 2) as usize,
        "only {count} pixels away from edges"
    );
    assert!(
        mean <= 0.005,
        "mean |MSAA − single| = {mean:.4} over {count} pixels"
    );
    assert!(
        big * 100 <= count,
        "{big} of {count} pixels differ by more than 0.05"
    );
    eprintln!(
        "MSAA vs single-sample away from edges: mean {mean:.5}, {big} of {count} beyond 0.05"
    );
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
