//! The GPU objects a [`Plan`] names for one frame size: its textures (created once per
//! size, [`Plan::spec`]), each step's bind groups (on even and odd frames, which differ
//! only for the passes that touch a history), and the bind groups of the inputs that the
//! caller passes (kept while the caller passes the same views). Frames at an unchanged
//! size with the same views create nothing.

use super::plan::{Dispatch, FrameAt, Grid, Plan, Res};
use crate::gpu::pipeline::{array_view, bind_group, make_texture, Compiled, ErrorScope};
use crate::passes::constants::{AO_FORMAT, PYRAMID_FORMAT, PYRAMID_LEVELS_PER_PASS};
use crate::passes::shader::Pass;
use crate::{Error, Result};

/// GPU objects an [`crate::Ao`] has created since [`crate::Ao::new`], by kind (see
/// [`crate::Ao::resource_creations`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ResourceCount {
    pub buffers: u32,
    pub textures: u32,
    pub texture_views: u32,
    pub bind_groups: u32,
}

/// The frame uniforms at full and at working resolution, and the compiled passes after
/// prepare (in [`Plan::passes`] order): what every step's bind group refers to.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shared<'a> {
    pub uniforms: &'a wgpu::Buffer,
    pub work_uniforms: &'a wgpu::Buffer,
    pub compiled: &'a [Compiled],
}

impl<'a> Shared<'a> {
    fn buffer(&self, at: FrameAt) -> &'a wgpu::Buffer {
        match at {
            FrameAt::Full => self.uniforms,
            FrameAt::Work => self.work_uniforms,
        }
    }

    fn compiled_index(&self, pass: Pass) -> usize {
        self.compiled
            .iter()
            .position(|c| c.pass == pass)
            .expect("every step's pass is compiled in Ao::new")
    }
}

/// What the prepare pass binds for normals when the caller gives none (1×1, never read).
pub(crate) fn placeholder_normals(device: &wgpu::Device) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("obscura no-normals placeholder"),
            size: wgpu::Extent3d {
                width: 1,
                height: 1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
        .create_view(&Default::default())
}

/// The MSAA depth resolve ([`Pass::ResolveDepth`]), created on the first frame whose depth
/// input is multisampled.
#[derive(Debug)]
pub(crate) struct Resolve {
    pub compiled: Compiled,
    /// One raw depth per pixel, at the depth texture's size (the prepare pass reads it at
    /// the viewport's texels, as it reads the caller's depth).
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
    /// The bind group of the last frame's depth view, kept while the caller passes it.
    pub binding: Option<(wgpu::TextureView, wgpu::BindGroup)>,
}

impl Resolve {
    /// Creates (or keeps) the resolve's texture at the depth texture's size and its bind
    /// group for `depth`. `compile` makes the pass the first time.
    pub fn ensure(
        slot: &mut Option<Resolve>,
        device: &wgpu::Device,
        uniforms: &wgpu::Buffer,
        depth: &wgpu::TextureView,
        compile: impl FnOnce() -> Compiled,
        created: &mut ResourceCount,
    ) -> Result<()> {
        let tex = depth.texture();
        let size = (tex.width(), tex.height());
        let fits = |r: &Resolve| (r.texture.width(), r.texture.height()) == size;
        if slot
            .as_ref()
            .is_some_and(|r| fits(r) && r.binding.as_ref().is_some_and(|b| &b.0 == depth))
        {
            return Ok(());
        }
        let scope = ErrorScope::push(device);
        let new_texture = || {
            let t = make_texture(
                device,
                "obscura resolved depth",
                size,
                1,
                1,
                crate::passes::constants::RESOLVED_DEPTH_FORMAT,
            );
            let v = t.create_view(&Default::default());
            (t, v)
        };
        match slot.as_mut() {
            None => {
                let compiled = compile();
                let (texture, view) = new_texture();
                *slot = Some(Resolve {
                    compiled,
                    texture,
                    view,
                    binding: None,
                });
                created.textures += 1;
                created.texture_views += 1;
            }
            Some(r) if !fits(r) => {
                (r.texture, r.view) = new_texture();
                r.binding = None;
                created.textures += 1;
                created.texture_views += 1;
            }
            Some(_) => {}
        }
        let r = slot.as_mut().expect("created above");
        let bg = bind_group(device, &r.compiled, uniforms, &[(1, depth), (2, &r.view)]);
        r.binding = Some((depth.clone(), bg));
        created.bind_groups += 1;
        let result = scope.pop("creating obscura's MSAA depth resolve");
        if result.is_err() {
            *slot = None;
        }
        result
    }
}

/// The prepare pass's bind group, kept while the caller passes the same views.
#[derive(Debug)]
pub(crate) struct PrepareBinding {
    pub depth: wgpu::TextureView,
    pub normals: Option<wgpu::TextureView>,
    pub second: Option<wgpu::TextureView>,
    /// Bound to the plane-fitting prepare pipeline.
    pub fit: bool,
    pub bind_group: wgpu::BindGroup,
}

/// What the prepare pass reads this frame: the depth (the caller's, or the MSAA
/// resolve's), the normals bound (the caller's, or a placeholder) with the caller's if any,
/// the caller's second depth layer if any, and whether the plane-fitting pipeline runs.
#[derive(Debug)]
pub(crate) struct PrepareInputs<'a> {
    pub depth: wgpu::TextureView,
    pub normals: (&'a wgpu::TextureView, Option<&'a wgpu::TextureView>),
    pub second: Option<&'a wgpu::TextureView>,
    pub fit: bool,
}

/// Textures and bind groups that depend on the viewport size.
#[derive(Debug)]
pub(crate) struct SizedResources {
    /// The processed rectangle's size: the viewport grown by the guard band.
    pub size: [u32; 2],
    /// The output's size: the viewport's.
    pub output_size: [u32; 2],
    /// Every texture of the plan, by name.
    pub textures: Vec<(Res, wgpu::Texture, wgpu::TextureView)>,
    /// Workgroups of the prepare pass (over pixels, or over layer texels when it splits).
    pub prepare_dispatch: Dispatch,
    /// Bind groups of every pass after prepare, in order: (compiled index, bind group on
    /// even and odd frames, workgroups). The pass that writes the output has none here
    /// (see `output_binding`).
    pub later: Vec<(usize, Option<[wgpu::BindGroup; 2]>, Dispatch)>,
    /// The pass writing the output: (index in `later`, index in the plan's steps).
    pub output_step: (usize, usize),
    /// The prepare bind group of the last frame's input views.
    pub prepare_binding: Option<PrepareBinding>,
    /// The output pass's bind groups (even, odd frames) and the output view they bind (the
    /// caller's, or `own_output`'s), kept while the caller passes the same view.
    pub output_binding: Option<(wgpu::TextureView, [wgpu::BindGroup; 2])>,
    /// The library's own output, created on the first frame without a caller output.
    pub own_output: Option<(wgpu::Texture, wgpu::TextureView)>,
}

impl SizedResources {
    pub fn view(&self, r: Res) -> Option<&wgpu::TextureView> {
        if r == Res::Output {
            return self.own_output.as_ref().map(|o| &o.1);
        }
        self.textures.iter().find(|t| t.0 == r).map(|t| &t.2)
    }

    pub fn texture(&self, r: Res) -> Option<&wgpu::Texture> {
        if r == Res::Output {
            return self.own_output.as_ref().map(|o| &o.0);
        }
        self.textures.iter().find(|t| t.0 == r).map(|t| &t.1)
    }

    /// Creates the plan's textures for `size` and every step's bind groups but the
    /// output's, inside error scopes.
    pub fn new(
        device: &wgpu::Device,
        plan: &Plan,
        shared: Shared<'_>,
        (size, output_size): ([u32; 2], [u32; 2]),
        created: &mut ResourceCount,
    ) -> Result<Self> {
        let scope = ErrorScope::push(device);
        let textures: Vec<(Res, wgpu::Texture, wgpu::TextureView)> = plan
            .textures()
            .into_iter()
            .filter_map(|r| plan.spec(r, size))
            .map(|s| {
                let t = make_texture(device, s.label, s.size, s.layers, s.mips, s.format);
                let v = if s.layers > 1 {
                    array_view(&t)
                } else {
                    t.create_view(&Default::default())
                };
                (s.res, t, v)
            })
            .collect();
        let find = |r: Res| textures.iter().find(|t| t.0 == r);
        let mip_views = std::cell::Cell::new(0);
        let placeholders = std::cell::Cell::new(0);
        // Mip m of the pyramid (or of the moments pyramid, same size).
        let mip_view = |r: Res, m: u32| {
            mip_views.set(mip_views.get() + 1);
            find(r).map(|t| {
                t.1.create_view(&wgpu::TextureViewDescriptor {
                    base_mip_level: m,
                    mip_level_count: Some(1),
                    ..Default::default()
                })
            })
        };
        let pyramid = find(Res::Pyramid).or(find(Res::Moments));
        let pyramid_mips = pyramid.map_or(0, |t| t.1.mip_level_count());
        let pyramid_base = pyramid.map_or((1, 1), |t| (t.1.width(), t.1.height()));
        let workgroups = |w: u32, h: u32| {
            let (x, y) = crate::passes::shader::dispatch_size([w, h]);
            Dispatch::Fixed([x, y, 1])
        };
        let mut later = Vec::new();
        let mut output_step = (0, 0);
        let mut bind_groups = 0;
        for (si, st) in plan.steps.iter().enumerate() {
            let i = shared.compiled_index(st.pass);
            let c = &shared.compiled[i];
            let buffer = shared.buffer(st.frame);
            if st.grid == Grid::PyramidMips {
                // Groups of 1 or PYRAMID_LEVELS_PER_PASS mips, each read from the mip above
                // the group; outputs past the last mip are 1×1 placeholders (kept alive by
                // the bind group).
                let per = if st.pass == Pass::PyramidLevels {
                    PYRAMID_LEVELS_PER_PASS
                } else {
                    1
                };
                let chain = if matches!(st.pass, Pass::Moments { .. }) {
                    Res::Moments
                } else {
                    Res::Pyramid
                };
                for m0 in (1..pyramid_mips).step_by(per as usize) {
                    let Some(from) = mip_view(chain, m0 - 1) else {
                        continue;
                    };
                    let outs: Vec<wgpu::TextureView> = (m0..m0 + per)
                        .filter_map(|m| {
                            if m < pyramid_mips {
                                return mip_view(chain, m);
                            }
                            placeholders.set(placeholders.get() + 1);
                            let t = make_texture(
                                device,
                                "obscura pyramid placeholder",
                                (1, 1),
                                1,
                                1,
                                PYRAMID_FORMAT,
                            );
                            Some(t.create_view(&Default::default()))
                        })
                        .collect();
                    let mut views = vec![(1, &from)];
                    views.extend(outs.iter().zip(2..).map(|(v, b)| (b, v)));
                    let bg = bind_group(device, c, buffer, &views);
                    bind_groups += 1;
                    let d = (1.max(pyramid_base.0 >> m0), 1.max(pyramid_base.1 >> m0));
                    later.push((i, Some([bg.clone(), bg]), workgroups(d.0, d.1)));
                }
                continue;
            }
            if st.views.iter().any(|v| v.1 == Res::Output) {
                output_step = (later.len(), si);
                later.push((i, None, plan.dispatch(st.grid, size)));
                continue;
            }
            let mips: Vec<(u32, wgpu::TextureView)> = st
                .views
                .iter()
                .filter_map(|&(b, r)| match r {
                    Res::PyramidMip(m) => mip_view(Res::Pyramid, m).map(|v| (b, v)),
                    Res::MomentsMip(m) => mip_view(Res::Moments, m).map(|v| (b, v)),
                    _ => None,
                })
                .collect();
            let parity_group = |parity: u32| {
                let views: Vec<(u32, &wgpu::TextureView)> = st
                    .views
                    .iter()
                    .filter_map(|&(b, r)| match r {
                        Res::PyramidMip(_) | Res::MomentsMip(_) => None,
                        r => find(r.at_parity(parity)).map(|t| (b, &t.2)),
                    })
                    .chain(mips.iter().map(|(b, v)| (*b, v)))
                    .collect();
                bind_group(device, c, buffer, &views)
            };
            let even = parity_group(0);
            let odd = if st.views.iter().any(|v| v.1.at_parity(0) != v.1) {
                bind_groups += 1;
                parity_group(1)
            } else {
                even.clone()
            };
            bind_groups += 1;
            later.push((i, Some([even, odd]), plan.dispatch(st.grid, size)));
        }
        created.textures += textures.len() as u32 + placeholders.get();
        created.texture_views += textures.len() as u32 + mip_views.get() + placeholders.get();
        created.bind_groups += bind_groups;
        let sized = SizedResources {
            size,
            output_size,
            textures,
            prepare_dispatch: plan.prepare_dispatch(size),
            later,
            output_step,
            prepare_binding: None,
            output_binding: None,
            own_output: None,
        };
        scope.pop(&format!(
            "creating obscura's {}x{} textures",
            size[0], size[1]
        ))?;
        Ok(sized)
    }

    /// The prepare pass's bind group for this frame's input views: last frame's when the
    /// caller passes the same views (an engine's usual case), else a new one.
    pub fn bind_prepare(
        &mut self,
        device: &wgpu::Device,
        plan: &Plan,
        (prepare, uniforms): (&Compiled, &wgpu::Buffer),
        inputs: PrepareInputs<'_>,
        created: &mut ResourceCount,
    ) -> Result<wgpu::BindGroup> {
        let PrepareInputs {
            depth,
            normals,
            second,
            fit,
        } = inputs;
        let cached = self.prepare_binding.as_ref().is_some_and(|b| {
            b.depth == depth
                && b.normals.as_ref() == normals.1
                && b.second.as_ref() == second
                && b.fit == fit
        });
        if !cached {
            let mut views = vec![(1, &depth), (2, normals.0)];
            views.extend(second.map(|s| (5, s)));
            for (b, r) in super::plan::prepare_targets(plan.prepare_store, plan.second_layer()) {
                let Some(target) = self.view(r) else {
                    return Err(Error::Gpu("no prepare target".into()));
                };
                views.push((b, target));
            }
            let bg = bind_group(device, prepare, uniforms, &views);
            created.bind_groups += 1;
            self.prepare_binding = Some(PrepareBinding {
                depth,
                normals: normals.1.cloned(),
                second: second.cloned(),
                fit,
                bind_group: bg,
            });
        }
        self.prepare_binding
            .as_ref()
            .map(|b| b.bind_group.clone())
            .ok_or_else(|| Error::Gpu("prepare bind group missing".into()))
    }

    /// The output pass's bind groups (even and odd frames) for the caller's output view,
    /// or for the library's own texture (created on the first frame that needs it). With a
    /// guard band the output pass stores the viewport alone (passes/output.wgsl).
    pub fn bind_output(
        &mut self,
        device: &wgpu::Device,
        plan: &Plan,
        shared: Shared<'_>,
        output: Option<&wgpu::TextureView>,
        created: &mut ResourceCount,
    ) -> Result<[wgpu::BindGroup; 2]> {
        if output.is_none() && self.own_output.is_none() {
            let scope = ErrorScope::push(device);
            let (w, h) = (self.output_size[0], self.output_size[1]);
            let t = make_texture(device, "obscura ao", (w, h), 1, 1, AO_FORMAT);
            let v = t.create_view(&Default::default());
            scope.pop("creating obscura's output texture")?;
            created.textures += 1;
            created.texture_views += 1;
            self.own_output = Some((t, v));
        }
        let out_view = match (output, &self.own_output) {
            (Some(v), _) | (None, Some((_, v))) => v.clone(),
            (None, None) => return Err(Error::Gpu("output texture missing".into())),
        };
        if self.output_binding.as_ref().map(|b| &b.0) != Some(&out_view) {
            let st = &plan.steps[self.output_step.1];
            let c = &shared.compiled[self.later[self.output_step.0].0];
            let mut groups = Vec::with_capacity(2);
            for parity in 0..2 {
                let mut views = Vec::with_capacity(st.views.len());
                for &(b, r) in &st.views {
                    let v = if r == Res::Output {
                        &out_view
                    } else {
                        self.view(r.at_parity(parity))
                            .ok_or_else(|| Error::Gpu(format!("texture {r:?} missing")))?
                    };
                    views.push((b, v));
                }
                groups.push(bind_group(device, c, shared.buffer(st.frame), &views));
                created.bind_groups += 1;
            }
            let odd = groups.pop().expect("two bind groups");
            let even = groups.pop().expect("two bind groups");
            self.output_binding = Some((out_view, [even, odd]));
        }
        let groups = self
            .output_binding
            .as_ref()
            .map(|b| b.1.clone())
            .ok_or_else(|| Error::Gpu("output bind group missing".into()));
        groups
    }
}
