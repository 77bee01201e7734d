//! The WGSL prelude generated from Rust constants and `gpu_struct!` declarations, shader
//! module creation, and dispatch sizes.

use crate::passes::constants::*;
use crate::passes::jitter::{PATTERN_COUNT, PATTERN_DIM};
use crate::passes::lights::{GpuLight, LightsUniforms};
use crate::passes::ssdo::SsdoUniforms;
use crate::passes::uniforms::FrameUniforms;

/// Compiles one of obscura's WGSL passes without wgpu's loop-bounding guard.
///
/// wgpu adds a counter to every shader loop by default (`force_loop_bounding`) so that an
/// infinite loop cannot become undefined behaviour in the driver's compiler. The counter
/// costs an increment and a branch per iteration, and it stops the driver from unrolling
/// constant-trip loops: on lavapipe the GTAO pass ran 13% slower with it
/// (BENCHMARKS.md, "Shader loops without wgpu's bound"). Every loop in obscura's passes
/// is a counted `for` whose counter moves monotonically toward a bound it cannot step
/// over, and the test `every_shader_loop_is_counted` (tests/gpu/shaders.rs) checks that
/// form in every file, so the guard has nothing to guard. Every other runtime check
/// (bounds checks, integer-division guards) stays on.
pub(crate) fn create_module(
    device: &wgpu::Device,
    label: Option<&str>,
    source: String,
) -> wgpu::ShaderModule {
    let mut checks = wgpu::ShaderRuntimeChecks::checked();
    checks.force_loop_bounding = false;
    // SAFETY: `force_loop_bounding = false` requires that no shader loops forever. The
    // sources are obscura's own passes, whose loops are all counted (see above, and the
    // test that enforces it); only this crate calls this function.
    #[allow(unsafe_code)]
    unsafe {
        device.create_shader_module_trusted(
            wgpu::ShaderModuleDescriptor {
                label,
                source: wgpu::ShaderSource::Wgsl(source.into()),
            },
            checks,
        )
    }
}

/// Constants and structs generated from Rust.
pub fn prelude() -> String {
    format!(
        "// Generated from Rust (crates/obscura/src/passes/constants.rs): do not copy these values.\n\
         const WG_SIZE: u32 = {WORKGROUP_SIZE}u;\n\
         const PATTERN_DIM: u32 = {PATTERN_DIM}u;\n\
         const PATTERN_COUNT: u32 = {PATTERN_COUNT}u;\n\
         const GUARD_AO_MARGIN: u32 = {GUARD_AO_MARGIN}u;\n\
         const NEAR_FIELD_CELLS: u32 = {NEAR_FIELD_CELLS}u;\n\
         const IGN_WEIGHTS: vec3<f32> = vec3<f32>({});\n\
         const IGN_SHIFT: f32 = {IGN_SHIFT:?};\n\
         const PLANE_TOLERANCE: f32 = {PLANE_TOLERANCE:?};\n\
         const DEPTH_RANGE_TOLERANCE: f32 = {DEPTH_RANGE_TOLERANCE:?};\n\
         const SPHERE_THICKNESS: f32 = {SPHERE_THICKNESS:?};\n\
         const DENOISE_RADIUS_TOLERANCE: f32 = {DENOISE_RADIUS_TOLERANCE:?};\n\
         const NOISE_TOLERANCE_SIGMAS: f32 = {NOISE_TOLERANCE_SIGMAS:?};\n\
         const DENOISE_RIDGE: f32 = {DENOISE_RIDGE:?};\n\
         const HISTORY_NORMAL_COS: f32 = {HISTORY_NORMAL_COS:?};\n\
         const TENT_WEIGHTS: array<f32, 3> = array<f32, 3>({});\n\
         const TENT_SPACING: i32 = {TENT_SPACING};\n\
         const ACOS_POLY: array<f32, 4> = array<f32, 4>({});\n\
         const ACOS_POLY_FINE: array<f32, 8> = array<f32, 8>({});\n\
         const FIT_RADIUS: i32 = {FIT_RADIUS};\n\
         const FIT_NORMAL_TAN: f32 = {FIT_NORMAL_TAN:?};\n\
         const FIT_MAX_STRIDE: i32 = {FIT_MAX_STRIDE};\n\
         const FIT_SIGMAS: f32 = {FIT_SIGMAS:?};\n\
         const FIT_SLOPE: f32 = {FIT_SLOPE:?};\n\
         const NOISE_OFFSET_SIGMAS: f32 = {NOISE_OFFSET_SIGMAS:?};\n\
         const LIGHTS_CLASS_MIN_WEIGHT: f32 = {LIGHTS_CLASS_MIN_WEIGHT:?};\n\
         const LIGHTS_MAX: u32 = {LIGHTS_MAX}u;\n\
         const LIT_RATIO_MAX: vec3<f32> = vec3<f32>({});\n\
         const LIT_NORMAL_MAX: f32 = {LIT_NORMAL_MAX:?};\n\
         const SSDO_SELF_TOLERANCE: f32 = {SSDO_SELF_TOLERANCE:?};\n\
         const SH9_SCALE: array<f32, 5> = array<f32, 5>({});\n\
         const SECTORS: u32 = {SECTORS}u;\n\
         const GTAO_FALLOFF_END: f32 = {GTAO_FALLOFF_END:?};\n\
         {}{}{}{}",
        wgsl_floats(&IGN_WEIGHTS),
        wgsl_floats(&TENT_WEIGHTS),
        wgsl_floats(&ACOS_POLY),
        wgsl_floats(&ACOS_POLY_FINE),
        wgsl_floats(&LIT_RATIO_MAX),
        wgsl_floats(&SH9_SCALE),
        FrameUniforms::wgsl(),
        GpuLight::wgsl(),
        LightsUniforms::wgsl(),
        SsdoUniforms::wgsl()
    )
}

/// `a, b, c` with every value spelled as a WGSL float literal.
fn wgsl_floats(values: &[f32]) -> String {
    values
        .iter()
        .map(|v| format!("{v:?}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Workgroups needed to cover `size` pixels.
pub fn dispatch_size(size: [u32; 2]) -> (u32, u32) {
    (
        size[0].div_ceil(WORKGROUP_SIZE),
        size[1].div_ceil(WORKGROUP_SIZE),
    )
}
