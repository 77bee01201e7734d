//! The constants that Rust and WGSL share: the one source of truth. Every pass's source
//! starts with [`crate::passes::shader::prelude`], generated from these values and from the
//! [`gpu_struct!`](crate::gpu_struct) declarations (the frame uniforms, and the structs in
//! the passes' folders), so a value is never written twice.

/// Compute workgroup edge: every pass runs `WORKGROUP_SIZE × WORKGROUP_SIZE` invocations.
pub const WORKGROUP_SIZE: u32 = 8;

/// Storage format of the prepared buffer: `vec4(linear depth, view normal xyz)`.
pub const PREPARED_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Storage format of the AO output: one channel, 1 = unoccluded, 0 = fully occluded.
pub const AO_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
/// Storage format of the AO beside its pixel's geometry, written by the pass the spatial
/// denoiser reads (the AO pass, or the temporal pass): `vec4(linear depth, normal x,
/// normal y, ±(1 + AO))`, the sign the normal's z's (passes/estimators/ao_packed.wgsl), so
/// that each of the denoiser's taps is one fetch instead of two.
pub const AO_PACKED_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Storage format of the full-resolution linear depth written by the fused downsampling
/// prepare pass ([`PrepareStore::Down`](crate::passes::shader::PrepareStore::Down)).
pub const LINEAR_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
/// Storage format of the MSAA resolve's output: the raw depth of one sample, or the mean of
/// all (passes/prepare/resolve_depth.wgsl), read by the prepare pass as a float depth input.
pub const RESOLVED_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
/// Storage format of the depth pyramid: `vec4(select, min, max, 0)` (passes/pyramid/pyramid.wgsl).
pub const PYRAMID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Storage format of the depth moments pyramid: `vec4(valid fraction, mean, variance, 0)`
/// of linear depth (passes/pyramid/moments.wgsl), read by VO's area integral.
pub const MOMENTS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// Inside a guard band ([`crate::AoInput::guard_band`]) the AO pass computes the output
/// and this many working texels around it, and skips the rest of the band (writing 1):
/// what the later passes read beyond the output (the denoiser's 2, box/tent downsampling's
/// 2 and the upsampler's 2 low-resolution texels) lies inside. Not with temporal
/// accumulation, whose reprojection may read anywhere in the band.
pub const GUARD_AO_MARGIN: u32 = 8;

/// The near field of the deinterleaved AO pass, in cells of its N-pixel lattice: offsets
/// shorter than this many cells are taken at full resolution (from whichever layer holds
/// the pixel), farther ones are snapped to the layer's own lattice. Snapping moves a sample
/// by up to half a cell in each axis, as much as the distance of the nearest samples, where
/// contact occlusion is decided; farther out it is a small fraction of the distance, and
/// neighbouring invocations keep fetching neighbouring texels of one layer (the layout's
/// cache benefit, seed 000: deinterleaved texturing).
pub const NEAR_FIELD_CELLS: u32 = 2;

/// Interleaved gradient noise (Jimenez 2014, "Next Generation Post Processing in Call of
/// Duty: Advanced Warfare"): `fract(c · fract(a x + b y))` for pixel (x, y) is `[a, b, c]`;
/// the second value of a pixel is the first at (x + s, y + s), s = [`IGN_SHIFT`]. The
/// deinterleaved AO pass turns each pixel's pattern by it (jitter.rs, `pixel_pattern`).
pub const IGN_WEIGHTS: [f32; 3] = [0.067_110_56, 0.005_837_15, 52.982_92];
/// See [`IGN_WEIGHTS`].
pub const IGN_SHIFT: f32 = 5.588_238;

/// Tangent-plane tolerance of the depth-aware passes (classified and bilateral upsampling,
/// the denoiser, temporal reprojection): a sample farther than this fraction of the depth
/// (or [`NOISE_TOLERANCE_SIGMAS`] σ of the depth noise, if more) from the centre's tangent
/// plane is on another surface. 2%: well above the depth change across a few pixels of a
/// surface at 80° to the view (~1%), well below the gap between stacked objects.
pub const PLANE_TOLERANCE: f32 = 0.02;
/// The classified upsampler treats a low-resolution texel whose footprint's depths (depth
/// pyramid min/max) span more than this fraction of its depth as an edge.
pub const DEPTH_RANGE_TOLERANCE: f32 = 0.05;

/// VO and VAO (passes/estimators/sphere.wgsl): the solid behind a visible surface is assumed this
/// many AO radii deep (Loos & Sloan 2010's thickness model) instead of infinitely deep.
/// Two radii, the sphere's diameter, chosen over all shared views among 1, 2 and ∞ radii:
/// mean discontinuity-band RMSE against ray-traced AO 0.165 → 0.127 (VO) and 0.151 → 0.093
/// (VAO), whole-image RMSE 0.147 → 0.150 (VO) and 0.113 → 0.098 (VAO).
pub const SPHERE_THICKNESS: f32 = 2.0;

/// The spatial denoiser's tangent-plane tolerance is also at most this fraction of the AO
/// radius (passes/denoise/denoise.wgsl): AO changes over the scale of the radius, so on a distant
/// view, where 2% of the depth spans several radii, points that far apart across a
/// surface do not share AO. Chosen over all shared views among 0.05, 0.1, 0.25 and no
/// limit (GTAO high, 2×2 deinterleaved, mean RMSE against ray-traced AO 0.0609, 0.0609,
/// 0.0613, 0.0619).
pub const DENOISE_RADIUS_TOLERANCE: f32 = 0.1;
/// Every depth-aware pass's tangent-plane tolerance (the upsamplers, temporal reprojection,
/// the denoiser) is at least this many σ of the depth noise ([`crate::DepthNoise`]), so
/// noise does not read as an edge (common.wgsl, `plane_tolerance`).
pub const NOISE_TOLERANCE_SIGMAS: f32 = 2.0;
/// Ridge on the spatial denoiser's slope, in px² (passes/denoise/denoise.wgsl). Against the spread
/// of two columns of full-weight taps (2/9 px² or more) it shrinks a slope by under 0.05%;
/// where the spread is about the ridge or less (taps across it nearly or wholly rejected)
/// the fit falls back towards the weighted mean, and taps that all lie on one line get
/// slope 0 across it instead of 0/0. It dominates f32 rounding of the spread (~1e-7).
pub const DENOISE_RIDGE: f32 = 1e-4;
/// Temporal reprojection keeps a history texel only if its surface normal is within about
/// 26° of this pixel's (cosine at least this): across a convex edge the neighbouring face's
/// texels lie within the tangent-plane tolerance of this face's plane, and on a face seen
/// edge-on (a pixel or two wide, just disoccluded) they made up most of the bilinear
/// footprint. The normal test of reprojection caches (SVGF, Schied et al. 2017), at about
/// the angle where the denoiser's normal weight halves (25°).
pub const HISTORY_NORMAL_COS: f32 = 0.9;
/// Storage format of the temporal history: `vec4(AO, frames accumulated, linear depth,
/// normal)`, the view-space normal packed in one float (passes/temporal/temporal.wgsl, `pack_normal`).
pub const HISTORY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Many-light shading ([`crate::lights`]): `vec4(irradiance rgb, 1)`.
pub const LIT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Many-light shading on its way to the merge (passes/lights/lit_packed.wgsl): linear depth,
/// the normal in 3 × 10 bits, and irradiance as its largest component and three ratios to it.
pub const LIT_PACKED_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
/// The packed normal's components are stored as `(n + 1) / 2 ×` this, rounded: 10 bits each
/// (passes/lights/lit_packed.wgsl), within 1/1023 of the normal; the merge's weights need no more.
pub const LIT_NORMAL_MAX: f32 = 1023.0;
/// The packed irradiance's ratios to its largest component are rounded to `ratio ×` these:
/// 11, 11 and 10 bits (passes/lights/lit_packed.wgsl).
pub const LIT_RATIO_MAX: [f32; 3] = [2047.0, 2047.0, 1023.0];
/// Bent normals ([`crate::AoOptions::bent_normals`]): `vec4(n, 0)`, n unit, view space.
pub const BENT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// One axis of seed 003's tent downsample filter (passes/denoise/ao_downsample.wgsl): taps 2
/// texels apart weighted 1-2-1 (the 2D weights are the outer product, 1-2-1 × 1-2-1 / 16).
pub const TENT_WEIGHTS: [f32; 3] = [1.0, 2.0, 1.0];
/// Abramowitz & Stegun 4.4.45: acos(x) ≈ sqrt(1 − x)(a0 + a1 x + a2 x² + a3 x³) on [0, 1],
/// |error| ≤ 5e-5 (GTAO's `fast_acos`, passes/estimators/gtao_arcs.wgsl, and its mirror).
pub const ACOS_POLY: [f32; 4] = [1.570_728_8, -0.212_114_4, 0.074_261, -0.018_729_3];
/// The end of GTAO's horizon falloff, in radii (passes/estimators/gtao.wgsl). A sample's
/// front within R counts in full, as the ray-traced reference counts hits within R. Beyond
/// R it still counts in part: a surface seen beyond R usually continues behind its front,
/// into the sphere (a ledge's top seen from above, a wall's far face), and the farther the
/// front, the less likely that is. Its weight (`gtao_falloff`, gtao_arcs.wgsl) falls
/// linearly in r² from 1 at R to 0 at GTAO_FALLOFF_END × R and mixes its horizon toward
/// the tangent plane's, as XeGTAO mixes toward its low horizon (there linear in distance,
/// and within R). With the published test (every front within R, none beyond) GTAO was
/// too bright on every shared view (bias +0.008). The bitmask's thickness prior models
/// the body exactly; its infinitely thick case follows GTAO. Chosen over all nine shared
/// views (end 1.6, 1.8, 2.0, 2.2, 2.5: mean RMSE 0.0452, 0.0440, 0.0437, 0.0441, 0.0456;
/// a hard cut at 1.3 R 0.0457, at R 0.0511; docs/history.md).
pub const GTAO_FALLOFF_END: f32 = 2.0;
/// The bitmask's sectors a slice (passes/estimators/bitmask.wgsl): the bits of a `u32`.
pub const SECTORS: u32 = 32;

/// Abramowitz & Stegun 4.4.46: acos(x) ≈ sqrt(1 − x)(a0 + a1 x + … + a7 x⁷) on [0, 1],
/// |error| ≤ 2e-8: the bitmask's sector edges (`sector_edge`, passes/estimators/bitmask.wgsl,
/// and its mirror), whose integrals must close to the hemisphere's at float precision. a0,
/// 1.5707963050, is π/2 in f32.
pub const ACOS_POLY_FINE: [f32; 8] = [
    std::f32::consts::FRAC_PI_2,
    -0.214_598_8,
    0.088_978_99,
    -0.050_174_3,
    0.030_891_88,
    -0.017_088_126,
    0.006_670_09,
    -0.001_262_491,
];
/// Noisy depth (passes/prepare/normals_fit.wgsl): each pixel's plane is fitted to
/// (2 · FIT_RADIUS + 1)² depths, taps `stride` pixels apart.
pub const FIT_RADIUS: i32 = 3;
/// The fit's window is the smallest (3 × 3, 5 × 5, 7 × 7 taps, then taps up to
/// FIT_MAX_STRIDE pixels apart) whose normal has a standard error below this tangent
/// (20°): wider windows smooth away real detail the size of the window. Chosen over all
/// shared views with Kinect-like noise among tan 5°, 10° and 20° (GTAO, 2×2
/// deinterleaved, no denoiser, FIT_SIGMAS 3, mean RMSE against ray-traced AO on six views 0.1359,
/// 0.1295, 0.1250; docs/depth-noise.md).
pub const FIT_NORMAL_TAN: f32 = 0.36;
pub const FIT_MAX_STRIDE: i32 = 4;
/// Taps whose depth is farther than FIT_SIGMAS σ from the plane (√2 FIT_SIGMAS σ from the
/// centre's depth, plus FIT_SLOPE footprints per pixel of offset, in the first fit) belong
/// to another surface. FIT_SLOPE = 4: surfaces up to 76° from facing the camera. 1.5:
/// chosen over all shared views with Kinect-like noise among 1, 1.5, 2 and 3 (mean RMSE
/// with the spatial denoiser 0.1004, 0.0980, 0.1011, 0.1198 at 20°; docs/depth-noise.md):
/// wider bands merge real steps of the size of the noise into the plane.
pub const FIT_SIGMAS: f32 = 1.5;
pub const FIT_SLOPE: f32 = 4.0;
/// The estimators measure occluders from the surface raised this many σ along its normal
/// ([`crate::DepthNoise`]; common.wgsl, `estimator_origin`).
pub const NOISE_OFFSET_SIGMAS: f32 = 1.0;
/// Texel distance between the tent filter's taps.
pub const TENT_SPACING: i32 = 2;

/// Pyramid levels one pass of [`Pass::PyramidLevels`](crate::passes::shader::Pass::PyramidLevels) writes: WebGPU's default limit of
/// storage textures per shader stage.
pub const PYRAMID_LEVELS_PER_PASS: u32 = 4;

/// A light's squared distance is clamped below at the square of this fraction of its
/// range (passes/lights/lights_shade.wgsl): the usual clamp of a virtual point light's 1/d²
/// singularity near surfaces (Keller 1997, "Instant Radiosity"), which otherwise puts a
/// firefly on every surface a light sits on. 5%: a light lights the disc of its range
/// with at most 400× the irradiance at its range's edge (before the window).
pub const LIGHT_MIN_DISTANCE: f32 = 0.05;

/// The merge (passes/lights/lights_merge.wgsl) leaves a pixel class out when its taps' weights
/// (linear, 1 to period − 1 each, times geometric, at most 1) sum below this: neither of
/// its taps lies within about 2.6 plane tolerances of the centre's surface (exp(−2.6²) ≈
/// 1e-3 for a tap of linear weight 1, a little farther for heavier ones).
pub const LIGHTS_CLASS_MIN_WEIGHT: f32 = 1e-3;

/// Most lights per frame: the lights are a uniform array (passes/lights/lights_shade.wgsl),
/// and 2048 × 32 bytes is WebGPU's default `maxUniformBufferBindingSize`, 64 KiB.
pub const LIGHTS_MAX: u32 = 2048;

/// The SSDO bounce skips samples less than this fraction of the depth (plus the depth noise's
/// tolerance) above the receiver's tangent plane: they are its own surface, which a sample
/// snapped off the slice can show a hair above the horizon (passes/ssdo/ssdo_bounce.wgsl).
/// Relative to the depth, not the radius: the AO denoiser's plane tolerance (2% of the
/// depth) can exceed the whole AO radius on a distant view and dropped every occluder
/// there (the bounce of the city views fell by half).
pub const SSDO_SELF_TOLERANCE: f32 = 1e-4;

/// The harmonics' normalising constants: 1/(2√π), √3/(2√π), √15/(2√π), √5/(4√π),
/// √15/(4√π) (shared with passes/ssdo/ssdo_env.wgsl).
pub const SH9_SCALE: [f32; 5] = [0.282_095, 0.488_603, 1.092_548, 0.315_392, 0.546_274];
