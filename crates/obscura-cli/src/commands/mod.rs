//! The subcommands, one module each. None imports another: what they share lives in the
//! crate's top-level modules (`options`, `views`, `timing`, `readback`, `progress`,
//! `ssdo_shading`, `output`).

pub mod bench;
pub mod cost;
pub mod eval;
pub mod lights;
pub mod render;
