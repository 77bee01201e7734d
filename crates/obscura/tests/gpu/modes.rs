//! Every layout against the CPU reference, and the resources the estimators read: depth
//! moments, the depth pyramid, the split layers, the viewport.

use super::*;

/// GPU AO in every mode against the CPU reference (per full-resolution pixel: the layer's
/// pattern, offsets snapped to the N-pixel lattice), run on the GPU's own prepared buffer.
fn check_modes_against_reference(projection: Projection, raw: &[f32], what: &str) {
    let params = AoParams {
        radius: 1.5,
        ..Default::default()
    };
    let base = AoOptions {
        directions: 6,
        steps: 5,
        ..randomized()
    };
    let prepared = run_linear(raw, W, H, projection, base, &params);
    let mut by_mode = Vec::new();
    for v in all_variants() {
        let options = AoOptions {
            directions: 6,
            steps: 5,
            ..v
        };
        let r = run_linear(raw, W, H, projection, options, &params);
        let cpu = reference::ao(&r.frame, &options, &prepared.prepared);
        assert_matches_mirror(&r.ao, &cpu, &format!("{what} {options:?}"));
        if projection.is_perspective() {
            assert!(
                r.ao.iter().any(|&a| a < 0.8),
                "{what}: the scene has occlusion"
            );
        }
        by_mode.push((options, r.ao));
    }
    // Fused and unfused split/merge do the same work: bit-identical results.
    for pair in by_mode.windows(2) {
        if pair[0].0.mode == pair[1].0.mode && pair[0].0.estimator == pair[1].0.estimator {
            assert_eq!(pair[0].1, pair[1].1, "{what}: fused and unfused differ");
        }
    }
}

#[test]
fn every_mode_matches_cpu_reference_on_odd_sizes() {
    let _g = lock();
    let p = persp(W, H);
    check_modes_against_reference(p, &test_scene(&p, W, H), "perspective");
    let o = Projection::Orthographic {
        half_width: 4.0 * W as f32 / H as f32,
        half_height: 4.0,
        near: 0.1,
        far: 20.0,
    };
    check_modes_against_reference(o, &test_scene(&o, W, H), "orthographic");
}

/// The depth moments pyramid matches the CPU's in every mode, on odd sizes (orphan rows and
/// columns); and VO's area integral really reads it: the GPU's matches the CPU's area
/// integral, and differs on many pixels from the line integral, which is what it would be
/// if it never left level 0. Tolerance: fraction within 1e-6, mean within 1e-5 of it,
/// variance within 1e-3 of itself plus 1e-9 of the mean² (float rounding: the GPU may fuse
/// multiply-adds; E[z²] − E[z]² in f32 would miss by ~1e-7 of the mean²).
#[test]
fn depth_moments_match_cpu_and_vo_area_reads_them() {
    let _g = lock();
    let params = AoParams {
        radius: 3.0,
        ..Default::default()
    };
    for (w, h) in [(W, H), (97, 61), (2, 7)] {
        let p = persp(w, h);
        let raw = test_scene(&p, w, h);
        let area = AoOptions {
            estimator: Estimator::VoArea,
            ..randomized()
        };
        let full = run_linear(&raw, w, h, p, area, &params);
        let cpu = reference::moments([w, h], &full.prepared);
        for options in all_variants()
            .into_iter()
            .filter(|o| o.estimator == Estimator::VoArea)
        {
            let r = run_linear(&raw, w, h, p, options, &params);
            assert_eq!(r.moments.len(), cpu.len(), "{w}x{h} {options:?}: levels");
            for (level, (g, c)) in r.moments.iter().zip(&cpu).enumerate() {
                assert_eq!(g.len(), c.texels.len(), "{w}x{h}: level {} size", level + 1);
                for (i, (g, c)) in g.iter().zip(&c.texels).enumerate() {
                    let ok = (g[0] - c[0]).abs() <= 1e-6
                        && (g[1] - c[1]).abs() <= 1e-5 * c[1].max(1.0)
                        && (g[2] - c[2]).abs() <= 1e-3 * c[2] + 1e-9 * c[1] * c[1];
                    assert!(
                        ok,
                        "{w}x{h} {options:?}: level {} texel {i}: {g:?} vs {c:?}",
                        level + 1
                    );
                }
            }
        }
    }
    let p = persp(W, H);
    let raw = test_scene(&p, W, H);
    let options = AoOptions {
        estimator: Estimator::VoArea,
        ..randomized()
    };
    let r = run_linear(&raw, W, H, p, options, &params);
    let area = reference::ao(&r.frame, &options, &r.prepared);
    let line = reference::ao(
        &r.frame,
        &AoOptions {
            estimator: Estimator::Vo,
            ..options
        },
        &r.prepared,
    );
    assert_matches_mirror(&r.ao, &area, "VO area integral");
    let differing =
        r.ao.iter()
            .zip(&line)
            .filter(|(g, c)| (*g - *c).abs() > 2e-3)
            .count();
    assert!(
        differing * 10 >= r.ao.len(),
        "VO's area integral does not read the moments: {differing} of {} pixels differ from the line integral",
        r.ao.len()
    );
}

/// The depth pyramid equals the CPU's bit for bit in every mode, built one level per pass
/// or four (it only selects values),
/// on odd sizes; and SAO really reads it: the CPU SAO that ignores the pyramid differs from
/// the GPU's on many pixels while the one that reads it matches (every_mode_matches_...).
#[test]
fn depth_pyramid_matches_cpu_and_sao_reads_it() {
    let _g = lock();
    let params = AoParams {
        radius: 3.0,
        ..Default::default()
    };
    // 134×70 and 301×177: odd levels whose orphan row and column fall in the next
    // workgroup's tile, and more than one pass of four levels.
    for (w, h) in [(W, H), (97, 61), (1, 1), (2, 7), (134, 70), (301, 177)] {
        let p = persp(w, h);
        let raw = test_scene(&p, w, h);
        let sao = AoOptions {
            estimator: Estimator::Sao,
            ..randomized()
        };
        let full = run_linear(&raw, w, h, p, sao, &params);
        let cpu = reference::pyramid([w, h], &full.prepared);
        let base = [1.max(w >> 1), 1.max(h >> 1)];
        assert_eq!(cpu.len() as u32, base[0].max(base[1]).ilog2() + 1);
        let builds = [
            PyramidBuild::OneLevelPerPass,
            PyramidBuild::FourLevelsPerPass,
        ];
        for options in all_variants()
            .into_iter()
            .filter(|o| o.estimator == Estimator::Sao)
            .flat_map(|o| builds.map(|pyramid| AoOptions { pyramid, ..o }))
        {
            let r = run_linear(&raw, w, h, p, options, &params);
            assert_eq!(r.pyramid.len(), cpu.len(), "{w}x{h} {options:?}: levels");
            for (level, (g, c)) in r.pyramid.iter().zip(&cpu).enumerate() {
                assert_eq!(g, &c.texels, "{w}x{h} {options:?}: level {}", level + 1);
            }
        }
        // Min <= select <= max wherever the footprint has geometry, and the coarsest
        // level's min/max bound every depth in the image.
        let depths: Vec<f32> = full
            .prepared
            .iter()
            .map(|v| v.x)
            .filter(|&d| d > 0.0)
            .collect();
        let top = cpu.last().unwrap();
        if top.size == [1, 1] && !depths.is_empty() {
            let t = top.texels[0];
            assert_eq!(t[1], depths.iter().cloned().fold(f32::MAX, f32::min));
            assert_eq!(t[2], depths.iter().cloned().fold(0.0, f32::max));
        }
        for l in &cpu {
            for t in &l.texels {
                assert!(t[0] <= 0.0 || (t[1] <= t[0] && t[0] <= t[2]), "{t:?}");
            }
        }
    }
    // SAO with a radius spanning 16+ pixels: GPU ≈ CPU with the pyramid, far from without.
    let p = persp(W, H);
    let raw = test_scene(&p, W, H);
    let options = AoOptions {
        estimator: Estimator::Sao,
        ..randomized()
    };
    let r = run_linear(&raw, W, H, p, options, &params);
    let with = reference::ao(&r.frame, &options, &r.prepared);
    let without: Vec<f32> = {
        let px = reference::Pixels {
            f: &r.frame,
            directions: options.directions,
            steps: options.steps,
            march_exponent: options.march_exponent,
            prepared: &r.prepared,
            lattice: 1,
            pyramid: &[],
            moments: &[],
            second: &[],
        };
        (0..H as i32)
            .flat_map(|y| (0..W as i32).map(move |x| [x, y]))
            .map(|q| {
                let pattern = r.frame.patterns[obscura::jitter::pattern_index(
                    q[0] as u32,
                    q[1] as u32,
                    obscura::jitter::PATTERN_DIM,
                )];
                reference::sao_pixel(&px, q, pattern)
            })
            .collect()
    };
    let differing = |cpu: &[f32]| {
        r.ao.iter()
            .zip(cpu)
            .filter(|(g, c)| (*g - *c).abs() > 2e-3)
            .count()
    };
    let n = r.ao.len();
    assert!(
        differing(&with) * 200 <= n,
        "GPU SAO ≠ CPU SAO with pyramid"
    );
    // Ignoring the pyramid changes 7.9% of pixels here (radius 3 spans 16–23 px: level 1
    // for the outer samples); a GPU that never read it would match `without` exactly.
    assert!(
        differing(&without) * 25 >= n,
        "SAO does not read the pyramid: only {} of {n} pixels change without it",
        differing(&without)
    );
}

#[test]
fn split_layers_hold_exactly_the_prepared_pixels() {
    let _g = lock();
    let c = ctx();
    let p = persp(W, H);
    let raw = test_scene(&p, W, H);
    let tex = upload_r32(&raw, W, H);
    let view = tex.create_view(&Default::default());
    let input = linear_input(&view, p);
    let params = AoParams::default();
    for mode in [AoMode::Deinterleaved2, AoMode::Deinterleaved4] {
        let n = mode.split();
        let (lw, lh) = layout::layer_size(W, H, n);
        let mut layers_by_fusion = Vec::new();
        for fused in [false, true] {
            let mut ao = Ao::new(
                &c.device,
                AoOptions {
                    mode,
                    fused,
                    ..Default::default()
                },
            )
            .unwrap();
            c.run(|enc| ao.record(&c.device, &c.queue, enc, &input, &params))
                .unwrap();
            let layers = c
                .read_f32(ao.prepared_layers_view().unwrap().texture())
                .unwrap();
            assert_eq!(layers.len(), (lw * lh * n * n * 4) as usize);
            if !fused {
                // The split pass copies each full-resolution texel to (x/N, y/N) of layer
                // x%N + N·(y%N): compare bit for bit.
                let full = c.read_f32(ao.prepared_view().unwrap().texture()).unwrap();
                for y in 0..H {
                    for x in 0..W {
                        let l = layout::layer_of(x, y, n);
                        let (tx, ty) = layout::layer_texel(x, y, n);
                        let li = (((l * lh + ty) * lw + tx) * 4) as usize;
                        let fi = ((y * W + x) * 4) as usize;
                        let a: &[u32] = bytemuck::cast_slice(&layers[li..li + 4]);
                        let b: &[u32] = bytemuck::cast_slice(&full[fi..fi + 4]);
                        assert_eq!(a, b, "{mode:?} pixel ({x}, {y})");
                    }
                }
            }
            layers_by_fusion.push(layers);
        }
        // The prepare pass writing layers directly (fused split) gives the same layers,
        // compared on the texels that have a source pixel (the rest is padding).
        for l in 0..n * n {
            for ty in 0..lh {
                for tx in 0..lw {
                    if layout::full_pixel(l, (tx, ty), n, W, H).is_some() {
                        let i = (((l * lh + ty) * lw + tx) * 4) as usize;
                        assert_eq!(
                            layers_by_fusion[0][i..i + 4],
                            layers_by_fusion[1][i..i + 4],
                            "{mode:?} layer {l} texel ({tx}, {ty})"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn viewport_selects_a_region_without_shifting_it() {
    let _g = lock();
    let (bw, bh) = (W + 9, H + 6);
    let vp = Viewport {
        x: 5,
        y: 4,
        width: W,
        height: H,
    };
    let p = persp(W, H);
    let inner = test_scene(&p, W, H);
    let mut big = vec![3.0f32; (bw * bh) as usize];
    for y in 0..H {
        for x in 0..W {
            big[((y + vp.y) * bw + x + vp.x) as usize] = inner[(y * W + x) as usize];
        }
    }
    let params = AoParams {
        radius: 1.5,
        ..Default::default()
    };
    let a = run_linear(&inner, W, H, p, AoOptions::default(), &params);
    let b = run_ao(
        &big,
        bw,
        bh,
        p,
        DepthConvention::LinearView,
        Some(vp),
        AoOptions::default(),
        &params,
    );
    assert_eq!(a.ao, b.ao);
}
