//! Screen-space directional occlusion with one diffuse bounce, on the
//! AO's outputs and its prepared buffer.
//!
//! Ritschel, Grosch & Seidel (2009, "Approximating Dynamic Global Illumination in Image
//! Space") light each pixel from the directions its screen-space samples find open, and
//! add one bounce from the samples that block. Here both halves reuse obscura's machinery:
//!
//! - **Directional occlusion of the environment.** Any AO plan's AO `V` and bent normal
//!   `b` (every layout, resolution, the denoiser and the temporal pass) give the
//!   environment's light as `V · E(b)`, `E` the environment's irradiance
//!   ([`crate::environment`], nine harmonics): the bent cone's approximation that engines
//!   use with XeGTAO's bent normals (exact for a constant sky).
//! - **One bounce** (passes/ssdo/ssdo_bounce.wgsl): GTAO's slices (Jimenez et al. 2016) marched
//!   again per pixel; on each side the arc between the tangent plane and the horizon is
//!   lit by the sample that set the horizon, whose radiance is its albedo times the
//!   environment's irradiance at its normal (unshadowed). Interleaved like the many-light
//!   pass: each pixel class of a `period` × `period` tile takes its own slice rotation and
//!   step offset, and the geometry-aware merge of [`crate::Lights`]
//!   (passes/lights/lights_merge.wgsl) reconstructs every pixel from all classes.
//! - **Combine** (passes/ssdo/ssdo_combine.wgsl): radiance = albedo · (V · E(b) + bounce).
//!
//! ```text
//! prepared, albedo ──ssdo_bounce (class k: its slices)──▶ bounce ──lights_merge ×2──▶ merged
//! AO, bent, albedo, merged ──ssdo_combine──▶ radiance (rgb, alpha 1; 0 on sky)
//! ```
//!
//! CPU mirror: [`crate::reference::ssdo_bounce`], [`crate::reference::ssdo_combine`].

use crate::gpu::pipeline::{compile_with, make_texture, Compiled, ErrorScope};
pub use crate::passes::constants::SSDO_SELF_TOLERANCE;
use crate::passes::constants::{AO_FORMAT, BENT_FORMAT, LIT_FORMAT};
use crate::passes::shader::{dispatch_size, Pass};
pub use crate::passes::ssdo::{SsdoUniforms, SSDO_PATTERNS};
use crate::passes::uniforms::FrameUniforms;
use crate::shading::environment::IrradianceSh;
use crate::shading::prepared::Prepared;
use crate::{Error, Result};

/// Periods of the bounce's interleaving: 1 (every pixel the same slices), 2, 4.
pub const SSDO_PERIODS: [u32; 3] = [1, 2, 4];

/// How [`Ssdo`] runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SsdoOptions {
    /// Add the diffuse bounce. Off: directional occlusion of the environment only.
    pub bounce: bool,
    /// Interleaving period of the bounce's slices, one of [`SSDO_PERIODS`]; above 1 the
    /// classes are merged.
    pub period: u32,
    /// Slices per pixel of the bounce, 1–8 (each marches both ways).
    pub directions: u32,
    /// Steps per side of a slice, 1–16.
    pub steps: u32,
}

impl Default for SsdoOptions {
    /// 2 slices × 4 steps per pixel over 2 × 2 pixel classes: 8 slice directions per tile.
    /// Measured on the nine shared views against the extended ray tracer (docs/ssdo.md):
    /// the 2 × 2 merge beat the 4 × 4 one and cost less (0.0127 against 0.0134 RMSE at
    /// albedo 0.5, 0.0310 against 0.0354 at albedo 1, 64 against 72 ms at 640×400 on
    /// lavapipe; its interpolation spans fewer pixels across edges); 4 slices cost 21% more for 2–6% less error, 1 slice saved 6% for
    /// 11–25% more.
    fn default() -> Self {
        Self {
            bounce: true,
            period: 2,
            directions: 2,
            steps: 4,
        }
    }
}

impl SsdoOptions {
    /// Checks the period, directions and steps ([`Ssdo::new`] does).
    pub fn validate(&self) -> Result<()> {
        let bad = |field, value: u32, expected| {
            Err(Error::InvalidSetting {
                field,
                value: value.to_string(),
                expected,
            })
        };
        if !SSDO_PERIODS.contains(&self.period) {
            return bad("period", self.period, "1, 2 or 4");
        }
        if !(1..=8).contains(&self.directions) {
            return bad("directions", self.directions, "1 to 8");
        }
        if !(1..=16).contains(&self.steps) {
            return bad("steps", self.steps, "1 to 16");
        }
        Ok(())
    }

    fn merges(&self) -> bool {
        self.bounce && self.period > 1
    }

    /// The bounce's per-class patterns: class k of n² turns its first slice by
    /// π / directions · (k + ½) / n², so the tile's slices are spread evenly over half a
    /// turn, and offsets its steps by the golden-ratio sequence (k + ½) · 0.618… mod 1.
    pub fn patterns(&self) -> [[f32; 4]; SSDO_PATTERNS] {
        let classes = (self.period * self.period) as f32;
        let mut out = [[0.0; 4]; SSDO_PATTERNS];
        for (k, p) in out.iter_mut().enumerate() {
            let t = (k as f32 + 0.5) / classes;
            let angle = std::f32::consts::PI / self.directions as f32 * t;
            let offset = ((k as f32 + 0.5) * 0.618_034).fract();
            *p = [angle.cos(), angle.sin(), offset, 0.0];
        }
        out
    }
}

/// What [`Ssdo::record`] reads, at the frame's processed size (`frame.size`, the guard band
/// included) but for the AO, at its output's (`frame.output_size`).
#[derive(Clone, Copy, Debug)]
pub struct SsdoInputs<'a> {
    /// Linear depth and view normals ([`crate::Ao::prepared_source`]).
    pub prepared: Prepared<'a>,
    /// Linear diffuse albedo (rgb; any float-readable format, TEXTURE_BINDING).
    pub albedo: &'a wgpu::Texture,
    /// The AO ([`crate::Ao::output`], [`AO_FORMAT`]).
    pub ao: &'a wgpu::Texture,
    /// Bent normals ([`crate::Ao::bent_normals`], [`BENT_FORMAT`]); `None`: the surface
    /// normal.
    pub bent: Option<&'a wgpu::Texture>,
}

/// The frame's lighting: the environment's irradiance and the camera's orientation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SsdoLighting {
    pub irradiance: IrradianceSh,
    /// Columns of the rotation from view space to world space (the inverse view matrix's
    /// upper 3 × 3; orthonormal: a scaled matrix scales the irradiance's directions).
    pub view_to_world: [[f32; 3]; 3],
}

impl SsdoInputs<'_> {
    fn validate(&self, size: [u32; 2], output_size: [u32; 2]) -> Result<()> {
        self.prepared.validate(size)?;
        let check = |what, t: &wgpu::Texture, format: Option<wgpu::TextureFormat>| {
            let size = if what == "ao" { output_size } else { size };
            let float = matches!(
                t.format().sample_type(None, None),
                Some(wgpu::TextureSampleType::Float { .. })
            );
            let ok = [t.width(), t.height()] == size
                && t.depth_or_array_layers() == 1
                && t.sample_count() == 1
                && format.is_none_or(|f| t.format() == f)
                && float
                && t.usage().contains(wgpu::TextureUsages::TEXTURE_BINDING);
            if ok {
                return Ok(());
            }
            Err(Error::InvalidTexture {
                what,
                reason: format!(
                    "{:?} {}x{}x{} ({:?}); expected {} at {}x{}, one layer, one sample, TEXTURE_BINDING",
                    t.format(),
                    t.width(),
                    t.height(),
                    t.depth_or_array_layers(),
                    t.usage(),
                    format.map_or("a float format".to_string(), |f| format!("{f:?}")),
                    size[0],
                    size[1],
                ),
            })
        };
        check("albedo", self.albedo, None)?;
        check("ao", self.ao, Some(AO_FORMAT))?;
        if let Some(b) = self.bent {
            check("bent normals", b, Some(BENT_FORMAT))?;
        }
        Ok(())
    }
}

#[derive(Debug)]
struct Pipelines {
    split: u32,
    bounce: Compiled,
    merge: Option<[Compiled; 2]>,
    combine: Compiled,
}

/// Which textures the bind groups were made for.
#[derive(Debug, PartialEq)]
struct Key {
    size: [u32; 2],
    output_size: [u32; 2],
    split: u32,
    prepared: wgpu::Texture,
    albedo: wgpu::Texture,
    ao: wgpu::Texture,
    bent: Option<wgpu::Texture>,
}

#[derive(Debug)]
struct Sized {
    key: Key,
    bounce: wgpu::Texture,
    merged: Option<[wgpu::Texture; 2]>,
    output: wgpu::Texture,
    bounce_group: wgpu::BindGroup,
    merge_groups: Option<[wgpu::BindGroup; 2]>,
    combine_group: wgpu::BindGroup,
}

/// The SSDO passes. Create once; call [`Ssdo::record`] per frame after the AO's.
#[derive(Debug)]
pub struct Ssdo {
    options: SsdoOptions,
    pipelines: Vec<Pipelines>,
    frame: wgpu::Buffer,
    uniforms: wgpu::Buffer,
    sized: Option<Sized>,
    created: u32,
}

impl Ssdo {
    /// Compiles the passes for a full-resolution prepared texture.
    pub fn new(device: &wgpu::Device, options: SsdoOptions) -> Result<Self> {
        options.validate()?;
        let scope = ErrorScope::push(device);
        let pipelines = vec![Self::compile(device, &options, 0)];
        let buffer = |label, size: usize| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let frame = buffer("ssdo frame", std::mem::size_of::<FrameUniforms>());
        let uniforms = buffer("ssdo uniforms", std::mem::size_of::<SsdoUniforms>());
        scope.pop("compiling the SSDO passes")?;
        Ok(Self {
            options,
            pipelines,
            frame,
            uniforms,
            sized: None,
            created: 2 + 2 + 2 * options.merges() as u32,
        })
    }

    fn compile(device: &wgpu::Device, options: &SsdoOptions, split: u32) -> Pipelines {
        let layers = split > 0;
        let mut constants = vec![("PERIOD", options.period as f64)];
        if layers {
            constants.push(("SPLIT", split as f64));
        }
        let mut bounce_constants = constants.clone();
        bounce_constants.extend([
            ("DIRECTIONS", options.directions as f64),
            ("STEPS", options.steps as f64),
        ]);
        // Where the merge follows, the bounce is packed with its geometry (one fetch per
        // tap, as crate::Lights merges).
        let packed = options.merges();
        let bounce = compile_with(
            device,
            Pass::SsdoBounce { layers, packed },
            &bounce_constants,
        );
        let merge =
            packed.then(|| crate::shading::lights::compile_merge(device, options.period, false));
        let split_only: Vec<_> = constants
            .iter()
            .filter(|c| c.0 == "SPLIT")
            .copied()
            .collect();
        let combine = compile_with(device, Pass::SsdoCombine { layers }, &split_only);
        Pipelines {
            split,
            bounce,
            merge,
            combine,
        }
    }

    /// The options it was made with.
    pub fn options(&self) -> &SsdoOptions {
        &self.options
    }

    /// Records the bounce, its merge and the combine at `frame.size` (the `FrameUniforms`
    /// the AO's [`crate::Ao::validate`] returned). Everything is checked before any GPU
    /// work.
    pub fn record(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        inputs: SsdoInputs<'_>,
        frame: &FrameUniforms,
        lighting: &SsdoLighting,
    ) -> Result<()> {
        inputs.validate(frame.size, frame.output_size)?;
        let finite = lighting
            .irradiance
            .coefficients
            .iter()
            .chain(&lighting.view_to_world)
            .all(|c| c.iter().all(|v| v.is_finite()));
        if !finite {
            return Err(Error::InvalidSetting {
                field: "lighting",
                value: format!("{lighting:?}"),
                expected: "finite harmonics and rotation",
            });
        }
        let split = inputs.prepared.split();
        if !self.pipelines.iter().any(|p| p.split == split) {
            let scope = ErrorScope::push(device);
            let compiled = Self::compile(device, &self.options, split);
            scope.pop("compiling the SSDO passes for layers")?;
            self.created += 2 + 2 * self.options.merges() as u32;
            self.pipelines.push(compiled);
        }
        self.ensure_sized(device, &inputs, (frame.size, frame.output_size))?;
        let (Some(sized), Some(pipelines)) = (
            &self.sized,
            self.pipelines.iter().find(|p| p.split == split),
        ) else {
            return Err(Error::Gpu("SSDO resources missing".into()));
        };
        let vec4 = |v: [f32; 3]| [v[0], v[1], v[2], 0.0];
        let uniforms = SsdoUniforms {
            irradiance: lighting.irradiance.coefficients.map(vec4),
            view_to_world: lighting.view_to_world.map(vec4),
            patterns: self.options.patterns(),
            flags: [
                inputs.bent.is_some() as u32,
                self.options.bounce as u32,
                0,
                0,
            ],
        };
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&uniforms));
        queue.write_buffer(&self.frame, 0, bytemuck::bytes_of(frame));
        let (x, y) = dispatch_size(frame.size);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("obscura ssdo"),
            timestamp_writes: None,
        });
        if self.options.bounce {
            pass.set_pipeline(&pipelines.bounce.pipeline);
            pass.set_bind_group(0, &sized.bounce_group, &[]);
            pass.dispatch_workgroups(x, y, 1);
        }
        if let (Some(merge), Some(groups)) = (&pipelines.merge, &sized.merge_groups) {
            for (c, group) in merge.iter().zip(groups) {
                pass.set_pipeline(&c.pipeline);
                pass.set_bind_group(0, group, &[]);
                pass.dispatch_workgroups(x, y, 1);
            }
        }
        pass.set_pipeline(&pipelines.combine.pipeline);
        pass.set_bind_group(0, &sized.combine_group, &[]);
        let (ox, oy) = dispatch_size(frame.output_size);
        pass.dispatch_workgroups(ox, oy, 1);
        Ok(())
    }

    fn ensure_sized(
        &mut self,
        device: &wgpu::Device,
        inputs: &SsdoInputs<'_>,
        (size, output_size): ([u32; 2], [u32; 2]),
    ) -> Result<()> {
        let key = Key {
            size,
            output_size,
            split: inputs.prepared.split(),
            prepared: inputs.prepared.texture().clone(),
            albedo: inputs.albedo.clone(),
            ao: inputs.ao.clone(),
            bent: inputs.bent.cloned(),
        };
        if self.sized.as_ref().is_some_and(|s| s.key == key) {
            return Ok(());
        }
        let Some(pipelines) = self.pipelines.iter().find(|p| p.split == key.split) else {
            return Err(Error::Gpu("SSDO passes missing".into()));
        };
        self.sized = None;
        let scope = ErrorScope::push(device);
        let dims = (size[0], size[1]);
        // The bounce keeps the processed rectangle; the combine crops to the output.
        let (bounce, merged) = crate::shading::lights::make_lit_textures(
            device,
            "obscura ssdo bounce",
            (dims, dims),
            pipelines.merge.is_some(),
        );
        let output_dims = (output_size[0], output_size[1]);
        let output = make_texture(device, "obscura ssdo", output_dims, 1, 1, LIT_FORMAT);
        let prepared = key.prepared.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(if key.split > 0 {
                wgpu::TextureViewDimension::D2Array
            } else {
                wgpu::TextureViewDimension::D2
            }),
            ..Default::default()
        });
        let view = |t: &wgpu::Texture| t.create_view(&Default::default());
        let (albedo, ao, bounce_view, output_view) = (
            view(&key.albedo),
            view(&key.ao),
            view(&bounce),
            view(&output),
        );
        let bent = key.bent.as_ref().map_or_else(|| ao.clone(), view);
        let group = |c: &Compiled, views: &[(u32, &wgpu::TextureView)], uniforms: bool| {
            let mut entries = vec![wgpu::BindGroupEntry {
                binding: 0,
                resource: self.frame.as_entire_binding(),
            }];
            if uniforms {
                entries.push(wgpu::BindGroupEntry {
                    binding: 3,
                    resource: self.uniforms.as_entire_binding(),
                });
            }
            entries.extend(views.iter().map(|&(binding, v)| wgpu::BindGroupEntry {
                binding,
                resource: wgpu::BindingResource::TextureView(v),
            }));
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(c.pass.label()),
                layout: &c.layout,
                entries: &entries,
            })
        };
        let bounce_group = group(
            &pipelines.bounce,
            &[(1, &prepared), (2, &albedo), (4, &bounce_view)],
            true,
        );
        let (merge_groups, merged_view) = match (&pipelines.merge, &merged) {
            (Some([x, y]), Some([mx, my])) => {
                let (mx, my) = (view(mx), view(my));
                let groups = [
                    group(x, &[(2, &bounce_view), (4, &mx)], false),
                    group(y, &[(2, &mx), (4, &my)], false),
                ];
                (Some(groups), my)
            }
            _ => (None, bounce_view.clone()),
        };
        // Without a bounce, the AO stands in for the unread bounce binding.
        let bounce_read = if self.options.bounce {
            &merged_view
        } else {
            &ao
        };
        let combine_group = group(
            &pipelines.combine,
            &[
                (1, &prepared),
                (2, &albedo),
                (4, &ao),
                (5, &bent),
                (6, bounce_read),
                (7, &output_view),
            ],
            true,
        );
        scope.pop("creating the SSDO textures")?;
        // Textures: bounce, output (and two merged); bind groups: bounce, combine (and two
        // merges).
        self.created += 4 + 4 * merged.is_some() as u32;
        self.sized = Some(Sized {
            key,
            bounce,
            merged,
            output,
            bounce_group,
            merge_groups,
            combine_group,
        });
        Ok(())
    }

    /// The last frame's radiance: `vec4(albedo · (V · E(b) + bounce), 1)` on surfaces, 0 on
    /// sky ([`LIT_FORMAT`]), the viewport's size (without the guard band). `None` before
    /// the first frame.
    pub fn output(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().map(|s| &s.output)
    }

    /// The last frame's bounce irradiance (before the albedo), merged where it merges, over
    /// the processed rectangle (the guard band included); `None` before the first frame or
    /// without [`SsdoOptions::bounce`].
    pub fn bounce(&self) -> Option<&wgpu::Texture> {
        self.sized
            .as_ref()
            .filter(|_| self.options.bounce)
            .map(|s| s.merged.as_ref().map_or(&s.bounce, |[_, m]| m))
    }

    /// The raw interleaved bounce before the merge (`None` as for [`Ssdo::bounce`]): where it
    /// merges, packed with each pixel's geometry ([`crate::passes::constants::LIT_PACKED_FORMAT`];
    /// [`crate::reference::unpack_lit`] decodes it), else as [`Ssdo::bounce`].
    pub fn bounce_raw(&self) -> Option<&wgpu::Texture> {
        self.sized
            .as_ref()
            .filter(|_| self.options.bounce)
            .map(|s| &s.bounce)
    }

    /// GPU objects created so far: constant once frames repeat with the same textures.
    pub fn resource_creations(&self) -> u32 {
        self.created
    }
}
