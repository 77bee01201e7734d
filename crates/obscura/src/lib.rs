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
//! 1. Give your depth texture `TEXTURE_BINDING` usage (any depth format, or `R32Float`
//!    linear depth; not multisampled).
//! 2. Once: `let mut ao = Ao::new(&device, AoOptions::default())?;` compiles the passes;
//!    describe the camera with [`Projection::from_matrix`] (or by parameters) and the
//!    [`DepthConvention`] it writes.
//! 3. Once: make an `R32Float` texture with `STORAGE_BINDING | TEXTURE_BINDING` usage for
//!    the AO (or leave [`AoInput::output`] `None` and read [`Ao::output_view`]).
//! 4. Each frame, after the depth pass, into the same encoder:
//!    `ao.record(&device, &queue, &mut encoder, &AoInput { depth, convention, projection,
//!    normals: None, viewport: None, output: Some(&ao_view) }, &AoParams { radius, ..Default::default() })?;`
//!    — it validates, writes one uniform buffer and records the passes; no GPU objects
//!    are created after the first frame at a size.
//! 5. Read the AO (1 = unoccluded) in your lighting, e.g. multiply the ambient term.
//!
//! The same layout serves other sparse screen-space filters: [`Lights`] shades hundreds
//! of point lights from the AO's prepared buffer, each pixel of an N×N tile a different
//! 1/N² of them, and merges the tile back guided by geometry ([`lights`]).
//!
//! Every input is validated before any GPU work; errors are typed ([`Error`]).

pub mod ao;
pub mod budget;
pub mod context;
pub mod depth_map;
pub mod environment;
pub mod error;
pub mod fuzz;
pub mod gpu_struct;
pub mod input;
pub mod jitter;
pub mod layout;
pub mod lights;
pub mod noise;
pub mod reference;
pub mod settings;
pub mod shader;
pub mod ssdo;
pub mod uniforms;

pub use ao::{Ao, AoInput, ResourceCount, Timing};
pub use context::{AdapterChoice, GpuContext, ADAPTER_ENV};
pub use depth_map::{DepthMap, Intrinsics};
pub use environment::{Environment, EnvironmentMap, IrradianceSh};
pub use error::{Error, Result};
pub use input::{DepthConvention, Linearize, NormalEncoding, Projection, SkyTest, Viewport};
pub use lights::{Lights, LightsOptions, PointLight, Prepared};
pub use noise::{NoiseBin, NoiseEstimate};
pub use settings::{
    AoMode, AoOptions, AoParams, CameraMotion, Denoise, DepthDownsample, DepthNoise, Estimator,
    Preset, PyramidBuild, Resolution, Upsampler, MIN_SCALE,
};
pub use ssdo::{Ssdo, SsdoInputs, SsdoLighting, SsdoOptions};
