//! Depth input: the conventions and projections a depth buffer comes with ([`input`]),
//! captured depth maps with intrinsics and their renderer ([`depth_map`]), and the
//! sensor-noise estimate ([`noise`]).

pub mod depth_map;
pub mod input;
pub mod noise;
