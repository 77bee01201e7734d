//! # obscura
//!
//! Screen-space ambient occlusion from a depth buffer, as wgpu compute passes.
//!
//! ```text
//! depth (+ normals) ──prepare──▶ vec4(linear depth, view normal) ──GTAO | HBAO──▶ AO (R32Float)
//!                  (N×N deinterleaved layers in the default mode, merged on write)
//! ```
//!
//! Integration in four steps:
//! 1. Create a [`GpuContext`] (or use your own `wgpu::Device`).
//! 2. `let mut ao = Ao::new(&device, AoOptions::default())?;` once.
//! 3. Each frame: `ao.record(&device, &queue, &mut encoder, &AoInput { .. }, &AoParams::default())?;`
//! 4. Read [`Ao::output_view`] (1 = unoccluded) in your lighting.
//!
//! Every input is validated before any GPU work; errors are typed ([`Error`]).

pub mod ao;
pub mod context;
pub mod error;
pub mod gpu_struct;
pub mod input;
pub mod jitter;
pub mod layout;
pub mod reference;
pub mod settings;
pub mod shader;
pub mod uniforms;

pub use ao::{Ao, AoInput, ResourceCount, Timing};
pub use context::{AdapterChoice, GpuContext, ADAPTER_ENV};
pub use error::{Error, Result};
pub use input::{DepthConvention, Linearize, NormalEncoding, Projection, SkyTest, Viewport};
pub use settings::{
    AoMode, AoOptions, AoParams, Denoise, DepthDownsample, Estimator, Preset, Resolution, Upsampler,
};
