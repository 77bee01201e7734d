//! WGSL source assembly. Every pass is `prelude + common.wgsl + <pass>.wgsl`, where the
//! prelude is generated here from Rust constants and [`gpu_struct!`](crate::gpu_struct)
//! declarations: the single source of truth for values both sides use.

use crate::jitter::{PATTERN_COUNT, PATTERN_DIM};
use crate::uniforms::FrameUniforms;

/// Compute workgroup edge: every pass runs `WORKGROUP_SIZE × WORKGROUP_SIZE` invocations.
pub const WORKGROUP_SIZE: u32 = 8;

/// Storage format of the prepared buffer: `vec4(linear depth, view normal xyz)`.
pub const PREPARED_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Storage format of the AO output: one channel, 1 = unoccluded, 0 = fully occluded.
pub const AO_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// The compute passes of the pipeline. The name is the file name, pipeline name and debug label.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pass {
    /// Linearize a depth-format texture (`texture_depth_2d`) and build normals.
    PrepareDepth,
    /// Linearize a float texture (`texture_2d<f32>`, e.g. linear view depth) and build normals.
    PrepareFloat,
    /// Horizon-based AO, one full-resolution pass, per-pixel 4×4 patterns.
    Hbao,
}

impl Pass {
    /// Every pass, for validation tests.
    pub const ALL: [Pass; 3] = [Pass::PrepareDepth, Pass::PrepareFloat, Pass::Hbao];

    /// The pass's label (also its WGSL file's stem).
    pub fn label(self) -> &'static str {
        match self {
            Pass::PrepareDepth => "prepare_depth",
            Pass::PrepareFloat => "prepare_float",
            Pass::Hbao => "hbao",
        }
    }

    /// The complete WGSL source of the pass.
    pub fn source(self) -> String {
        let body = match self {
            Pass::PrepareDepth => [
                include_str!("../shaders/depth_input_depth.wgsl"),
                include_str!("../shaders/prepare.wgsl"),
            ]
            .concat(),
            Pass::PrepareFloat => [
                include_str!("../shaders/depth_input_float.wgsl"),
                include_str!("../shaders/prepare.wgsl"),
            ]
            .concat(),
            Pass::Hbao => include_str!("../shaders/hbao.wgsl").to_string(),
        };
        format!(
            "{}\n{}\n{}",
            prelude(),
            include_str!("../shaders/common.wgsl"),
            body
        )
    }
}

/// Constants and structs generated from Rust.
pub fn prelude() -> String {
    format!(
        "// Generated from Rust (crates/obscura/src/shader.rs): do not copy these values.\n\
         const WG_SIZE: u32 = {WORKGROUP_SIZE}u;\n\
         const PATTERN_DIM: u32 = {PATTERN_DIM}u;\n\
         const PATTERN_COUNT: u32 = {PATTERN_COUNT}u;\n\
         {}",
        FrameUniforms::wgsl()
    )
}

/// Workgroups needed to cover `size` pixels.
pub fn dispatch_size(size: [u32; 2]) -> (u32, u32) {
    (
        size[0].div_ceil(WORKGROUP_SIZE),
        size[1].div_ceil(WORKGROUP_SIZE),
    )
}
