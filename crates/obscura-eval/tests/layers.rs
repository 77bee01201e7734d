//! Renderer layers from the ray tracer (obscura-eval's `layers`) on scenes whose layers are
//! known by construction, and the screen-space limits' ordering: more of the hidden
//! geometry can only darken, a thinner solid only brighten.

use glam::Vec3;
use obscura_eval::layers::{deep_layers, layer_limit, Representation};
use obscura_eval::{bvh::Tri, Bvh};
use obscura_scene::{Camera, CameraProjection};

/// An axis-aligned box's 12 triangles, wound outward.
fn cube(min: Vec3, max: Vec3) -> Vec<Tri> {
    let c = |i: usize| {
        Vec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        )
    };
    // Each face as four corners counter-clockwise seen from outside.
    let faces = [
        [0, 4, 6, 2], // -x
        [1, 3, 7, 5], // +x
        [0, 1, 5, 4], // -y
        [2, 6, 7, 3], // +y
        [0, 2, 3, 1], // -z
        [4, 5, 7, 6], // +z
    ];
    faces
        .iter()
        .flat_map(|f| [[c(f[0]), c(f[1]), c(f[2])], [c(f[0]), c(f[2]), c(f[3])]])
        .collect()
}

fn camera() -> Camera {
    Camera {
        eye: Vec3::ZERO,
        target: Vec3::new(0.0, 0.0, -1.0),
        up: Vec3::Y,
        projection: CameraProjection::Perspective { fov_y_deg: 40.0 },
        near: 0.1,
        far: 100.0,
    }
}

/// Two boxes one behind the other on the view axis: the centre pixel sees the first's
/// front (5) and back (6), the second's front (8) and back (9); a single-sided quad has no
/// back, and its second layer is the first front face beyond the prior. A pixel past the
/// boxes' sides sees nothing.
#[test]
fn layers_of_known_solids() {
    let mut tris = cube(Vec3::new(-1.0, -1.0, -6.0), Vec3::new(1.0, 1.0, -5.0));
    tris.extend(cube(Vec3::new(-3.0, -3.0, -9.0), Vec3::new(3.0, 3.0, -8.0)));
    let bvh = Bvh::new(tris);
    let (w, h) = (33, 21);
    let l = deep_layers(&bvh, &camera(), (w, h), 0, 0.5);
    let centre = l.depth[(h / 2 * w + w / 2) as usize];
    for (got, want) in centre.iter().zip([5.0, 6.0, 8.0, 9.0, 8.0, 9.0]) {
        assert!((got - want).abs() < 1e-3, "{centre:?}");
    }
    let n = l.normal[(h / 2 * w + w / 2) as usize];
    assert!((n - Vec3::Z).length() < 1e-4, "faces the camera: {n}");
    assert_eq!(l.depth[0], [0.0; 6], "the corner sees past both boxes");

    // One-sided quads at 5 and 5.3 (facing the camera), a box at 8..9.
    let quad = |z: f32| -> [Tri; 2] {
        let (a, b, c, d) = (
            Vec3::new(-1.0, -1.0, z),
            Vec3::new(1.0, -1.0, z),
            Vec3::new(1.0, 1.0, z),
            Vec3::new(-1.0, 1.0, z),
        );
        [[a, b, c], [a, c, d]]
    };
    let mut tris = quad(-5.0).to_vec();
    tris.extend(quad(-5.3));
    tris.extend(cube(Vec3::new(-3.0, -3.0, -9.0), Vec3::new(3.0, 3.0, -8.0)));
    let bvh = Bvh::new(tris);
    let l = deep_layers(&bvh, &camera(), (w, h), 0, 0.5);
    let close =
        |got: [f32; 6], want: [f32; 6]| got.iter().zip(want).all(|(g, w)| (g - w).abs() < 1e-3);
    // The quad's "back face" is the box's (9), bounded by the prior: the quad at 5.3 lies
    // inside the 0.5 prior, so layer 2 (either peel) is the box.
    let centre = l.depth[(h / 2 * w + w / 2) as usize];
    assert!(close(centre, [5.0, 9.0, 8.0, 9.0, 8.0, 9.0]), "{centre:?}");
    // A thinner prior peels the second quad.
    let l = deep_layers(&bvh, &camera(), (w, h), 0, 0.2);
    let centre = l.depth[(h / 2 * w + w / 2) as usize];
    assert!(close(centre, [5.0, 9.0, 5.3, 9.0, 5.3, 9.0]), "{centre:?}");
    // A box 5..5.1, thin against the prior: layer 2 starts at its back face (the quad at
    // 5.3), layer 2' at the prior (past the quad: the far box).
    let mut tris = cube(Vec3::new(-1.0, -1.0, -5.1), Vec3::new(1.0, 1.0, -5.0));
    tris.extend(quad(-5.3));
    tris.extend(cube(Vec3::new(-3.0, -3.0, -9.0), Vec3::new(3.0, 3.0, -8.0)));
    let l = deep_layers(&Bvh::new(tris), &camera(), (w, h), 0, 0.5);
    let centre = l.depth[(h / 2 * w + w / 2) as usize];
    assert!(close(centre, [5.0, 5.1, 5.3, 9.0, 8.0, 9.0]), "{centre:?}");
}

/// The solids each representation gives a pixel's layers.
#[test]
fn representations_bound_back_faces_by_the_prior() {
    let l = [5.0, 6.0, 8.0, 8.2, 7.0, 7.5];
    let p = 0.5;
    assert_eq!(
        Representation::Infinite.solids(l, p),
        [Some((5.0, f32::INFINITY)), None]
    );
    assert_eq!(Representation::Prior.solids(l, p), [Some((5.0, 5.5)), None]);
    assert_eq!(
        Representation::BackFaces.solids(l, p),
        [Some((5.0, 5.5)), None]
    );
    assert_eq!(
        Representation::TwoLayersPrior.solids(l, p),
        [Some((5.0, 5.5)), Some((7.0, 7.5))]
    );
    assert_eq!(
        Representation::TwoLayers.solids(l, p),
        [Some((5.0, 5.5)), Some((8.0, 8.2))]
    );
    // No back face: the prior; no surface: nothing.
    assert_eq!(
        Representation::BackFaces.solids([5.0, 0.0, 0.0, 0.0, 0.0, 0.0], p),
        [Some((5.0, 5.5)), None]
    );
    assert_eq!(Representation::TwoLayers.solids([0.0; 6], p), [None, None]);
}

/// Per pixel, on boxes on a floor seen obliquely: a thinner prior's solids lie within a
/// thicker one's, back faces no deeper than the prior (so each is at least as bright), and
/// a second layer only adds solids (at least as dark), with the prior or with back faces.
/// The prior and infinite thickness are not ordered: a finite solid whose front lies
/// beyond the radius occludes with its part within it, which GTAO's rule ignores, and
/// the boxes standing in front of the floor give such pixels.
/// With the guard band the view's own pixels read more solids; jittered, too.
#[test]
fn limits_are_ordered_by_what_each_representation_sees() {
    let mut tris = cube(Vec3::new(-20.0, -1.0, -40.0), Vec3::new(20.0, 0.0, 0.0));
    tris.extend(cube(Vec3::new(-1.0, 0.0, -9.0), Vec3::new(0.0, 0.3, -8.0)));
    tris.extend(cube(Vec3::new(0.5, 0.0, -7.0), Vec3::new(0.7, 1.5, -6.8)));
    tris.extend(cube(Vec3::new(0.2, 0.0, -10.0), Vec3::new(1.2, 2.0, -9.5)));
    let bvh = Bvh::new(tris);
    let cam = Camera {
        eye: Vec3::new(0.0, 1.5, 0.0),
        target: Vec3::new(0.0, 0.0, -8.0),
        ..camera()
    };
    let (radius, thickness) = (1.0, 0.5);
    let l = deep_layers(&bvh, &cam, (48, 32), 6, thickness * radius);
    let run = |rep, guarded| {
        layer_limit(&l, &cam, (radius, thickness), (8, 8, false), rep, guarded).unwrap()
    };
    let inf = run(Representation::Infinite, false);
    let prior = run(Representation::Prior, false);
    let thicker = layer_limit(
        &l,
        &cam,
        (radius, 2.0 * thickness),
        (8, 8, false),
        Representation::Prior,
        false,
    )
    .unwrap();
    let back = run(Representation::BackFaces, false);
    let two_prior = run(Representation::TwoLayersPrior, false);
    let two = run(Representation::TwoLayers, false);
    for i in 0..inf.len() {
        assert!(
            two_prior[i] <= prior[i] + 1e-6,
            "pixel {i}: second layer brightens"
        );
        assert!(
            prior[i] >= thicker[i] - 1e-6,
            "pixel {i}: {} < {}",
            prior[i],
            thicker[i]
        );
        assert!(
            back[i] >= prior[i] - 1e-6,
            "pixel {i}: {} < {}",
            back[i],
            prior[i]
        );
        assert!(
            two[i] <= back[i] + 1e-6,
            "pixel {i}: {} > {}",
            two[i],
            back[i]
        );
    }
    let strict = |a: &[f32], b: &[f32]| a.iter().zip(b).any(|(x, y)| x != y);
    assert!(
        strict(&thicker, &prior) && strict(&two, &back),
        "the scene tells them apart"
    );
    assert!(
        prior.iter().zip(&inf).any(|(p, i)| p < &(i - 0.01)),
        "a box in front reaches into the radius of a pixel behind it"
    );
    let banded = run(Representation::Infinite, true);
    assert!(strict(&inf, &banded), "the band changes the edges");
    // Jittered per pixel (the randomized layout's patterns), each pixel keeps the ordering.
    let jit = |rep| layer_limit(&l, &cam, (radius, thickness), (4, 4, true), rep, false).unwrap();
    let (one, two) = (
        jit(Representation::Prior),
        jit(Representation::TwoLayersPrior),
    );
    assert!(one.iter().zip(&two).all(|(a, b)| *b <= a + 1e-6));
    assert!(strict(&one, &jit(Representation::Infinite)) || strict(&one, &two));
    let fixed = layer_limit(
        &l,
        &cam,
        (radius, thickness),
        (4, 4, false),
        Representation::Prior,
        false,
    )
    .unwrap();
    assert!(strict(&one, &fixed), "the patterns vary by pixel");
}
