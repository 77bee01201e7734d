//! Ground truth and metrics for judging obscura: a CPU ray tracer of ambient occlusion
//! over the scene's triangles (the reference every estimator is compared with) and image
//! error metrics. Used by `obscura eval` and the quality documents.

pub mod bvh;
pub mod cache;
pub mod flip;
pub mod layers;
pub mod metrics;
pub mod sensor;
pub mod trace;
pub mod views;

pub use bvh::Bvh;
pub use trace::{
    ao_at, ao_bent_at, ssdo_at, trace_ssdo_view, trace_view, Falloff, PixelSampling, Primary,
    PrimaryHit, ReferenceAo, ReferenceSsdo, TraceSettings,
};

/// The triangles of a mesh, for [`Bvh::new`].
pub fn triangles(mesh: &obscura_scene::Mesh) -> Vec<bvh::Tri> {
    mesh.indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]].map(|i| glam::Vec3::from(mesh.positions[i as usize])))
        .collect()
}
