//! The standard views: one per shared scene, used by `obscura eval --all` and
//! docs/quality.md. Cameras chosen by hand where a scene has an inside to look into (Sponza interior,
//! Cornell box); otherwise the scene is framed from its bounding box
//! (`Camera::framing`, 50° vertical field of view). The AO radius is 3% of the scene's
//! bounding-box diagonal, the CLI's default rule, for every view.

/// A named view of a scene under `shared/scenes`.
#[derive(Clone, Copy, Debug)]
pub struct StandardView {
    pub name: &'static str,
    /// Path relative to the `shared/scenes` folder.
    pub file: &'static str,
    /// `(eye, target, vertical fov in degrees)`, or `None` to frame the bounds.
    pub camera: Option<([f32; 3], [f32; 3], f32)>,
}

/// Every standard view.
pub const STANDARD_VIEWS: [StandardView; 9] = [
    StandardView {
        name: "sponza",
        file: "sponza_dabrovic/sponza_dabrovic.glb",
        camera: Some(([-14.0, 2.0, 0.0], [10.0, 5.0, 0.0], 60.0)),
    },
    StandardView {
        name: "cornell",
        file: "cornell_box/cornell_box.obj",
        camera: Some(([278.0, 273.0, -800.0], [278.0, 273.0, 0.0], 39.0)),
    },
    StandardView {
        name: "house5",
        file: "voxel_houses_mmmm/scene_house5.glb",
        camera: None,
    },
    StandardView {
        name: "house6",
        file: "voxel_houses_mmmm/scene_house6.glb",
        camera: None,
    },
    StandardView {
        name: "etoile",
        file: "city_etoile/etoile.glb",
        camera: None,
    },
    StandardView {
        name: "munich",
        file: "city_munich/munich.glb",
        camera: None,
    },
    StandardView {
        name: "bunny",
        file: "objects/stanford-bunny.obj",
        camera: None,
    },
    StandardView {
        name: "teapot",
        file: "objects/teapot.obj",
        camera: None,
    },
    StandardView {
        name: "dragon",
        file: "objects/dragon_lowpoly_hackmans.glb",
        camera: None,
    },
];

/// Looks a view up by name.
pub fn find(name: &str) -> Option<&'static StandardView> {
    STANDARD_VIEWS.iter().find(|v| v.name == name)
}
