//! One AO frame: the plan as data ([`plan`]), the GPU objects it names ([`resources`]),
//! and [`Ao`], the recorder that walks it. Validation of the caller's inputs, the state
//! temporal accumulation carries between frames, and per-pass timing live beside them.

pub mod access;
pub mod ao;
pub mod cost;
pub mod plan;
#[cfg(test)]
mod plan_tests;
mod plan_types;
pub mod resources;
pub mod temporal;
pub mod timing;
pub mod validate;

pub use ao::Ao;
pub use resources::ResourceCount;
pub use timing::Timing;
pub use validate::AoInput;
