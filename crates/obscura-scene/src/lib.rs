//! Scenes for obscura's CLI, tests and evaluation: mesh loading (glTF 2.0, OBJ), a
//! camera, a built-in default scene, and G-buffer rasterization (reversed-Z Depth32Float
//! depth plus view-space normals). Not needed by engines that bring their own depth buffer.

#[cfg(feature = "gpu")]
pub mod camera;
pub mod default_scene;
#[cfg(feature = "gpu")]
pub mod gbuffer;
mod load;
pub mod mesh;

#[cfg(feature = "gpu")]
pub use camera::{Camera, CameraProjection, DEPTH_CONVENTION, SKY_DEPTH};
#[cfg(feature = "gpu")]
pub use gbuffer::{DepthLayer, GBuffer, GBufferRenderer, GpuMesh, MsaaDepth, ALBEDO_FORMAT};
pub use mesh::{Aabb, Mesh, DEFAULT_ALBEDO};

/// Errors from loading scenes and cameras.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    #[error("cannot read `{path}`: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("unsupported scene file extension `{0}` (expected .glb, .gltf or .obj)")]
    UnsupportedExtension(String),
    #[error("invalid glTF file `{path}`: {reason}")]
    Gltf { path: String, reason: String },
    #[error("invalid OBJ file `{path}`: {reason}")]
    Obj { path: String, reason: String },
    #[error("`{0}` contains no triangles")]
    Empty(String),
    #[error("invalid camera: {0}")]
    Camera(String),
    #[cfg(feature = "gpu")]
    #[error(transparent)]
    Gpu(#[from] obscura::Error),
}
