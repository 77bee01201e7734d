//! What the caller hands over each frame ([`AoInput`]) and its validation: every input is
//! checked before any GPU work, and errors are typed ([`crate::Error`]).

use crate::passes::constants::AO_FORMAT;
use crate::passes::shader::DepthBinding;
use crate::passes::uniforms::{guarded, FrameUniforms};
use crate::{
    AoOptions, AoParams, DepthConvention, Error, NormalEncoding, Projection, Result, Viewport,
};

/// What the caller hands over each frame.
#[derive(Clone, Copy, Debug)]
pub struct AoInput<'a> {
    /// Depth, as a depth format (Depth32Float, Depth24Plus, Depth16Unorm; depth-only view
    /// for combined depth-stencil formats) or a float format (R32Float, R16Float), with
    /// `TEXTURE_BINDING` usage. A multisampled depth-format texture (MSAA) is resolved
    /// first, one depth per pixel (passes/prepare/resolve_depth.wgsl: the pixel-centre depth
    /// where every sample sees one surface, else the nearest sample).
    pub depth: &'a wgpu::TextureView,
    /// How the depth values are encoded.
    pub convention: DepthConvention,
    /// The camera projection that produced the depth.
    pub projection: Projection,
    /// Optional view-space normals, same size as the depth texture; reconstructed from
    /// depth when `None`.
    pub normals: Option<(&'a wgpu::TextureView, NormalEncoding)>,
    /// The region to process; `None` means the whole depth texture.
    pub viewport: Option<Viewport>,
    /// A guard band: pixels of depth on each side of the viewport that the samples read
    /// but the output does not cover (0: none, samples stop at the viewport's edge). The
    /// depth texture (and the normal texture) must hold the band. `projection` stays the
    /// viewport's; the passes widen it over the band. The AO is computed over the band
    /// too and cropped, so it costs the band's pixels; the intermediate textures
    /// ([`crate::Ao::bent_normals`], [`crate::Ao::prepared`], the history) cover the
    /// viewport grown by the band, the viewport at (band, band). Beyond
    /// [`crate::constants::GUARD_AO_MARGIN`] working texels of the viewport (without a
    /// history) the AO pass skips the band: AO 1 and zero bent normals there.
    /// [`crate::Lights`] and [`crate::Ssdo`] shade and merge the band too and output the
    /// viewport alone.
    pub guard_band: u32,
    /// The second depth layer ([`AoOptions::second_layer`]): per pixel the depth of the
    /// nearest front-facing surface behind the first layer's, peeled at least the thickness
    /// prior ([`AoParams::thickness`], times the radius) behind it (a depth-peeling pass
    /// that discards fragments nearer than that), the clear value where there is none. The
    /// depth texture's format, size and convention, single-sampled, with
    /// `TEXTURE_BINDING` usage. Required when the options ask for it, refused otherwise.
    pub second_layer: Option<&'a wgpu::TextureView>,
    /// Where to write the AO: a view of a whole `R32Float` 2D texture (one mip, one layer)
    /// of the viewport's size with `STORAGE_BINDING` usage; 1 = unoccluded. `None`: a
    /// texture the library owns ([`crate::Ao::output`]).
    pub output: Option<&'a wgpu::TextureView>,
}

/// The second layer's checks ([`AoInput::second_layer`]).
fn check_second_layer(options: &AoOptions, input: &AoInput<'_>) -> Result<()> {
    let bad = |reason: String| {
        Err(Error::InvalidTexture {
            what: "second layer",
            reason,
        })
    };
    let Some(second) = input.second_layer else {
        if options.second_layer {
            return bad("the options ask for a second layer (AoOptions::second_layer) but the input has none".into());
        }
        return Ok(());
    };
    if !options.second_layer {
        return bad(
            "the input has one but the options were created without AoOptions::second_layer".into(),
        );
    }
    let (t, d) = (second.texture(), input.depth.texture());
    if d.sample_count() != 1 {
        return bad("it needs single-sampled depth; resolve the multisampled depth first".into());
    }
    if t.format() != d.format() || t.sample_count() != 1 {
        return bad(format!(
            "it is {:?} with {} samples but the depth is {:?}: it must have the depth's format, single-sampled",
            t.format(),
            t.sample_count(),
            d.format()
        ));
    }
    if (t.width(), t.height()) != (d.width(), d.height()) {
        return bad(format!(
            "it is {}x{} but the depth texture is {}x{}",
            t.width(),
            t.height(),
            d.width(),
            d.height()
        ));
    }
    if !t.usage().contains(wgpu::TextureUsages::TEXTURE_BINDING) {
        return bad("it lacks TEXTURE_BINDING usage".into());
    }
    Ok(())
}

/// How a depth input binds.
pub(crate) fn depth_binding(format: wgpu::TextureFormat) -> Result<DepthBinding> {
    use wgpu::TextureFormat as F;
    match format {
        F::Depth32Float
        | F::Depth24Plus
        | F::Depth16Unorm
        | F::Depth24PlusStencil8
        | F::Depth32FloatStencil8 => Ok(DepthBinding::Depth),
        F::R32Float | F::R16Float => Ok(DepthBinding::Float),
        _ => Err(Error::UnsupportedFormat {
            what: "depth",
            format,
            expected: "Depth32Float, Depth24Plus, Depth16Unorm, a depth-stencil format, R32Float or R16Float",
        }),
    }
}

/// Checks `input` and `params` against `options` and the device's largest texture side
/// (`max_dim`), and derives the frame uniforms. No GPU work.
pub(crate) fn validate(
    options: &AoOptions,
    max_dim: u32,
    input: &AoInput<'_>,
    params: &AoParams,
) -> Result<FrameUniforms> {
    let tex = input.depth.texture();
    let binding = depth_binding(tex.format())?;
    if tex.sample_count() != 1 && binding != DepthBinding::Depth {
        return Err(Error::UnsupportedFormat {
            what: "multisampled depth",
            format: tex.format(),
            expected: "a depth format (Depth32Float, Depth24Plus, Depth16Unorm, a depth-stencil format) when multisampled",
        });
    }
    if !tex.usage().contains(wgpu::TextureUsages::TEXTURE_BINDING) {
        return Err(Error::InvalidTexture {
            what: "depth",
            reason: "it lacks TEXTURE_BINDING usage".into(),
        });
    }
    let viewport = input
        .viewport
        .unwrap_or(Viewport::full(tex.width(), tex.height()));
    let fits = |v: Viewport, w: u32, h: u32| {
        v.x.checked_add(v.width).is_some_and(|r| r <= w)
            && v.y.checked_add(v.height).is_some_and(|b| b <= h)
    };
    if !fits(viewport, tex.width(), tex.height()) {
        return Err(Error::InvalidViewport(format!(
            "{viewport:?} does not fit the {}x{} depth texture",
            tex.width(),
            tex.height()
        )));
    }
    let processed = guarded(viewport, input.guard_band)?;
    if !fits(processed, tex.width(), tex.height()) {
        return Err(Error::InvalidViewport(format!(
            "a guard band of {} px around {viewport:?} leaves the {}x{} depth texture; \
             the depth texture must hold the viewport and the band on every side",
            input.guard_band,
            tex.width(),
            tex.height()
        )));
    }
    if processed.width > max_dim || processed.height > max_dim {
        return Err(Error::TooLarge {
            width: processed.width,
            height: processed.height,
            max: max_dim,
        });
    }
    if let Some((n, _)) = input.normals {
        let nt = n.texture();
        if !matches!(
            nt.format().sample_type(None, None),
            Some(wgpu::TextureSampleType::Float { .. })
        ) || nt.sample_count() != 1
        {
            return Err(Error::UnsupportedFormat {
                what: "normal",
                format: nt.format(),
                expected: "a single-sampled float or unorm colour format",
            });
        }
        if nt.width() != tex.width() || nt.height() != tex.height() {
            return Err(Error::InvalidTexture {
                what: "normal",
                reason: format!(
                    "it is {}x{} but the depth texture is {}x{}",
                    nt.width(),
                    nt.height(),
                    tex.width(),
                    tex.height()
                ),
            });
        }
        if !nt.usage().contains(wgpu::TextureUsages::TEXTURE_BINDING) {
            return Err(Error::InvalidTexture {
                what: "normal",
                reason: "it lacks TEXTURE_BINDING usage".into(),
            });
        }
    }
    check_second_layer(options, input)?;
    if let Some(out) = input.output {
        let t = out.texture();
        if t.format() != AO_FORMAT {
            return Err(Error::UnsupportedFormat {
                what: "output",
                format: t.format(),
                expected: "R32Float",
            });
        }
        let bad = |reason: String| {
            Err(Error::InvalidTexture {
                what: "output",
                reason,
            })
        };
        if !t.usage().contains(wgpu::TextureUsages::STORAGE_BINDING) {
            return bad("it lacks STORAGE_BINDING usage".into());
        }
        if t.dimension() != wgpu::TextureDimension::D2
            || t.depth_or_array_layers() != 1
            || t.mip_level_count() != 1
            || t.sample_count() != 1
        {
            return bad("it must be a single-sampled 2D texture with one mip and one layer".into());
        }
        if (t.width(), t.height()) != (viewport.width, viewport.height) {
            return bad(format!(
                "it is {}x{} but the viewport is {}x{}",
                t.width(),
                t.height(),
                viewport.width,
                viewport.height
            ));
        }
    }
    FrameUniforms::new(
        &input.projection,
        input.convention,
        input.normals.map(|n| n.1),
        (viewport, input.guard_band),
        options,
        params,
    )
}
