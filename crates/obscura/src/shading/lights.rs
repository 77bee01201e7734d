//! Interleaved many-light shading on the AO's prepared buffer.
//!
//! Hundreds of point lights (virtual point lights, say) shaded at every pixel cost one
//! light evaluation per light per pixel. Segovia, Iehl, Mitanchey & Péroche (2006, "Non-
//! interleaved Deferred Shading of Interleaved Sample Patterns") give each pixel of an
//! N × N tile a different 1/N² of the lights and merge the tile back with a geometry-aware
//! filter: seed 000's interleaved sampling applied to lights instead of AO directions. Here
//! the shading pass (passes/lights/lights_shade.wgsl) reads the prepared `vec4(linear depth, view
//! normal)` buffer of an [`crate::Ao`] (one texture or its N×N layers,
//! [`crate::Ao::prepared_source`]; or any texture in that format), and the merge
//! (passes/lights/lights_merge.wgsl) interpolates each pixel class's lattice at every pixel with
//! the AO denoiser's geometric weights (passes/denoise/merge.wgsl) and averages the classes: one
//! layout, one set of weights, two filters (docs/filters.md).
//!
//! ```text
//! prepared ──lights_shade (pixel class k of N×N: lights k, k+N², …, × N²)──▶ lit (packed)
//!          ──lights_merge along x (each class interpolated, plane + normal weights)──▶ packed
//!          ──lights_merge along y──▶ irradiance
//! ```
//!
//! Where a merge follows, the shading writes each pixel's depth, normal and irradiance
//! in one packed texel (passes/lights/lit_packed.wgsl), so each of the merge's taps is one
//! fetch instead of two: on lavapipe the merge cost about a third less so (BENCHMARKS.md,
//! "Many-light shading").
//!
//! `period` 1 shades every light at every pixel (the reference the interleaved result is
//! judged against). Created once; [`Lights::record`] per frame writes three small buffers
//! (frame, count, lights) and records one dispatch, or three with the merge; GPU objects are
//! made only on the first frame at a size or with a new prepared texture. CPU mirror: [`crate::reference::shade_lights`] and
//! [`crate::reference::merge_lights_packed`] (and [`crate::reference::pack_lit`]).

use crate::gpu::pipeline::{compile_with, make_texture, Compiled, ErrorScope};
use crate::passes::bindings::lit_format;
pub use crate::passes::constants::{LIGHTS_CLASS_MIN_WEIGHT, LIGHTS_MAX, LIGHT_MIN_DISTANCE};
pub use crate::passes::lights::{GpuLight, LightsUniforms};
use crate::passes::shader::{dispatch_size, Pass};
use crate::passes::uniforms::FrameUniforms;
pub use crate::shading::prepared::Prepared;
use crate::{Error, Result};

/// Periods the passes support: 1 (every light, no merge) and 2, 4, 8.
pub const LIGHT_PERIODS: [u32; 4] = [1, 2, 4, 8];

/// A point light in the prepared buffer's view space (x right, y up, camera looking down
/// −z, the units of the linear depth).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    /// View-space position.
    pub position: [f32; 3],
    /// Irradiance at unit distance, facing the light, linear rgb.
    pub colour: [f32; 3],
    /// Distance at which the light's falloff window reaches zero (> 0).
    pub range: f32,
}

impl PointLight {
    fn gpu(&self) -> GpuLight {
        let [x, y, z] = self.position;
        let [r, g, b] = self.colour;
        let min_distance = LIGHT_MIN_DISTANCE * self.range;
        GpuLight {
            position_inv_range2: [x, y, z, 1.0 / (self.range * self.range)],
            colour_min_distance2: [r, g, b, min_distance * min_distance],
        }
    }

    /// Checks that the light can be shaded in f32 without overflow: a finite position, a
    /// colour in [0, 1e20] and a range in [1e-15, 1e18]. `index` names it in the error.
    pub fn validate(&self, index: usize) -> Result<()> {
        let finite = self.position.iter().all(|v| v.is_finite());
        let colour = self.colour.iter().all(|v| (0.0..=1e20).contains(v));
        let range = (1e-15..=1e18).contains(&self.range);
        if finite && colour && range {
            return Ok(());
        }
        Err(Error::InvalidSetting {
            field: "lights",
            value: format!("light {index}: {self:?}"),
            expected: "a finite position, a colour in [0, 1e20] and a range in [1e-15, 1e18]",
        })
    }
}

/// How [`Lights`] shades.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LightsOptions {
    /// Each pixel of a `period` × `period` tile shades 1/period² of the lights (one of
    /// [`LIGHT_PERIODS`]); 1 shades every light at every pixel.
    pub period: u32,
    /// Shade in the deinterleaved layout: one dispatch layer per pixel class, so the
    /// invocations of a workgroup read the same lights (with `period` > 1). The same image
    /// either way. Default on: on an NVIDIA H100 layered 4×4 shading with the merge was
    /// 2.1–14× faster than every light while the pixel grid was 0.71–0.74× (slower: a warp
    /// then reads 16 different lights); on lavapipe the two are within 2–7% of each other
    /// (BENCHMARKS.md, "On a hardware GPU" and "Many-light shading").
    pub layered: bool,
    /// Merge the interleaved classes (with `period` > 1). Off: [`Lights::output`] is the
    /// raw interleaved shading, for a merge of the caller's own (a TAA, say).
    pub merge: bool,
}

impl Default for LightsOptions {
    fn default() -> Self {
        Self {
            period: 4,
            layered: true,
            merge: true,
        }
    }
}

impl LightsOptions {
    fn validate(&self) -> Result<()> {
        if !LIGHT_PERIODS.contains(&self.period) {
            return Err(Error::InvalidSetting {
                field: "period",
                value: self.period.to_string(),
                expected: "1 (every light), 2, 4 or 8",
            });
        }
        Ok(())
    }

    fn merges(&self) -> bool {
        self.merge && self.period > 1
    }
}

/// The passes for one kind of prepared source (`split` 0: one texture).
#[derive(Debug)]
struct Pipelines {
    split: u32,
    shade: Compiled,
    /// The merge along x, then along y.
    merge: Option<[Compiled; 2]>,
}

/// Resources for one size and one prepared texture.
#[derive(Debug)]
struct Sized {
    size: [u32; 2],
    output_size: [u32; 2],
    prepared: wgpu::Texture,
    split: u32,
    lit: wgpu::Texture,
    /// The merge along x, and the result.
    merged: Option<[wgpu::Texture; 2]>,
    shade_group: wgpu::BindGroup,
    merge_groups: Option<[wgpu::BindGroup; 2]>,
}

/// Many-light shading passes. Create once; call [`Lights::record`] per frame.
#[derive(Debug)]
pub struct Lights {
    options: LightsOptions,
    /// Compiled for one texture at creation, for layers on the first frame that has them.
    pipelines: Vec<Pipelines>,
    frame: wgpu::Buffer,
    uniforms: wgpu::Buffer,
    lights: wgpu::Buffer,
    staging: Vec<GpuLight>,
    sized: Option<Sized>,
    created: u32,
}

/// The merge's two passes over `period` (along x, writing packed texels; along y, writing
/// irradiance), from packed texels only: geometry and irradiance in one fetch. Shared by
/// [`Lights`] and the SSDO bounce ([`crate::Ssdo`]). With `crops` the pass along y stores
/// the viewport alone (lit_out_plain.wgsl's CROPS: Lights' output; the bounce keeps the
/// processed rectangle for the combine).
pub(crate) fn compile_merge(device: &wgpu::Device, period: u32, crops: bool) -> [Compiled; 2] {
    [0.0, 1.0].map(|axis| {
        let mut c = vec![("PERIOD", period as f64), ("AXIS", axis)];
        if axis == 1.0 {
            c.push(("CROPS", crops as u32 as f64));
        }
        let pass = Pass::LightsMerge {
            packed_out: axis == 0.0,
        };
        compile_with(device, pass, &c)
    })
}

/// The textures of interleaved shading and its merge at `dims` (the processed rectangle):
/// the raw shading (packed where `merges`, else irradiance) and, where `merges`, the
/// merge's output along x (packed) and along y (irradiance). The last of them, the output,
/// is `out_dims` (the viewport; `dims` without a guard band). Shared by [`Lights`] and the
/// SSDO bounce.
pub(crate) fn make_lit_textures(
    device: &wgpu::Device,
    label: &str,
    (dims, out_dims): ((u32, u32), (u32, u32)),
    merges: bool,
) -> (wgpu::Texture, Option<[wgpu::Texture; 2]>) {
    let raw_dims = if merges { dims } else { out_dims };
    let raw = make_texture(device, label, raw_dims, 1, 1, lit_format(merges));
    let merged = merges.then(|| {
        [(" merged x", true, dims), (" merged", false, out_dims)].map(|(what, packed, d)| {
            make_texture(
                device,
                &format!("{label}{what}"),
                d,
                1,
                1,
                lit_format(packed),
            )
        })
    });
    (raw, merged)
}

impl Lights {
    /// Compiles the passes and makes the light buffer.
    pub fn new(device: &wgpu::Device, options: LightsOptions) -> Result<Self> {
        options.validate()?;
        let need = LIGHTS_MAX as u64 * std::mem::size_of::<GpuLight>() as u64;
        let has = device.limits().max_uniform_buffer_binding_size;
        if has < need {
            return Err(Error::InvalidSetting {
                field: "max_uniform_buffer_binding_size",
                value: has.to_string(),
                expected:
                    "at least 65536 (WebGPU's default) for the LIGHTS_MAX-light uniform array",
            });
        }
        let scope = ErrorScope::push(device);
        let pipelines = vec![Self::compile(device, &options, 0)];
        let buffer = |label, size: usize, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size as u64,
                usage: usage | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let frame = buffer(
            "lights frame",
            std::mem::size_of::<FrameUniforms>(),
            wgpu::BufferUsages::UNIFORM,
        );
        let uniforms = buffer(
            "lights uniforms",
            std::mem::size_of::<LightsUniforms>(),
            wgpu::BufferUsages::UNIFORM,
        );
        let lights = buffer(
            "lights",
            LIGHTS_MAX as usize * std::mem::size_of::<GpuLight>(),
            wgpu::BufferUsages::UNIFORM,
        );
        scope.pop("compiling the many-light passes")?;
        Ok(Self {
            options,
            pipelines,
            frame,
            uniforms,
            lights,
            staging: Vec::with_capacity(LIGHTS_MAX as usize),
            sized: None,
            created: 4 + if options.merges() { 2 } else { 0 },
        })
    }

    /// The shading and merge passes for a prepared source of `split` (0: one texture).
    fn compile(device: &wgpu::Device, options: &LightsOptions, split: u32) -> Pipelines {
        let layers = split > 0;
        let mut constants = vec![("PERIOD", options.period as f64)];
        if layers {
            constants.push(("SPLIT", split as f64));
        }
        let mut shade_constants = constants.clone();
        shade_constants.push((
            "LAYERED",
            (options.layered && options.period > 1) as u32 as f64,
        ));
        let packed = options.merges();
        if !packed {
            // The shading is the output: it crops a guard band away.
            shade_constants.push(("CROPS", 1.0));
        }
        let shade = compile_with(
            device,
            Pass::LightsShade { layers, packed },
            &shade_constants,
        );
        let merge = packed.then(|| compile_merge(device, options.period, true));
        Pipelines {
            split,
            shade,
            merge,
        }
    }

    /// The options it was made with.
    pub fn options(&self) -> &LightsOptions {
        &self.options
    }

    /// Records the shading (and the merge) of `lights` over `prepared` at `frame.size` (for
    /// example [`crate::Ao::prepared_source`] after the AO's frame, with the
    /// `FrameUniforms` its [`crate::Ao::validate`] returned; a plain texture converts to
    /// [`Prepared::Full`]). With a guard band ([`crate::AoInput::guard_band`]) the band is
    /// shaded and merged too, so the merge reads it beside the viewport's edges, and the
    /// output holds the viewport alone (`frame.output_size`). Everything is checked before
    /// any GPU work.
    pub fn record<'p>(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        prepared: impl Into<Prepared<'p>>,
        frame: &FrameUniforms,
        lights: &[PointLight],
    ) -> Result<()> {
        let prepared = prepared.into();
        if lights.len() > LIGHTS_MAX as usize {
            return Err(Error::InvalidSetting {
                field: "lights",
                value: format!("{} lights", lights.len()),
                expected: "at most LIGHTS_MAX (2048) per frame; shade more in several Lights",
            });
        }
        for (i, l) in lights.iter().enumerate() {
            l.validate(i)?;
        }
        prepared.validate(frame.size)?;
        let split = prepared.split();
        if !self.pipelines.iter().any(|p| p.split == split) {
            let scope = ErrorScope::push(device);
            let compiled = Self::compile(device, &self.options, split);
            scope.pop("compiling the many-light passes for layers")?;
            self.created += 1 + 2 * self.options.merges() as u32;
            self.pipelines.push(compiled);
        }
        let size = frame.size;
        self.ensure_sized(device, prepared, (size, frame.output_size))?;
        let (Some(sized), Some(pipelines)) = (
            &self.sized,
            self.pipelines.iter().find(|p| p.split == split),
        ) else {
            return Err(Error::Gpu("many-light resources missing".into()));
        };
        self.staging.clear();
        self.staging.extend(lights.iter().map(PointLight::gpu));
        if !self.staging.is_empty() {
            queue.write_buffer(&self.lights, 0, bytemuck::cast_slice(&self.staging));
        }
        let uniforms = LightsUniforms {
            count: lights.len() as u32,
            pad0: 0,
            pad1: [0; 2],
        };
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&uniforms));
        queue.write_buffer(&self.frame, 0, bytemuck::bytes_of(frame));
        let (x, y) = dispatch_size(size);
        let n = self.options.period;
        let (sx, sy, sz) = if self.options.layered && n > 1 {
            let (lx, ly) = dispatch_size([size[0].div_ceil(n), size[1].div_ceil(n)]);
            (lx, ly, n * n)
        } else {
            (x, y, 1)
        };
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("obscura lights"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&pipelines.shade.pipeline);
        pass.set_bind_group(0, &sized.shade_group, &[]);
        pass.dispatch_workgroups(sx, sy, sz);
        if let (Some(merge), Some(groups)) = (&pipelines.merge, &sized.merge_groups) {
            for (c, group) in merge.iter().zip(groups) {
                pass.set_pipeline(&c.pipeline);
                pass.set_bind_group(0, group, &[]);
                pass.dispatch_workgroups(x, y, 1);
            }
        }
        Ok(())
    }

    /// Makes the textures and bind groups for `prepared` at `size` with an output of
    /// `output_size` unless they exist.
    fn ensure_sized(
        &mut self,
        device: &wgpu::Device,
        prepared: Prepared<'_>,
        (size, output_size): ([u32; 2], [u32; 2]),
    ) -> Result<()> {
        let (texture, split) = (prepared.texture(), prepared.split());
        if self.sized.as_ref().is_some_and(|s| {
            s.size == size
                && s.output_size == output_size
                && s.prepared == *texture
                && s.split == split
        }) {
            return Ok(());
        }
        let Some(pipelines) = self.pipelines.iter().find(|p| p.split == split) else {
            return Err(Error::Gpu("many-light passes missing".into()));
        };
        self.sized = None;
        let scope = ErrorScope::push(device);
        let dims = ((size[0], size[1]), (output_size[0], output_size[1]));
        let (lit, merged) =
            make_lit_textures(device, "obscura lit", dims, pipelines.merge.is_some());
        let prepared_view = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(if split > 0 {
                wgpu::TextureViewDimension::D2Array
            } else {
                wgpu::TextureViewDimension::D2
            }),
            ..Default::default()
        });
        let lit_view = lit.create_view(&Default::default());
        let group = |c: &Compiled, entries: &[wgpu::BindGroupEntry]| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(c.pass.label()),
                layout: &c.layout,
                entries,
            })
        };
        let frame = wgpu::BindGroupEntry {
            binding: 0,
            resource: self.frame.as_entire_binding(),
        };
        let view = |binding, v| wgpu::BindGroupEntry {
            binding,
            resource: wgpu::BindingResource::TextureView(v),
        };
        let shade_group = group(
            &pipelines.shade,
            &[
                frame.clone(),
                view(1, &prepared_view),
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: self.lights.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: self.uniforms.as_entire_binding(),
                },
                view(4, &lit_view),
            ],
        );
        let merge_groups = match (&pipelines.merge, &merged) {
            (Some([x, y]), Some([mx, my])) => {
                let (mx, my) = (
                    mx.create_view(&Default::default()),
                    my.create_view(&Default::default()),
                );
                let entries = |from, to| [frame.clone(), view(2, from), view(4, to)];
                Some([
                    group(x, &entries(&lit_view, &mx)),
                    group(y, &entries(&mx, &my)),
                ])
            }
            _ => None,
        };
        scope.pop("creating the many-light textures")?;
        self.created += 2 + 4 * merged.is_some() as u32;
        self.sized = Some(Sized {
            size,
            output_size,
            prepared: texture.clone(),
            split,
            lit,
            merged,
            shade_group,
            merge_groups,
        });
        Ok(())
    }

    /// The result of the last frame: merged irradiance, or the raw shading when nothing
    /// merges (`vec4(rgb, 1)`, [`crate::passes::constants::LIT_FORMAT`]), the viewport's
    /// size (without the guard band). `None` before the first frame.
    pub fn output(&self) -> Option<&wgpu::Texture> {
        self.sized
            .as_ref()
            .map(|s| s.merged.as_ref().map_or(&s.lit, |[_, m]| m))
    }

    /// The raw shading before the merge (each pixel its class's lights, × period²): where
    /// the passes merge, packed with each pixel's geometry ([`crate::passes::constants::LIT_PACKED_FORMAT`];
    /// [`crate::reference::unpack_lit`] decodes it) over the processed rectangle (the guard
    /// band included), else as [`Lights::output`].
    pub fn raw(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().map(|s| &s.lit)
    }

    /// GPU objects (pipelines, buffers, textures, bind groups) created so far: constant
    /// once frames repeat at one size with one prepared texture.
    pub fn resource_creations(&self) -> u32 {
        self.created
    }
}
