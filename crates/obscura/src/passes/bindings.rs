//! Each pass's bind group layout: the frame uniforms at binding 0, then its textures by
//! binding number, as its WGSL declares them (the plan, [`crate::frame::plan`], binds the
//! same numbers).

use crate::passes::constants::{
    AO_FORMAT, AO_PACKED_FORMAT, BENT_FORMAT, HISTORY_FORMAT, LINEAR_DEPTH_FORMAT, LIT_FORMAT,
    LIT_PACKED_FORMAT, MOMENTS_FORMAT, PREPARED_FORMAT, PYRAMID_FORMAT, PYRAMID_LEVELS_PER_PASS,
    RESOLVED_DEPTH_FORMAT,
};
use crate::passes::shader::{DepthBinding, Pass, PrepareStore, PyramidSource};
use crate::Upsampler;

fn texture_entry(
    binding: u32,
    sample_type: wgpu::TextureSampleType,
    view_dimension: wgpu::TextureViewDimension,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension,
            multisampled: false,
        },
        count: None,
    }
}

fn storage_entry(
    binding: u32,
    format: wgpu::TextureFormat,
    view_dimension: wgpu::TextureViewDimension,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format,
            view_dimension,
        },
        count: None,
    }
}

fn uniform_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

const UNFILTERED: wgpu::TextureSampleType = wgpu::TextureSampleType::Float { filterable: false };
const D2: wgpu::TextureViewDimension = wgpu::TextureViewDimension::D2;
const D2_ARRAY: wgpu::TextureViewDimension = wgpu::TextureViewDimension::D2Array;

/// The many-light passes' output: packed for the merge, or irradiance.
pub fn lit_format(packed: bool) -> wgpu::TextureFormat {
    if packed {
        LIT_PACKED_FORMAT
    } else {
        LIT_FORMAT
    }
}

/// The AO or temporal pass's AO output: packed beside the geometry for the denoiser, or
/// the AO alone.
pub fn ao_format(packed: bool) -> wgpu::TextureFormat {
    if packed {
        AO_PACKED_FORMAT
    } else {
        AO_FORMAT
    }
}

/// The bind group layout of `pass`: uniforms at 0, then its textures.
pub fn layout_entries(pass: Pass) -> Vec<wgpu::BindGroupLayoutEntry> {
    let dim = |layers: bool| if layers { D2_ARRAY } else { D2 };
    let rest = match pass {
        Pass::Prepare {
            depth,
            store,
            second_layer,
            ..
        } => {
            let raw = match depth {
                DepthBinding::Depth => wgpu::TextureSampleType::Depth,
                DepthBinding::Float => UNFILTERED,
            };
            let mut v = vec![
                texture_entry(1, raw, D2),
                texture_entry(2, UNFILTERED, D2),
                storage_entry(3, PREPARED_FORMAT, dim(store == PrepareStore::Layers)),
            ];
            if let PrepareStore::Down { normals, .. } = store {
                let format = if normals {
                    PREPARED_FORMAT
                } else {
                    LINEAR_DEPTH_FORMAT
                };
                v.push(storage_entry(4, format, D2));
            }
            if second_layer {
                v.extend([
                    texture_entry(5, raw, D2),
                    storage_entry(6, LINEAR_DEPTH_FORMAT, D2),
                ]);
            }
            v
        }
        Pass::AoFull {
            bent,
            second_layer,
            packed,
            ..
        } => {
            let mut v = vec![
                texture_entry(1, UNFILTERED, D2),
                storage_entry(2, ao_format(packed), D2),
            ];
            if bent {
                v.push(storage_entry(4, BENT_FORMAT, D2));
            }
            if second_layer {
                v.push(texture_entry(5, UNFILTERED, D2));
            }
            v
        }
        Pass::AoLayered {
            merge,
            bent,
            second_layer,
            packed,
            ..
        } => {
            let mut v = vec![
                texture_entry(1, UNFILTERED, D2_ARRAY),
                storage_entry(2, ao_format(packed), dim(!merge)),
            ];
            if bent {
                v.push(storage_entry(4, BENT_FORMAT, D2));
            }
            if second_layer {
                v.push(texture_entry(5, UNFILTERED, D2));
            }
            v
        }
        // The split reuses the prepare store fragment (binding 3); 2 is unused.
        Pass::Deinterleave => vec![
            texture_entry(1, UNFILTERED, D2),
            storage_entry(3, PREPARED_FORMAT, D2_ARRAY),
        ],
        Pass::Interleave => vec![
            texture_entry(1, UNFILTERED, D2_ARRAY),
            storage_entry(2, AO_FORMAT, D2),
        ],
        Pass::Pyramid { source } => vec![
            texture_entry(1, UNFILTERED, dim(source == PyramidSource::Layers)),
            storage_entry(2, PYRAMID_FORMAT, D2),
        ],
        Pass::Moments { source } => vec![
            texture_entry(1, UNFILTERED, dim(source == PyramidSource::Layers)),
            storage_entry(2, MOMENTS_FORMAT, D2),
        ],
        Pass::PyramidLevels => std::iter::once(texture_entry(1, UNFILTERED, D2))
            .chain((2..2 + PYRAMID_LEVELS_PER_PASS).map(|b| storage_entry(b, PYRAMID_FORMAT, D2)))
            .collect(),
        Pass::Downsample { .. } | Pass::Rescale => vec![
            texture_entry(1, UNFILTERED, D2),
            storage_entry(2, PREPARED_FORMAT, D2),
        ],
        Pass::UpsampleScaled => vec![
            texture_entry(1, UNFILTERED, D2),
            texture_entry(2, UNFILTERED, D2),
            texture_entry(3, UNFILTERED, D2),
            storage_entry(4, AO_FORMAT, D2),
        ],
        Pass::Upsample {
            upsampler, bent, ..
        } => {
            let mut v = vec![
                texture_entry(1, UNFILTERED, D2),
                texture_entry(2, UNFILTERED, D2),
                texture_entry(3, UNFILTERED, D2),
                storage_entry(4, AO_FORMAT, D2),
            ];
            if upsampler == Upsampler::Classified {
                v.push(texture_entry(5, UNFILTERED, D2));
            }
            if bent {
                v.extend([
                    texture_entry(6, UNFILTERED, D2),
                    storage_entry(7, BENT_FORMAT, D2),
                ]);
            }
            v
        }
        // The packed taps carry their geometry: no prepared source at 1.
        Pass::Denoise { bent } => {
            let mut v = vec![
                texture_entry(2, UNFILTERED, D2),
                storage_entry(3, AO_FORMAT, D2),
            ];
            if bent {
                v.extend([
                    texture_entry(4, UNFILTERED, D2),
                    storage_entry(5, BENT_FORMAT, D2),
                ]);
            }
            v
        }
        Pass::Temporal {
            layers,
            bent,
            packed,
        } => {
            let mut v = vec![
                texture_entry(1, UNFILTERED, dim(layers)),
                texture_entry(2, UNFILTERED, D2),
                texture_entry(3, UNFILTERED, D2),
                storage_entry(4, HISTORY_FORMAT, D2),
                storage_entry(5, ao_format(packed), D2),
            ];
            if bent {
                v.extend([
                    texture_entry(6, UNFILTERED, D2),
                    texture_entry(7, UNFILTERED, D2),
                    storage_entry(8, BENT_FORMAT, D2),
                    storage_entry(9, BENT_FORMAT, D2),
                ]);
            }
            v
        }
        Pass::AoDownsample { .. } => vec![
            texture_entry(1, UNFILTERED, D2),
            storage_entry(2, AO_FORMAT, D2),
        ],
        Pass::LightsShade { layers, packed } => vec![
            texture_entry(1, UNFILTERED, dim(layers)),
            uniform_entry(2),
            uniform_entry(3),
            storage_entry(4, lit_format(packed), D2),
        ],
        Pass::LightsMerge { packed_out } => vec![
            texture_entry(2, wgpu::TextureSampleType::Uint, D2),
            storage_entry(4, lit_format(packed_out), D2),
        ],
        Pass::SsdoBounce { layers, packed } => vec![
            texture_entry(1, UNFILTERED, dim(layers)),
            texture_entry(2, UNFILTERED, D2),
            uniform_entry(3),
            storage_entry(4, lit_format(packed), D2),
        ],
        Pass::SsdoCombine { layers } => vec![
            texture_entry(1, UNFILTERED, dim(layers)),
            texture_entry(2, UNFILTERED, D2),
            uniform_entry(3),
            texture_entry(4, UNFILTERED, D2),
            texture_entry(5, UNFILTERED, D2),
            texture_entry(6, UNFILTERED, D2),
            storage_entry(7, LIT_FORMAT, D2),
        ],
        Pass::ResolveDepth => vec![
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Depth,
                    view_dimension: D2,
                    multisampled: true,
                },
                count: None,
            },
            storage_entry(2, RESOLVED_DEPTH_FORMAT, D2),
        ],
    };
    let pyramid = match pass {
        Pass::AoFull { estimator, .. } | Pass::AoLayered { estimator, .. } => {
            estimator.uses_pyramid() || estimator.uses_moments()
        }
        _ => false,
    };
    let rest = rest
        .into_iter()
        .chain(pyramid.then(|| texture_entry(3, UNFILTERED, D2)));
    std::iter::once(uniform_entry(0)).chain(rest).collect()
}
