//! [`Ao`]: the AO pipeline object and the recorder that walks its [`Plan`]. Creation
//! compiles the plan's passes; each frame, [`Ao::record`] validates the inputs, writes
//! the frame uniforms (full and working resolution), creates what the plan names at a new
//! size ([`super::resources`]) and records the passes into the caller's encoder.

use super::plan::Plan;
use super::resources::SizedResources;
use super::resources::{placeholder_normals, PrepareInputs, Resolve, Shared};
use super::temporal::TemporalState;
#[cfg(not(target_arch = "wasm32"))]
use super::timing::time_passes;
use super::timing::PassCall;
use super::validate::{depth_binding, validate};
// The types of `Ao`'s signatures, also at this module's path (`obscura::ao::AoInput`).
pub use super::{resources::ResourceCount, timing::Timing, validate::AoInput};
use crate::gpu::pipeline::{compile, compile_with, uniform_buffer, Compiled, ErrorScope};
use crate::passes::shader::{dispatch_size, DepthBinding, Pass};
use crate::passes::uniforms::FrameUniforms;
use crate::{AoOptions, AoParams, Error, Resolution, Result};

/// The AO pipeline. Create once; call [`Ao::record`] per frame.
#[derive(Debug)]
pub struct Ao {
    pub(super) options: AoOptions,
    pub(super) plan: Plan,
    /// Prepare for [depth-format, float] inputs × [given, reconstructed] normals.
    prepare: [[Compiled; 2]; 2],
    /// Prepare with depth and normals from plane fits, for [depth-format, float] inputs:
    /// compiled on the first frame with a depth noise model ([`AoParams::depth_noise`]).
    prepare_fit: [Option<Compiled>; 2],
    /// The pipelines of the passes after prepare, in [`Plan::passes`] order.
    later: Vec<Compiled>,
    /// Frame uniforms at full and at working resolution (the same when full).
    uniforms: wgpu::Buffer,
    work_uniforms: wgpu::Buffer,
    dummy_normals: wgpu::TextureView,
    max_dim: u32,
    pub(super) sized: Option<SizedResources>,
    pub(super) resolve: Option<Resolve>,
    /// The output step's pass with `CROPS` (passes/output.wgsl), compiled on the first
    /// frame with a guard band: it stores the viewport alone.
    output_crops: Option<Compiled>,
    created: ResourceCount,
    pub(super) temporal: TemporalState,
}

impl Ao {
    /// Validates `options` and compiles every pipeline they need.
    pub fn new(device: &wgpu::Device, options: AoOptions) -> Result<Self> {
        options.validate()?;
        let scope = ErrorScope::push(device);
        let pyramid_levels = options
            .pyramid
            .levels_per_pass(device.adapter_info().device_type);
        let plan = Plan::new(&options, pyramid_levels);
        let prepare = [DepthBinding::Depth, DepthBinding::Float].map(|depth| {
            [false, true].map(|reconstruct| {
                let store = plan.prepare_store;
                let fit = false;
                let pass = Pass::Prepare {
                    depth,
                    store,
                    reconstruct,
                    fit,
                    second_layer: options.second_layer,
                };
                compile(device, pass, &options)
            })
        });
        let later = plan
            .passes()
            .into_iter()
            .map(|pass| compile(device, pass, &options))
            .collect();
        let size = std::mem::size_of::<FrameUniforms>();
        let uniforms = uniform_buffer(device, "obscura frame uniforms", size);
        let work_uniforms =
            uniform_buffer(device, "obscura working-resolution frame uniforms", size);
        let dummy_normals = placeholder_normals(device);
        scope.pop("creating obscura's pipelines")?;
        let created = ResourceCount {
            buffers: 2,
            textures: 1,
            texture_views: 1,
            bind_groups: 0,
        };
        Ok(Self {
            options,
            plan,
            prepare,
            prepare_fit: [None, None],
            later,
            uniforms,
            work_uniforms,
            dummy_normals,
            max_dim: device.limits().max_texture_dimension_2d,
            sized: None,
            resolve: None,
            output_crops: None,
            created,
            temporal: TemporalState::default(),
        })
    }

    /// The options the pipelines were compiled for.
    pub fn options(&self) -> &AoOptions {
        &self.options
    }

    /// The frame plan the pipelines were compiled for: passes, textures and bindings.
    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    /// Checks `input` and `params` and derives the frame uniforms. No GPU work.
    pub fn validate(&self, input: &AoInput<'_>, params: &AoParams) -> Result<FrameUniforms> {
        validate(&self.options, self.max_dim, input, params)
    }

    /// Validates, uploads uniforms, creates what a new size or new input views need, and
    /// returns the passes of this frame in order.
    fn frame_passes(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        input: &AoInput<'_>,
        params: &AoParams,
    ) -> Result<Vec<PassCall<'_>>> {
        let mut frame = self.validate(input, params)?;
        let multisampled = input.depth.texture().sample_count() > 1;
        // A multisampled depth is resolved first and the prepare pass reads the result.
        let (depth_view, binding) = if multisampled {
            let compile_resolve = || compile(device, Pass::ResolveDepth, &self.options);
            let (uniforms, created) = (&self.uniforms, &mut self.created);
            Resolve::ensure(
                &mut self.resolve,
                device,
                uniforms,
                input.depth,
                compile_resolve,
                created,
            )?;
            let r = self
                .resolve
                .as_ref()
                .expect("resolve resources were just created");
            (r.view.clone(), DepthBinding::Float)
        } else {
            let binding = depth_binding(input.depth.texture().format())?;
            (input.depth.clone(), binding)
        };
        let shared = Shared {
            uniforms: &self.uniforms,
            work_uniforms: &self.work_uniforms,
            compiled: &self.later,
        };
        let sizes = (frame.size, frame.output_size);
        if self
            .sized
            .as_ref()
            .is_none_or(|s| (s.size, s.output_size) != sizes)
        {
            // Drop the old set first: at large sizes two sets may not fit together.
            self.sized = None;
            let sized = SizedResources::new(device, &self.plan, shared, sizes, &mut self.created)?;
            self.sized = Some(sized);
            // A new size starts a new history.
            self.temporal.valid = false;
        }
        let parity = self
            .temporal
            .apply(&self.options, params.motion, &mut frame);
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&frame));
        let mut work = if self.options.resolution == Resolution::Scaled {
            frame.at_scale()
        } else {
            frame.at_factor(self.options.resolution.factor())
        };
        self.temporal.set_grid(&mut work);
        queue.write_buffer(&self.work_uniforms, 0, bytemuck::bytes_of(&work));
        let Some(sized) = self.sized.as_mut() else {
            return Err(Error::Gpu("size-dependent resources missing".into()));
        };
        let b = match binding {
            DepthBinding::Depth => 0,
            DepthBinding::Float => 1,
        };
        let fit = input.normals.is_none() && !params.depth_noise.is_none();
        if fit && self.prepare_fit[b].is_none() {
            let scope = ErrorScope::push(device);
            let pass = Pass::Prepare {
                depth: binding,
                store: self.plan.prepare_store,
                reconstruct: true,
                fit: true,
                second_layer: self.options.second_layer,
            };
            let compiled = compile(device, pass, &self.options);
            scope.pop("compiling the noisy-depth prepare pass")?;
            self.prepare_fit[b] = Some(compiled);
        }
        let prepare = match (&self.prepare_fit[b], fit) {
            (Some(c), true) => c,
            _ => &self.prepare[b][input.normals.is_none() as usize],
        };
        let normals = input.normals.map(|n| n.0);
        let normals = (normals.unwrap_or(&self.dummy_normals), normals);
        let inputs = PrepareInputs {
            depth: depth_view,
            normals,
            second: input.second_layer,
            fit,
        };
        let prepare_bind = sized.bind_prepare(
            device,
            &self.plan,
            (prepare, &self.uniforms),
            inputs,
            &mut self.created,
        )?;
        // With a guard band the output step stores the viewport alone.
        let banded = frame.size != frame.output_size;
        if banded && self.output_crops.is_none() {
            let Some(pass) = self.plan.output_step().map(|i| self.plan.steps[i].pass) else {
                return Err(Error::Gpu("output step missing".into()));
            };
            let mut constants = pass.constants(&self.options);
            constants.push(("CROPS", 1.0));
            let scope = ErrorScope::push(device);
            let compiled = compile_with(device, pass, &constants);
            scope.pop("compiling the output pass that drops a guard band")?;
            self.output_crops = Some(compiled);
        }
        let output_bind =
            sized.bind_output(device, &self.plan, shared, input.output, &mut self.created)?;
        let p = parity as usize;
        let mut passes = Vec::with_capacity(sized.later.len() + 2);
        if let (true, Some(r)) = (multisampled, &self.resolve) {
            let (x, y) = dispatch_size(frame.size);
            let bg = r.binding.as_ref().map(|b| b.1.clone());
            let bg = bg.ok_or_else(|| Error::Gpu("resolve bind group missing".into()))?;
            passes.push((&r.compiled, bg, [x, y, 1]));
        }
        let n = self.options.mode.split();
        passes.push((
            prepare,
            prepare_bind,
            sized.prepare_dispatch.at(work.size, n),
        ));
        for (k, (i, bg, d)) in sized.later.iter().enumerate() {
            let bg = bg.as_ref().unwrap_or(&output_bind)[p].clone();
            let c = match &self.output_crops {
                Some(c) if banded && k == sized.output_step.0 => c,
                _ => &self.later[*i],
            };
            passes.push((c, bg, d.at(work.size, n)));
        }
        Ok(passes)
    }

    /// Validates the inputs, writes the frame uniforms and records the AO passes into
    /// `encoder`, in one compute pass with a debug group per pass. The result is
    /// [`Ao::output`] (or [`AoInput::output`]) once the encoder's commands have run.
    /// Record at most once per queue submission (the uniforms are shared).
    ///
    /// Creating resources (the first frame at a size, new input views) happens inside
    /// out-of-memory and validation error scopes and comes back as a typed error. Errors
    /// of the recorded commands themselves (a device lost mid-frame) reach the device's
    /// uncaptured-error and device-lost handlers, as for any other pass of yours; a scope
    /// per frame would cost every frame. [`crate::GpuContext::run`] turns them into typed
    /// errors.
    pub fn record(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        input: &AoInput<'_>,
        params: &AoParams,
    ) -> Result<()> {
        let passes = self.frame_passes(device, queue, input, params)?;
        let mut cpass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("obscura"),
            timestamp_writes: None,
        });
        for (c, bg, d) in &passes {
            cpass.push_debug_group(c.pass.label());
            cpass.set_pipeline(&c.pipeline);
            cpass.set_bind_group(0, bg, &[]);
            cpass.dispatch_workgroups(d[0], d[1], d[2]);
            cpass.pop_debug_group();
        }
        Ok(())
    }

    /// Runs one frame and returns each pass's label and milliseconds, measured as `timing`
    /// says. For benchmarks: it creates timing resources per call. Native only (it blocks).
    #[cfg(not(target_arch = "wasm32"))]
    pub fn run_timed(
        &mut self,
        ctx: &crate::GpuContext,
        input: &AoInput<'_>,
        params: &AoParams,
        timing: Timing,
    ) -> Result<Vec<(&'static str, f64)>> {
        let passes = self.frame_passes(&ctx.device, &ctx.queue, input, params)?;
        time_passes(ctx, &passes, timing)
    }

    /// How many GPU objects this `Ao` has created. Frames at an unchanged size with the same
    /// input views create nothing; a resize recreates only the size-dependent textures,
    /// views and bind groups; new input views cost one bind group. ([`Ao::run_timed`], for
    /// benchmarks, also creates query buffers, not counted.)
    pub fn resource_creations(&self) -> ResourceCount {
        self.created
    }

    /// Forgets the temporal history: the next frame starts a new one (as after a camera
    /// cut, [`crate::CameraMotion::Cut`], or a resize).
    pub fn reset_history(&mut self) {
        self.temporal.valid = false;
    }

    /// Forgets the temporal history and restarts the frame sequence, so the next frames
    /// sample as the first ones did: accumulations that can be reproduced call by call.
    pub fn restart(&mut self) {
        self.temporal.valid = false;
        self.temporal.frame = 0;
    }
}
