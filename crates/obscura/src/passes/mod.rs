//! Every compute pass: one folder a concern, each with its WGSL files and, in its
//! `mod.rs`, the CPU mirror that reads like the WGSL (same names, same order of
//! operations) and that the tests compare the GPU with. [`shader`] assembles a pass's
//! source from the fragments, [`bindings`] gives its bind group layout, [`constants`] and
//! [`uniforms`] are the values and the struct that Rust and WGSL share.

pub mod bindings;
pub mod constants;
pub mod denoise;
pub mod estimators;
pub mod jitter;
pub mod layers;
pub mod lights;
pub mod prepare;
pub mod pyramid;
pub mod shader;
pub mod ssdo;
pub mod temporal;
pub mod uniforms;
pub mod upsample;
