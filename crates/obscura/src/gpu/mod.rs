//! The device and the wgpu plumbing every pipeline object shares: adapter choice and the
//! device ([`context`]), pipelines, bind groups and error scopes ([`pipeline`]), and the
//! macro that declares a struct once for Rust and WGSL ([`gpu_struct`](crate::gpu_struct)).

pub(crate) mod compat;
pub mod context;
pub mod gpu_struct;
pub mod pipeline;
