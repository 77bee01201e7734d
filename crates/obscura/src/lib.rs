//! # obscura
//!
//! Screen-space ambient occlusion from a depth buffer, as wgpu compute passes.
//!
//! ```text
//! depth (+ normals) ──prepare──▶ vec4(linear depth, view normal) ──GTAO | HBAO | VO | VAO | SAO | VO-area──▶ AO
//!   (N×N deinterleaved layers in the default mode, merged on write; or at half/quarter
//!    resolution: downsampled by a depth rule, upsampled depth-aware)
//! ```
//!
//! Integration in five steps (`examples/compose.rs` does exactly these in a small app):
//! 1. Give your depth texture `TEXTURE_BINDING` usage (any depth format, multisampled or
//!    not, or `R32Float` linear depth).
//! 2. Once: `let mut ao = Ao::new(&device, AoOptions::default())?;` compiles the passes;
//!    describe the camera with [`Projection::from_matrix`] (or by parameters) and the
//!    [`DepthConvention`] it writes.
//! 3. Once: make an `R32Float` texture with `STORAGE_BINDING | TEXTURE_BINDING` usage for
//!    the AO (or leave [`AoInput::output`] `None` and read [`Ao::output_view`]).
//! 4. Each frame, after the depth pass, into the same encoder:
//!    `ao.record(&device, &queue, &mut encoder, &AoInput { depth, convention, projection,
//!    normals: None, viewport: None, guard_band: 0, second_layer: None, output: Some(&ao_view) }, &AoParams { radius, ..Default::default() })?;`
//!    — it validates, writes one uniform buffer and records the passes; no GPU objects
//!    are created after the first frame at a size.
//! 5. Read the AO (1 = unoccluded) in your lighting, e.g. multiply the ambient term.
//!
//! The same layout serves other sparse screen-space filters: [`Lights`] shades hundreds
//! of point lights from the AO's prepared buffer, each pixel of an N×N tile a different
//! 1/N² of them, and merges the tile back guided by geometry ([`lights`]).
//!
//! Every input is validated before any GPU work; errors are typed ([`Error`]).
//!
//! The wgpu it is built on is [`wgpu`] (re-exported): wgpu 30 by default, wgpu 29 with the
//! feature `wgpu29` (for Bevy 0.19's device and encoders; exactly one of the two).

// The wgpu major by feature (Cargo.toml): `wgpu` names it throughout the crate.
/// The wgpu obscura is built on (wgpu 29): pass its devices, encoders and textures.
#[cfg(all(feature = "wgpu29", not(feature = "wgpu30")))]
pub extern crate wgpu29 as wgpu;
#[cfg(not(any(feature = "wgpu29", feature = "wgpu30")))]
compile_error!("obscura needs one wgpu: the feature `wgpu30` (the default) or `wgpu29`");
#[cfg(all(feature = "wgpu29", feature = "wgpu30"))]
compile_error!(
    "obscura builds on one wgpu: `wgpu29` needs `default-features = false` (no `wgpu30`)"
);

/// The wgpu obscura is built on (wgpu 30): pass its devices, encoders and textures.
#[cfg(feature = "wgpu30")]
pub use wgpu;

pub mod budget;
pub mod depth;
pub mod error;
pub mod frame;
pub mod fuzz;
pub mod gpu;
pub mod passes;
pub mod reference;
pub mod settings;
pub mod shading;

// Short paths to the modules users reach for (and the paths of earlier releases).
pub use depth::{depth_map, input, noise};
pub use frame::ao;
pub use gpu::{context, gpu_struct};
pub use passes::layers as layout;
pub use passes::{constants, jitter, shader, uniforms};
pub use shading::{environment, lights, ssdo};

pub use context::{AdapterChoice, GpuContext, ADAPTER_ENV};
pub use depth_map::{DepthMap, Intrinsics};
pub use environment::{Environment, EnvironmentMap, IrradianceSh};
pub use error::{Error, Result};
pub use frame::{Ao, AoInput, ResourceCount, Timing};
pub use input::{DepthConvention, Linearize, NormalEncoding, Projection, SkyTest, Viewport};
pub use lights::{Lights, LightsOptions, PointLight};
pub use noise::{NoiseBin, NoiseEstimate};
pub use settings::{
    AoMode, AoOptions, AoParams, CameraMotion, Denoise, DepthDownsample, DepthNoise, Estimator,
    Preset, PyramidBuild, Resolution, Upsampler, DEFAULT_THICKNESS, DEPTH_MAP_ESTIMATOR,
    EVEN_MARCH_EXPONENT, FINE_LATTICE_PX, HIGH_MARCH_EXPONENT, LAYERED_GUARD_BAND,
    LAYERED_THICKNESS, MIN_SCALE,
};
pub use shading::prepared::Prepared;
pub use ssdo::{Ssdo, SsdoInputs, SsdoLighting, SsdoOptions};

/// The Rust blocks of the README and of the guide, compiled and run as doctests so that
/// they cannot fall behind the API (`cargo test --doc -p obscura`).
#[cfg(doctest)]
mod doc_pages {
    #[doc = include_str!("../../../README.md")]
    struct Readme;
    #[doc = include_str!("../../../docs/guide/integrate.md")]
    struct Integrate;
    #[doc = include_str!("../../../docs/guide/depth-maps.md")]
    struct DepthMaps;
    #[doc = include_str!("../../../docs/guide/frame-budget.md")]
    struct FrameBudget;
    #[doc = include_str!("../../../docs/guide/lights-ssdo.md")]
    struct LightsSsdo;
    #[doc = include_str!("../../../docs/guide/evaluate.md")]
    struct Evaluate;
    #[doc = include_str!("../../../docs/guide/web.md")]
    struct Web;
}
