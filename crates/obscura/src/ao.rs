//! [`Ao`]: the AO pipeline object. Creation compiles the passes for an [`AoOptions`];
//! each frame, [`Ao::record`] validates the inputs, writes one small uniform buffer and
//! records the passes into the caller's command encoder:
//!
//! ```text
//! randomized:           prepare ─▶ hbao (full resolution, 4×4 per-pixel patterns)
//! deinterleaved, fused: prepare_split (writes N×N layers) ─▶ hbao_layers_merge (writes full res)
//! deinterleaved:        prepare ─▶ deinterleave ─▶ hbao_layers ─▶ interleave
//! half / quarter:       prepare_down (half-res vec4(d, n) + full-res linear depth)
//!                       ─▶ [downsample to quarter] ─▶ AO at working resolution
//!                       ─▶ [blur | box/tent] ─▶ upsample (full res)
//! scaled (any scale):   prepare ─▶ rescale ─▶ AO on the frame's working grid ─▶ [temporal]
//!                       ─▶ [denoise] ─▶ upsample_scaled (full res)
//! ```
//!
//! Estimators that read the depth pyramid (SAO), and the classified upsampler, get its levels
//! built between prepare and the AO pass: `pyramid_from_full` (or `_from_layers`), then one
//! `pyramid_levels` pass per four further levels on GPUs, one `pyramid` pass per level on CPU
//! adapters ([`crate::PyramidBuild`]). VO's area integral gets a moments pyramid of the same
//! size the same way, one `moments` pass per level.

use crate::layout::layer_size;
use crate::shader::{
    dispatch_size, DepthBinding, Pass, PrepareStore, PyramidSource, AO_FORMAT, BENT_FORMAT,
    HISTORY_FORMAT, LINEAR_DEPTH_FORMAT, LIT_FORMAT, LIT_PACKED_FORMAT, MOMENTS_FORMAT,
    PREPARED_FORMAT, PYRAMID_FORMAT, PYRAMID_LEVELS_PER_PASS, RESOLVED_DEPTH_FORMAT,
};
use crate::uniforms::FrameUniforms;
use crate::{
    AoOptions, AoParams, CameraMotion, Denoise, DepthConvention, Error, NormalEncoding, Projection,
    Resolution, Result, Upsampler, Viewport,
};

/// What the caller hands over each frame.
#[derive(Clone, Copy, Debug)]
pub struct AoInput<'a> {
    /// Depth, as a depth format (Depth32Float, Depth24Plus, Depth16Unorm; depth-only view
    /// for combined depth-stencil formats) or a float format (R32Float, R16Float), with
    /// `TEXTURE_BINDING` usage. A multisampled depth-format texture (MSAA) is resolved
    /// first, one depth per pixel (shaders/resolve_depth.wgsl: the pixel-centre depth
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
    /// Where to write the AO: a view of a whole `R32Float` 2D texture (one mip, one layer)
    /// of the viewport's size with `STORAGE_BINDING` usage; 1 = unoccluded. `None`: a
    /// texture the library owns ([`Ao::output`]).
    pub output: Option<&'a wgpu::TextureView>,
}

/// A texture the passes read or write. Sizes: `full` = the viewport, `work` = the AO's
/// working resolution (`ceil(full / resolution factor)`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Res {
    /// `prepared`: full size, PREPARED_FORMAT.
    Prepared,
    /// `linear depth`: full size, LINEAR_DEPTH_FORMAT (written by [`PrepareStore::Down`]).
    LinearDepth,
    /// `prepared_layers`: work layer size × N² layers, PREPARED_FORMAT (deinterleaved).
    PreparedLayers,
    /// `prepared` downsampled k ≥ 1 times by the depth rule: `ceil(full / 2^k)`.
    Level(u32),
    /// `prepared` at the frame's scale ([`crate::Resolution::Scaled`]): created at full
    /// size, the working grid `ceil(full × scale)` used.
    Scaled,
    /// `pyramid`: `max(1, full >> 1)` with every mip, PYRAMID_FORMAT; all mips.
    Pyramid,
    /// One mip of the pyramid.
    PyramidMip(u32),
    /// `moments`: the pyramid's size and mips, MOMENTS_FORMAT (VO's area integral).
    Moments,
    /// One mip of the moments pyramid.
    MomentsMip(u32),
    /// `ao_work`: work size, AO_FORMAT (when post-processing follows the AO pass).
    AoWork,
    /// `ao_tmp`: work size, AO_FORMAT (between the temporal pass and the denoiser).
    AoTmp,
    /// `ao_layers`: work layer size × N², AO_FORMAT (unfused deinterleaved).
    AoLayers,
    /// `ao_half`: `ceil(work / 2)`, AO_FORMAT (box or tent denoise).
    AoHalf,
    /// `output`: full size, AO_FORMAT.
    Output,
    /// The temporal history read this frame (last frame's): work size, HISTORY_FORMAT;
    /// one of the two [`Res::History`] textures, alternating by frame.
    HistoryPrev,
    /// The temporal history written this frame: the other [`Res::History`] texture.
    HistoryNext,
    /// History texture 0 or 1 (what `HistoryPrev`/`HistoryNext` resolve to).
    History(u32),
    /// `bent normals`: work size, BENT_FORMAT (the result, [`Ao::bent_normals`]).
    Bent,
    /// `bent normals raw`: work size, BENT_FORMAT (the AO pass's, when a temporal pass or
    /// the denoiser follows).
    BentRaw,
    /// `bent normals accumulated`: work size, BENT_FORMAT (between the temporal pass and
    /// the denoiser).
    BentTmp,
    /// The bent-normal history read this frame, as [`Res::HistoryPrev`].
    BentHistoryPrev,
    /// The bent-normal history written this frame, as [`Res::HistoryNext`].
    BentHistoryNext,
    /// Bent-normal history texture 0 or 1: work size, BENT_FORMAT.
    BentHistory(u32),
}

impl Res {
    /// The texture this resource is on frame parity `parity` (history alternates).
    fn at_parity(self, parity: u32) -> Res {
        match self {
            Res::HistoryPrev => Res::History(parity),
            Res::HistoryNext => Res::History(1 - parity),
            Res::BentHistoryPrev => Res::BentHistory(parity),
            Res::BentHistoryNext => Res::BentHistory(1 - parity),
            r => r,
        }
    }
}

/// Which uniform buffer a pass binds: the full-resolution frame or the working one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FrameAt {
    Full,
    Work,
}

/// The invocation grid of a pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Grid {
    /// One invocation per pixel of a prepared level (0 = full resolution).
    Level(u32),
    /// One invocation per pixel of this frame's working grid ([`crate::Resolution::Scaled`]).
    Work,
    /// Work layer texels × N² layers (of this frame's working grid).
    Layers,
    /// One dispatch per pyramid (or moments) mip after the first, or per four of them (each
    /// reads the mip above).
    PyramidMips,
    /// Pyramid mip 0.
    PyramidBase,
}

/// One pass of the plan: what it binds (binding → texture), with which frame, over which grid.
#[derive(Clone, Debug)]
struct Step {
    pass: Pass,
    views: Vec<(u32, Res)>,
    frame: FrameAt,
    grid: Grid,
}

/// A pass's workgroup counts: fixed by the frame size, or taken from each frame's working
/// grid (which [`crate::Resolution::Scaled`] changes every frame).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Dispatch {
    Fixed([u32; 3]),
    Work,
    WorkLayers,
}

impl Dispatch {
    /// The workgroup counts for a working grid of `work` pixels and an `n` × `n` split.
    fn at(self, work: [u32; 2], n: u32) -> [u32; 3] {
        let (grid, z) = match self {
            Dispatch::Fixed(d) => return d,
            Dispatch::Work => (work, 1),
            Dispatch::WorkLayers => {
                let l = layer_size(work[0], work[1], n);
                ([l.0, l.1], n * n)
            }
        };
        let (x, y) = dispatch_size(grid);
        [x, y, z]
    }
}

/// What the prepare pass stores, and the textures it writes, by binding.
fn prepare_targets(store: PrepareStore) -> Vec<(u32, Res)> {
    match store {
        PrepareStore::Full => vec![(3, Res::Prepared)],
        PrepareStore::Layers => vec![(3, Res::PreparedLayers)],
        PrepareStore::Down { normals: true, .. } => vec![(3, Res::Level(1)), (4, Res::Prepared)],
        PrepareStore::Down { normals: false, .. } => {
            vec![(3, Res::Level(1)), (4, Res::LinearDepth)]
        }
    }
}

/// How the prepare pass stores for `options`, and the passes after it, in order;
/// `pyramid_levels`: levels per pass of the pyramid after its first (1 or 4).
fn plan_steps(o: &AoOptions, pyramid_levels: u32) -> (PrepareStore, Vec<Step>) {
    if o.resolution == Resolution::Scaled {
        return (PrepareStore::Full, plan_scaled_steps(o));
    }
    let n = o.mode.split();
    let work_level = o.resolution.factor().ilog2();
    let up_level = o.upsample_factor().ilog2();
    let direct = o.direct();
    let upsample = up_level > 0;
    // The prepare pass writes the layers itself at full resolution; the denoiser and the
    // temporal pass then read the prepared values from the layers.
    let fused_prepare = n > 1 && o.fused && work_level == 0 && !o.denoise.downsamples();
    // Below full resolution the prepare pass writes the first level itself, and at full
    // resolution only what the upsampler and the pyramid read (linear depth, plus normals
    // for the bilateral upsampler), unless unfused.
    let fused_down = o.fused && work_level >= 1;
    let normals = o.upsample == Upsampler::Bilateral;
    let prepare_store = if fused_prepare {
        PrepareStore::Layers
    } else if fused_down {
        PrepareStore::Down {
            rule: o.downsample,
            normals,
        }
    } else {
        PrepareStore::Full
    };
    // The upsampler's and the pyramid's full-resolution input (they read `.x` as depth).
    let full_depth = if fused_down && !normals {
        Res::LinearDepth
    } else {
        Res::Prepared
    };
    let level = |k: u32| if k == 0 { Res::Prepared } else { Res::Level(k) };
    let work_prepared = level(work_level);
    let step = |pass, views: Vec<(u32, Res)>, frame, grid| Step {
        pass,
        views,
        frame,
        grid,
    };
    let mut steps = Vec::new();
    let classified = upsample && o.upsample == Upsampler::Classified;
    // Where the first level of the depth pyramid and of the moments pyramid reads depth.
    let (source, from) = if fused_prepare {
        (PyramidSource::Layers, Res::PreparedLayers)
    } else {
        (PyramidSource::Full, full_depth)
    };
    if o.estimator.uses_pyramid() || classified {
        steps.push(step(
            Pass::Pyramid { source },
            vec![(1, from), (2, Res::PyramidMip(0))],
            FrameAt::Full,
            Grid::PyramidBase,
        ));
        let mips = if pyramid_levels == PYRAMID_LEVELS_PER_PASS {
            Pass::PyramidLevels
        } else {
            Pass::Pyramid {
                source: PyramidSource::Mip,
            }
        };
        steps.push(step(mips, vec![], FrameAt::Full, Grid::PyramidMips));
    }
    if o.estimator.uses_moments() {
        steps.push(step(
            Pass::Moments { source },
            vec![(1, from), (2, Res::MomentsMip(0))],
            FrameAt::Full,
            Grid::PyramidBase,
        ));
        let mips = Pass::Moments {
            source: PyramidSource::Mip,
        };
        steps.push(step(mips, vec![], FrameAt::Full, Grid::PyramidMips));
    }
    let first_downsample = if fused_down { 2 } else { 1 };
    for k in first_downsample..=work_level.max(up_level) {
        steps.push(step(
            Pass::Downsample {
                rule: o.downsample,
                level: k,
            },
            vec![(1, level(k - 1)), (2, Res::Level(k))],
            FrameAt::Full,
            Grid::Level(k),
        ));
    }
    let ao_target = if direct { Res::Output } else { Res::AoWork };
    // Bent normals: written by the AO pass, then through the temporal pass, the spatial
    // denoiser and the upsampler where they run; each of these writes the other work-size
    // texture (BentRaw, BentTmp), the last one Bent.
    let bent = o.bent_normals;
    let filter_bent = bent && o.denoise == Denoise::Spatial;
    let accumulate_bent = bent && o.history > 0;
    let upsample_bent = bent && bent_upsampled(o);
    let bent_other = |r: Res| {
        if r == Res::BentRaw {
            Res::BentTmp
        } else {
            Res::BentRaw
        }
    };
    let bent_next = |r: Res, more: bool| if more { bent_other(r) } else { Res::Bent };
    let mut bent_current = bent_next(
        Res::BentTmp,
        accumulate_bent || filter_bent || upsample_bent,
    );
    let pyramid = |mut v: Vec<(u32, Res)>| {
        if o.estimator.uses_pyramid() {
            v.push((3, Res::Pyramid));
        }
        if o.estimator.uses_moments() {
            v.push((3, Res::Moments));
        }
        if bent {
            v.push((4, bent_current));
        }
        v
    };
    let e = o.estimator;
    let layers = |merge| Pass::AoLayered {
        merge,
        estimator: e,
        bent,
    };
    match (n > 1, fused_prepare, direct) {
        (false, ..) => steps.push(step(
            Pass::AoFull { estimator: e, bent },
            pyramid(vec![(1, work_prepared), (2, ao_target)]),
            FrameAt::Work,
            Grid::Level(work_level),
        )),
        (true, true, _) => steps.push(step(
            layers(true),
            pyramid(vec![(1, Res::PreparedLayers), (2, ao_target)]),
            FrameAt::Work,
            Grid::Layers,
        )),
        (true, false, unfused_direct) => {
            steps.push(step(
                Pass::Deinterleave,
                vec![(1, work_prepared), (3, Res::PreparedLayers)],
                FrameAt::Work,
                Grid::Layers,
            ));
            // Below full resolution (or before denoising) the merge is always fused; the
            // separate interleave pass is kept for the direct unfused mode, to measure it.
            if unfused_direct {
                steps.push(step(
                    layers(false),
                    pyramid(vec![(1, Res::PreparedLayers), (2, Res::AoLayers)]),
                    FrameAt::Work,
                    Grid::Layers,
                ));
                steps.push(step(
                    Pass::Interleave,
                    vec![(1, Res::AoLayers), (2, Res::Output)],
                    FrameAt::Work,
                    Grid::Level(0),
                ));
            } else {
                steps.push(step(
                    layers(true),
                    pyramid(vec![(1, Res::PreparedLayers), (2, Res::AoWork)]),
                    FrameAt::Work,
                    Grid::Layers,
                ));
            }
        }
    }
    // After the AO pass: [temporal] → [denoise] → [upsample]; `current` is the texture
    // holding the AO so far, the last pass before the upsampler (or none) writes Output.
    let (src_layers, src) = if fused_prepare {
        (true, Res::PreparedLayers)
    } else {
        (false, work_prepared)
    };
    let mut current = Res::AoWork;
    let other = |r: Res| {
        if r == Res::AoWork {
            Res::AoTmp
        } else {
            Res::AoWork
        }
    };
    if o.history > 0 {
        let more = o.denoise != Denoise::None || upsample;
        let next = if more { other(current) } else { Res::Output };
        let mut views = vec![
            (1, src),
            (2, current),
            (3, Res::HistoryPrev),
            (4, Res::HistoryNext),
            (5, next),
        ];
        if accumulate_bent {
            let next = bent_next(bent_current, filter_bent || upsample_bent);
            views.extend([
                (6, bent_current),
                (7, Res::BentHistoryPrev),
                (8, Res::BentHistoryNext),
                (9, next),
            ]);
            bent_current = next;
        }
        steps.push(step(
            Pass::Temporal {
                layers: src_layers,
                bent: accumulate_bent,
            },
            views,
            FrameAt::Work,
            Grid::Level(work_level),
        ));
        current = next;
    }
    match o.denoise {
        Denoise::None => {}
        Denoise::Spatial => {
            let next = if upsample {
                other(current)
            } else {
                Res::Output
            };
            let mut views = vec![(1, src), (2, current), (3, next)];
            if filter_bent {
                let next = bent_next(bent_current, upsample_bent);
                views.extend([(4, bent_current), (5, next)]);
                bent_current = next;
            }
            steps.push(step(
                Pass::Denoise {
                    layers: src_layers,
                    bent: filter_bent,
                },
                views,
                FrameAt::Work,
                Grid::Level(work_level),
            ));
            current = next;
        }
        Denoise::Box | Denoise::Tent => steps.push(step(
            Pass::AoDownsample {
                tent: o.denoise == Denoise::Tent,
            },
            vec![(1, current), (2, Res::AoHalf)],
            FrameAt::Full,
            Grid::Level(work_level + 1),
        )),
    }
    if upsample {
        let from = if o.denoise.downsamples() {
            Res::AoHalf
        } else {
            current
        };
        let mut views = vec![
            (1, full_depth),
            (2, from),
            (3, level(up_level)),
            (4, Res::Output),
        ];
        if classified {
            views.push((5, Res::Pyramid));
        }
        if upsample_bent {
            views.extend([(6, bent_current), (7, Res::Bent)]);
        }
        // One invocation per texel of the AO it reads (each writes its block of pixels).
        steps.push(step(
            Pass::Upsample {
                upsampler: o.upsample,
                bent: upsample_bent,
                full_normals: full_depth == Res::Prepared,
            },
            views,
            FrameAt::Full,
            Grid::Level(up_level),
        ));
    }
    (prepare_store, steps)
}

/// The passes after prepare for [`Resolution::Scaled`]: rescale → AO on the working grid
/// (randomized, or deinterleaved by the unfused split) → [temporal accumulation on the
/// working grid, reprojecting into last frame's grid, whatever its scale] → [spatial
/// denoiser] → bilateral upsampling at the frame's scale. Temporal accumulation at full
/// resolution after the upsampler (where engines put TAA) cost 13 ms of a 31 ms frame at
/// scale 1/4 on lavapipe at 640×400 (BENCHMARKS.md), the floor no scale could go below.
fn plan_scaled_steps(o: &AoOptions) -> Vec<Step> {
    let step = |pass, views: Vec<(u32, Res)>, frame, grid| Step {
        pass,
        views,
        frame,
        grid,
    };
    let estimator = o.estimator;
    let mut steps = vec![step(
        Pass::Rescale,
        vec![(1, Res::Prepared), (2, Res::Scaled)],
        FrameAt::Work,
        Grid::Work,
    )];
    if o.mode.split() > 1 {
        steps.push(step(
            Pass::Deinterleave,
            vec![(1, Res::Scaled), (3, Res::PreparedLayers)],
            FrameAt::Work,
            Grid::Layers,
        ));
        steps.push(step(
            Pass::AoLayered {
                merge: true,
                estimator,
                bent: false,
            },
            vec![(1, Res::PreparedLayers), (2, Res::AoWork)],
            FrameAt::Work,
            Grid::Layers,
        ));
    } else {
        steps.push(step(
            Pass::AoFull {
                estimator,
                bent: false,
            },
            vec![(1, Res::Scaled), (2, Res::AoWork)],
            FrameAt::Work,
            Grid::Work,
        ));
    }
    // After the AO pass: [temporal] → [denoise], alternating the two working textures.
    let mut current = Res::AoWork;
    let other = |r: Res| {
        if r == Res::AoWork {
            Res::AoTmp
        } else {
            Res::AoWork
        }
    };
    if o.history > 0 {
        steps.push(step(
            Pass::Temporal {
                layers: false,
                bent: false,
            },
            vec![
                (1, Res::Scaled),
                (2, current),
                (3, Res::HistoryPrev),
                (4, Res::HistoryNext),
                (5, other(current)),
            ],
            FrameAt::Work,
            Grid::Work,
        ));
        current = other(current);
    }
    if o.denoise == Denoise::Spatial {
        steps.push(step(
            Pass::Denoise {
                layers: false,
                bent: false,
            },
            vec![(1, Res::Scaled), (2, current), (3, other(current))],
            FrameAt::Work,
            Grid::Work,
        ));
        current = other(current);
    }
    steps.push(step(
        Pass::UpsampleScaled,
        vec![
            (1, Res::Prepared),
            (2, current),
            (3, Res::Scaled),
            (4, Res::Output),
        ],
        FrameAt::Full,
        Grid::Level(0),
    ));
    steps
}

/// Whether the bent normals are upsampled to full resolution (below full resolution, unless
/// the box or tent filter downsampled the AO further: they stay at the working resolution).
fn bent_upsampled(o: &AoOptions) -> bool {
    o.resolution.factor() > 1 && !o.denoise.downsamples()
}

/// GPU objects an [`Ao`] has created since [`Ao::new`], by kind (see
/// [`Ao::resource_creations`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ResourceCount {
    pub buffers: u32,
    pub textures: u32,
    pub texture_views: u32,
    pub bind_groups: u32,
}

/// The MSAA depth resolve ([`Pass::ResolveDepth`]), created on the first frame whose depth
/// input is multisampled.
#[derive(Debug)]
struct Resolve {
    compiled: Compiled,
    /// One raw depth per pixel, at the depth texture's size (the prepare pass reads it at
    /// the viewport's texels, as it reads the caller's depth).
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    /// The bind group of the last frame's depth view, kept while the caller passes it.
    binding: Option<(wgpu::TextureView, wgpu::BindGroup)>,
}

/// The prepare pass's bind group, kept while the caller passes the same views.
#[derive(Debug)]
struct PrepareBinding {
    depth: wgpu::TextureView,
    normals: Option<wgpu::TextureView>,
    /// Bound to the plane-fitting prepare pipeline.
    fit: bool,
    bind_group: wgpu::BindGroup,
}

/// Textures and bind groups that depend on the viewport size.
#[derive(Debug)]
struct SizedResources {
    size: [u32; 2],
    /// Every texture of the plan, by name.
    textures: Vec<(Res, wgpu::Texture, wgpu::TextureView)>,
    /// Workgroups of the prepare pass (over pixels, or over layer texels when it splits).
    prepare_dispatch: Dispatch,
    /// Bind groups of every pass after prepare, in order: (compiled index, bind group on
    /// even and odd frames (they differ only for passes that touch the history),
    /// workgroups). The pass that writes the output has none here (see `output_binding`).
    later: Vec<(usize, Option<[wgpu::BindGroup; 2]>, Dispatch)>,
    /// The pass writing the output: (index in `later`, index in the plan's steps).
    output_step: (usize, usize),
    /// The prepare bind group of the last frame's input views.
    prepare_binding: Option<PrepareBinding>,
    /// The output pass's bind groups (even, odd frames) and the output view they bind (the
    /// caller's, or `own_output`'s), kept while the caller passes the same view.
    output_binding: Option<(wgpu::TextureView, [wgpu::BindGroup; 2])>,
    /// The library's own output, created on the first frame without a caller output.
    own_output: Option<(wgpu::Texture, wgpu::TextureView)>,
}

impl SizedResources {
    fn view(&self, r: Res) -> Option<&wgpu::TextureView> {
        if r == Res::Output {
            return self.own_output.as_ref().map(|o| &o.1);
        }
        self.textures.iter().find(|t| t.0 == r).map(|t| &t.2)
    }

    fn texture(&self, r: Res) -> Option<&wgpu::Texture> {
        if r == Res::Output {
            return self.own_output.as_ref().map(|o| &o.0);
        }
        self.textures.iter().find(|t| t.0 == r).map(|t| &t.1)
    }
}

/// How [`Ao::run_timed`] measures each pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Timing {
    /// Wall clock around submit + wait of each pass on its own: the only honest clock on
    /// lavapipe, whose timestamps do not bracket dispatches.
    WallClock,
    /// GPU timestamp queries around each pass, all passes in one submission (hardware
    /// adapters with `TIMESTAMP_QUERY`).
    Timestamps,
}

impl Timing {
    /// Timestamps where the context says they bracket dispatches, else the wall clock.
    pub fn best_for(ctx: &crate::GpuContext) -> Self {
        if ctx.has_timestamps() {
            Timing::Timestamps
        } else {
            Timing::WallClock
        }
    }
}

/// A compiled pass: pipeline and the layout of its bind group.
#[derive(Debug)]
pub(crate) struct Compiled {
    pub(crate) pass: Pass,
    pub(crate) pipeline: wgpu::ComputePipeline,
    pub(crate) layout: wgpu::BindGroupLayout,
}

/// The AO pipeline. Create once; call [`Ao::record`] per frame.
#[derive(Debug)]
pub struct Ao {
    options: AoOptions,
    /// Prepare for [depth-format, float] inputs × [given, reconstructed] normals.
    prepare: [[Compiled; 2]; 2],
    /// Prepare with depth and normals from plane fits, for [depth-format, float] inputs:
    /// compiled on the first frame with a depth noise model ([`AoParams::depth_noise`]).
    prepare_fit: [Option<Compiled>; 2],
    /// The pipelines of the passes after prepare (each compiled once).
    later: Vec<Compiled>,
    /// What prepare writes, and the passes after it in execution order.
    prepare_store: PrepareStore,
    steps: Vec<Step>,
    /// Frame uniforms at full and at working resolution (the same when full).
    uniforms: wgpu::Buffer,
    work_uniforms: wgpu::Buffer,
    dummy_normals: wgpu::TextureView,
    max_dim: u32,
    sized: Option<SizedResources>,
    resolve: Option<Resolve>,
    created: ResourceCount,
    temporal: TemporalState,
}

/// What temporal accumulation remembers between frames.
#[derive(Debug, Default)]
struct TemporalState {
    /// Frames recorded so far (the sampling patterns rotate with it).
    frame: u32,
    /// Whether the history texture holds the previous frame at this size.
    valid: bool,
    /// Which history texture this frame reads (0 or 1).
    parity: u32,
    /// The previous frame's projection scale and kind.
    previous: Option<([f32; 2], u32)>,
    /// The previous frame's working grid (`size`, `inv_size`), which the history holds.
    grid: Option<([u32; 2], [f32; 2])>,
}

impl TemporalState {
    /// Points this frame's working uniforms at the grid the history holds (the last frame's,
    /// which [`Resolution::Scaled`] may have run at another scale) and remembers this one.
    fn set_grid(&mut self, work: &mut FrameUniforms) {
        if let (Some((size, inv_size)), true) = (self.grid, work.history != 0) {
            work.prev_size = size;
            work.prev_inv_size = inv_size;
        }
        self.grid = Some((work.size, work.inv_size));
    }
}

impl TemporalState {
    /// Fills this frame's temporal uniforms and rotated patterns, and advances to the next
    /// frame; returns the parity of this frame's bind groups. Without temporal
    /// accumulation nothing changes (parity 0, the patterns of frame 0).
    fn apply(&mut self, o: &AoOptions, motion: CameraMotion, f: &mut FrameUniforms) -> u32 {
        if o.history == 0 {
            return 0;
        }
        let parity = self.parity;
        let same_kind = self.previous.is_some_and(|p| p.1 == f.perspective);
        let valid = self.valid && same_kind && motion != CameraMotion::Cut;
        f.history = valid as u32;
        if let (Some((scale, _)), true) = (self.previous, valid) {
            f.prev_ndc_to_view = scale;
        }
        if let CameraMotion::Moved {
            previous_from_current,
        } = motion
        {
            f.prev_from_view = previous_from_current;
        }
        if o.jitter {
            f.patterns = crate::jitter::pattern_table_frame(
                crate::jitter::rotation_sector(o.estimator, o.directions),
                self.frame,
            );
        }
        self.frame = self.frame.wrapping_add(1);
        self.valid = true;
        self.parity = 1 - parity;
        self.previous = Some((f.ndc_to_view, f.perspective));
        parity
    }
}

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
pub(crate) fn lit_format(packed: bool) -> wgpu::TextureFormat {
    if packed {
        LIT_PACKED_FORMAT
    } else {
        LIT_FORMAT
    }
}

/// The bind group layout of `pass`: uniforms at 0, then its textures.
fn layout_entries(pass: Pass) -> Vec<wgpu::BindGroupLayoutEntry> {
    let dim = |layers: bool| if layers { D2_ARRAY } else { D2 };
    let rest = match pass {
        Pass::Prepare { depth, store, .. } => {
            let mut v = vec![
                texture_entry(
                    1,
                    match depth {
                        DepthBinding::Depth => wgpu::TextureSampleType::Depth,
                        DepthBinding::Float => UNFILTERED,
                    },
                    D2,
                ),
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
            v
        }
        Pass::AoFull { bent, .. } => {
            let mut v = vec![
                texture_entry(1, UNFILTERED, D2),
                storage_entry(2, AO_FORMAT, D2),
            ];
            if bent {
                v.push(storage_entry(4, BENT_FORMAT, D2));
            }
            v
        }
        Pass::AoLayered { merge, bent, .. } => {
            let mut v = vec![
                texture_entry(1, UNFILTERED, D2_ARRAY),
                storage_entry(2, AO_FORMAT, dim(!merge)),
            ];
            if bent {
                v.push(storage_entry(4, BENT_FORMAT, D2));
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
        Pass::Denoise { layers, bent } => {
            let mut v = vec![
                texture_entry(1, UNFILTERED, dim(layers)),
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
        Pass::Temporal { layers, bent } => {
            let mut v = vec![
                texture_entry(1, UNFILTERED, dim(layers)),
                texture_entry(2, UNFILTERED, D2),
                texture_entry(3, UNFILTERED, D2),
                storage_entry(4, HISTORY_FORMAT, D2),
                storage_entry(5, AO_FORMAT, D2),
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

fn compile(device: &wgpu::Device, pass: Pass, options: &AoOptions) -> Compiled {
    compile_with(device, pass, &pass.constants(options))
}

/// Compiles `pass` with its bind group layout and the override `constants`.
pub(crate) fn compile_with(
    device: &wgpu::Device,
    pass: Pass,
    constants: &[(&str, f64)],
) -> Compiled {
    let label = Some(pass.label());
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label,
        entries: &layout_entries(pass),
    });
    let module = crate::shader::create_module(device, label, pass.source());
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label,
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label,
        layout: Some(&pipeline_layout),
        module: &module,
        entry_point: Some("main"),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants,
            ..Default::default()
        },
        cache: None,
    });
    Compiled {
        pass,
        pipeline,
        layout,
    }
}

/// Binds the frame uniforms at 0 and `views` at the given binding numbers.
fn bind_group(
    device: &wgpu::Device,
    c: &Compiled,
    uniforms: &wgpu::Buffer,
    views: &[(u32, &wgpu::TextureView)],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = std::iter::once(wgpu::BindGroupEntry {
        binding: 0,
        resource: uniforms.as_entire_binding(),
    })
    .chain(views.iter().map(|&(binding, v)| wgpu::BindGroupEntry {
        binding,
        resource: wgpu::BindingResource::TextureView(v),
    }))
    .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(c.pass.label()),
        layout: &c.layout,
        entries: &entries,
    })
}

/// Out-of-memory and validation error scopes around resource creation on the caller's
/// device (never around per-frame recording), so failures come back as typed errors
/// instead of reaching the device's uncaptured-error handler.
pub(crate) struct ErrorScope {
    oom: wgpu::ErrorScopeGuard,
    validation: wgpu::ErrorScopeGuard,
}

impl ErrorScope {
    pub(crate) fn push(device: &wgpu::Device) -> Self {
        let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        Self { oom, validation }
    }

    pub(crate) fn pop(self, doing: &str) -> Result<()> {
        let v = pollster::block_on(self.validation.pop());
        let o = pollster::block_on(self.oom.pop());
        match o.or(v).map(Error::from) {
            None => Ok(()),
            Some(Error::OutOfMemory(e)) => Err(Error::OutOfMemory(format!("{doing}: {e}"))),
            Some(Error::Gpu(e)) => Err(Error::Gpu(format!("{doing}: {e}"))),
            Some(e) => Err(e),
        }
    }
}

/// How a depth input binds.
fn depth_binding(format: wgpu::TextureFormat) -> Result<DepthBinding> {
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

pub(crate) fn make_texture(
    device: &wgpu::Device,
    label: &str,
    size: (u32, u32),
    layers: u32,
    mips: u32,
    format: wgpu::TextureFormat,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: layers,
        },
        mip_level_count: mips,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

fn array_view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(D2_ARRAY),
        ..Default::default()
    })
}

impl Ao {
    /// Validates `options` and compiles every pipeline they need.
    pub fn new(device: &wgpu::Device, options: AoOptions) -> Result<Self> {
        options.validate()?;
        let scope = ErrorScope::push(device);
        let pyramid_levels = options
            .pyramid
            .levels_per_pass(device.adapter_info().device_type);
        let (prepare_store, steps) = plan_steps(&options, pyramid_levels);
        let prepare = [DepthBinding::Depth, DepthBinding::Float].map(|depth| {
            [false, true].map(|reconstruct| {
                compile(
                    device,
                    Pass::Prepare {
                        depth,
                        store: prepare_store,
                        reconstruct,
                        fit: false,
                    },
                    &options,
                )
            })
        });
        let mut later: Vec<Compiled> = Vec::new();
        for st in &steps {
            if !later.iter().any(|c| c.pass == st.pass) {
                later.push(compile(device, st.pass, &options));
            }
        }
        let uniform_buffer = |label| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: std::mem::size_of::<FrameUniforms>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let uniforms = uniform_buffer("obscura frame uniforms");
        let work_uniforms = uniform_buffer("obscura working-resolution frame uniforms");
        let dummy_normals = device
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
            .create_view(&Default::default());
        scope.pop("creating obscura's pipelines")?;
        Ok(Self {
            options,
            prepare,
            prepare_fit: [None, None],
            later,
            prepare_store,
            steps,
            uniforms,
            work_uniforms,
            dummy_normals,
            max_dim: device.limits().max_texture_dimension_2d,
            sized: None,
            resolve: None,
            created: ResourceCount {
                buffers: 2,
                textures: 1,
                texture_views: 1,
                bind_groups: 0,
            },
            temporal: TemporalState::default(),
        })
    }

    /// The options the pipelines were compiled for.
    pub fn options(&self) -> &AoOptions {
        &self.options
    }

    /// Checks `input` and `params` and derives the frame uniforms. No GPU work.
    pub fn validate(&self, input: &AoInput<'_>, params: &AoParams) -> Result<FrameUniforms> {
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
        let fits = |w: u32, h: u32| {
            viewport
                .x
                .checked_add(viewport.width)
                .is_some_and(|r| r <= w)
                && viewport
                    .y
                    .checked_add(viewport.height)
                    .is_some_and(|b| b <= h)
        };
        if !fits(tex.width(), tex.height()) {
            return Err(Error::InvalidViewport(format!(
                "{viewport:?} does not fit the {}x{} depth texture",
                tex.width(),
                tex.height()
            )));
        }
        if viewport.width > self.max_dim || viewport.height > self.max_dim {
            return Err(Error::TooLarge {
                width: viewport.width,
                height: viewport.height,
                max: self.max_dim,
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
                return bad(
                    "it must be a single-sampled 2D texture with one mip and one layer".into(),
                );
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
            viewport,
            &self.options,
            params,
        )
    }

    /// Compiles the MSAA resolve pass and creates its texture (at the depth texture's size)
    /// and bind group, unless those of the last frame still fit `depth`.
    fn ensure_resolve(&mut self, device: &wgpu::Device, depth: &wgpu::TextureView) -> Result<()> {
        let tex = depth.texture();
        let size = (tex.width(), tex.height());
        let fits = |r: &Resolve| (r.texture.width(), r.texture.height()) == size;
        if self
            .resolve
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
                RESOLVED_DEPTH_FORMAT,
            );
            let v = t.create_view(&Default::default());
            (t, v)
        };
        match self.resolve.as_mut() {
            None => {
                let compiled = compile(device, Pass::ResolveDepth, &self.options);
                let (texture, view) = new_texture();
                self.resolve = Some(Resolve {
                    compiled,
                    texture,
                    view,
                    binding: None,
                });
                self.created.textures += 1;
                self.created.texture_views += 1;
            }
            Some(r) if !fits(r) => {
                (r.texture, r.view) = new_texture();
                r.binding = None;
                self.created.textures += 1;
                self.created.texture_views += 1;
            }
            Some(_) => {}
        }
        let r = self.resolve.as_mut().expect("created above");
        let bg = bind_group(
            device,
            &r.compiled,
            &self.uniforms,
            &[(1, depth), (2, &r.view)],
        );
        r.binding = Some((depth.clone(), bg));
        self.created.bind_groups += 1;
        let result = scope.pop("creating obscura's MSAA depth resolve");
        if result.is_err() {
            self.resolve = None;
        }
        result
    }

    /// Creates the size-dependent resources unless they already match `size`.
    fn ensure_size(&mut self, device: &wgpu::Device, size: [u32; 2]) -> Result<()> {
        if self.sized.as_ref().is_some_and(|s| s.size == size) {
            return Ok(());
        }
        // Drop the old set first: at large sizes two sets may not fit together.
        self.sized = None;
        let scope = ErrorScope::push(device);
        let n = self.options.mode.split();
        let work_factor = self.options.resolution.factor();
        let at = |f: u32| (size[0].div_ceil(f), size[1].div_ceil(f));
        let work = at(work_factor);
        let lsize = layer_size(work.0, work.1, n);
        let mut used: Vec<Res> = prepare_targets(self.prepare_store)
            .into_iter()
            .map(|t| t.1)
            .collect();
        for st in &self.steps {
            for &(_, r) in &st.views {
                let rs = match r {
                    Res::PyramidMip(_) => vec![Res::Pyramid],
                    Res::MomentsMip(_) => vec![Res::Moments],
                    Res::HistoryPrev | Res::HistoryNext => vec![Res::History(0), Res::History(1)],
                    Res::BentHistoryPrev | Res::BentHistoryNext => {
                        vec![Res::BentHistory(0), Res::BentHistory(1)]
                    }
                    r => vec![r],
                };
                for r in rs {
                    if !used.contains(&r) {
                        used.push(r);
                    }
                }
            }
        }
        // The output is the caller's or created on demand (see `Ao::plan`).
        used.retain(|&r| r != Res::Output);
        let textures: Vec<(Res, wgpu::Texture, wgpu::TextureView)> = used
            .into_iter()
            .map(|r| {
                let (label, dims, layers, format) = match r {
                    Res::Prepared => ("obscura prepared", at(1), 1, PREPARED_FORMAT),
                    Res::LinearDepth => ("obscura linear depth", at(1), 1, LINEAR_DEPTH_FORMAT),
                    Res::PreparedLayers => {
                        ("obscura prepared layers", lsize, n * n, PREPARED_FORMAT)
                    }
                    Res::Level(k) => ("obscura prepared level", at(1 << k), 1, PREPARED_FORMAT),
                    Res::Scaled => ("obscura prepared at scale", at(1), 1, PREPARED_FORMAT),
                    Res::Pyramid | Res::PyramidMip(_) => (
                        "obscura depth pyramid",
                        (1.max(size[0] >> 1), 1.max(size[1] >> 1)),
                        1,
                        PYRAMID_FORMAT,
                    ),
                    Res::Moments | Res::MomentsMip(_) => (
                        "obscura depth moments",
                        (1.max(size[0] >> 1), 1.max(size[1] >> 1)),
                        1,
                        MOMENTS_FORMAT,
                    ),
                    Res::AoWork => ("obscura ao work", work, 1, AO_FORMAT),
                    Res::AoTmp => ("obscura ao blur", work, 1, AO_FORMAT),
                    Res::AoLayers => ("obscura ao layers", lsize, n * n, AO_FORMAT),
                    Res::AoHalf => ("obscura ao half", at(2 * work_factor), 1, AO_FORMAT),
                    Res::History(_) => ("obscura ao history", work, 1, HISTORY_FORMAT),
                    Res::Bent => {
                        let dims = if bent_upsampled(&self.options) {
                            at(1)
                        } else {
                            work
                        };
                        ("obscura bent normals", dims, 1, BENT_FORMAT)
                    }
                    Res::BentRaw => ("obscura bent normals raw", work, 1, BENT_FORMAT),
                    Res::BentTmp => ("obscura bent normals accumulated", work, 1, BENT_FORMAT),
                    Res::BentHistory(_) => ("obscura bent normal history", work, 1, BENT_FORMAT),
                    Res::Output
                    | Res::HistoryPrev
                    | Res::HistoryNext
                    | Res::BentHistoryPrev
                    | Res::BentHistoryNext => {
                        unreachable!("the output is created on demand; history resolves by parity")
                    }
                };
                let mips = if r == Res::Pyramid || r == Res::Moments {
                    dims.0.max(dims.1).ilog2() + 1
                } else {
                    1
                };
                let t = make_texture(device, label, dims, layers, mips, format);
                let v = if layers > 1 {
                    array_view(&t)
                } else {
                    t.create_view(&Default::default())
                };
                (r, t, v)
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
        let workgroups = |w: u32, h: u32, z: u32| {
            let (x, y) = dispatch_size([w, h]);
            [x, y, z]
        };
        let grid = |g: Grid| match g {
            Grid::Level(k) => {
                let d = at(1 << k);
                Dispatch::Fixed(workgroups(d.0, d.1, 1))
            }
            Grid::Work => Dispatch::Work,
            Grid::Layers => Dispatch::WorkLayers,
            Grid::PyramidBase | Grid::PyramidMips => {
                Dispatch::Fixed(workgroups(pyramid_base.0, pyramid_base.1, 1))
            }
        };
        let mut later = Vec::new();
        let mut output_step = (0, 0);
        let mut bind_groups = 0;
        for (si, st) in self.steps.iter().enumerate() {
            let i = self
                .later
                .iter()
                .position(|c| c.pass == st.pass)
                .expect("every step's pass is compiled in Ao::new");
            let c = &self.later[i];
            let buffer = match st.frame {
                FrameAt::Full => &self.uniforms,
                FrameAt::Work => &self.work_uniforms,
            };
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
                    later.push((
                        i,
                        Some([bg.clone(), bg]),
                        Dispatch::Fixed(workgroups(d.0, d.1, 1)),
                    ));
                }
                continue;
            }
            if st.views.iter().any(|v| v.1 == Res::Output) {
                output_step = (later.len(), si);
                later.push((i, None, grid(st.grid)));
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
            later.push((i, Some([even, odd]), grid(st.grid)));
        }
        let prepare_dispatch = match self.prepare_store {
            PrepareStore::Full => grid(Grid::Level(0)),
            PrepareStore::Layers => Dispatch::Fixed(workgroups(lsize.0, lsize.1, n * n)),
            PrepareStore::Down { .. } => grid(Grid::Level(1)),
        };
        self.created.textures += textures.len() as u32 + placeholders.get();
        self.created.texture_views += textures.len() as u32 + mip_views.get() + placeholders.get();
        self.created.bind_groups += bind_groups;
        // A new size starts a new history.
        self.temporal.valid = false;
        self.sized = Some(SizedResources {
            size,
            textures,
            prepare_dispatch,
            later,
            output_step,
            prepare_binding: None,
            output_binding: None,
            own_output: None,
        });
        if let Err(e) = scope.pop(&format!(
            "creating obscura's {}x{} textures",
            size[0], size[1]
        )) {
            self.sized = None;
            return Err(e);
        }
        Ok(())
    }

    /// Validates, uploads uniforms, and returns the passes of this frame in order as
    /// (compiled pass, bind group, dispatch size).
    fn plan(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        input: &AoInput<'_>,
        params: &AoParams,
    ) -> Result<Vec<(&Compiled, wgpu::BindGroup, [u32; 3])>> {
        let mut frame = self.validate(input, params)?;
        let multisampled = input.depth.texture().sample_count() > 1;
        // A multisampled depth is resolved first and the prepare pass reads the result.
        let (depth_view, binding) = if multisampled {
            self.ensure_resolve(device, input.depth)?;
            let r = self
                .resolve
                .as_ref()
                .expect("resolve resources were just created");
            (r.view.clone(), DepthBinding::Float)
        } else {
            (
                input.depth.clone(),
                depth_binding(input.depth.texture().format())?,
            )
        };
        self.ensure_size(device, frame.size)?;
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
        let normals = input.normals.map_or(&self.dummy_normals, |n| n.0);
        let b = match binding {
            DepthBinding::Depth => 0,
            DepthBinding::Float => 1,
        };
        let fit = input.normals.is_none() && !params.depth_noise.is_none();
        if fit && self.prepare_fit[b].is_none() {
            let scope = ErrorScope::push(device);
            let pass = Pass::Prepare {
                depth: binding,
                store: self.prepare_store,
                reconstruct: true,
                fit: true,
            };
            let compiled = compile(device, pass, &self.options);
            scope.pop("compiling the noisy-depth prepare pass")?;
            self.prepare_fit[b] = Some(compiled);
        }
        let prepare = match (&self.prepare_fit[b], fit) {
            (Some(c), true) => c,
            _ => &self.prepare[b][input.normals.is_none() as usize],
        };
        // The same input views as last frame (an engine's usual case): reuse the bind group.
        let cached = sized.prepare_binding.as_ref().is_some_and(|b| {
            b.depth == depth_view
                && b.normals.as_ref() == input.normals.map(|n| n.0)
                && b.fit == fit
        });
        if !cached {
            let mut views = vec![(1, &depth_view), (2, normals)];
            for (b, r) in prepare_targets(self.prepare_store) {
                let Some(target) = sized.view(r) else {
                    return Err(Error::Gpu("no prepare target".into()));
                };
                views.push((b, target));
            }
            let bg = bind_group(device, prepare, &self.uniforms, &views);
            self.created.bind_groups += 1;
            sized.prepare_binding = Some(PrepareBinding {
                depth: depth_view,
                normals: input.normals.map(|n| n.0.clone()),
                fit,
                bind_group: bg,
            });
        }
        let Some(prepare_bind) = sized.prepare_binding.as_ref().map(|b| b.bind_group.clone())
        else {
            return Err(Error::Gpu("prepare bind group missing".into()));
        };
        // The output: the caller's view, or the library's own texture.
        if input.output.is_none() && sized.own_output.is_none() {
            let scope = ErrorScope::push(device);
            let t = make_texture(
                device,
                "obscura ao",
                (frame.size[0], frame.size[1]),
                1,
                1,
                AO_FORMAT,
            );
            let v = t.create_view(&Default::default());
            scope.pop("creating obscura's output texture")?;
            self.created.textures += 1;
            self.created.texture_views += 1;
            sized.own_output = Some((t, v));
        }
        let out_view = match (input.output, &sized.own_output) {
            (Some(v), _) | (None, Some((_, v))) => v.clone(),
            (None, None) => return Err(Error::Gpu("output texture missing".into())),
        };
        if sized.output_binding.as_ref().map(|b| &b.0) != Some(&out_view) {
            let (_, si) = sized.output_step;
            let st = &self.steps[si];
            let c = &self.later[sized.later[sized.output_step.0].0];
            let buffer = match st.frame {
                FrameAt::Full => &self.uniforms,
                FrameAt::Work => &self.work_uniforms,
            };
            let mut groups = Vec::with_capacity(2);
            for parity in 0..2 {
                let mut views = Vec::with_capacity(st.views.len());
                for &(b, r) in &st.views {
                    let v = if r == Res::Output {
                        &out_view
                    } else {
                        sized
                            .view(r.at_parity(parity))
                            .ok_or_else(|| Error::Gpu(format!("texture {r:?} missing")))?
                    };
                    views.push((b, v));
                }
                groups.push(bind_group(device, c, buffer, &views));
                self.created.bind_groups += 1;
            }
            let odd = groups.pop().expect("two bind groups");
            let even = groups.pop().expect("two bind groups");
            sized.output_binding = Some((out_view, [even, odd]));
        }
        let Some((_, output_bind)) = sized.output_binding.as_ref() else {
            return Err(Error::Gpu("output bind group missing".into()));
        };
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
        for (i, bg, d) in &sized.later {
            let bg = bg.as_ref().unwrap_or(output_bind)[p].clone();
            passes.push((&self.later[*i], bg, d.at(work.size, n)));
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
        let passes = self.plan(device, queue, input, params)?;
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
    /// says. For benchmarks: it creates timing resources per call.
    pub fn run_timed(
        &mut self,
        ctx: &crate::GpuContext,
        input: &AoInput<'_>,
        params: &AoParams,
        timing: Timing,
    ) -> Result<Vec<(&'static str, f64)>> {
        let passes = self.plan(&ctx.device, &ctx.queue, input, params)?;
        let dispatch = |enc: &mut wgpu::CommandEncoder,
                        (c, bg, d): &(&Compiled, wgpu::BindGroup, [u32; 3]),
                        ts: Option<wgpu::ComputePassTimestampWrites>| {
            let mut cpass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(c.pass.label()),
                timestamp_writes: ts,
            });
            cpass.set_pipeline(&c.pipeline);
            cpass.set_bind_group(0, bg, &[]);
            cpass.dispatch_workgroups(d[0], d[1], d[2]);
        };
        match timing {
            Timing::WallClock => {
                let mut times = Vec::with_capacity(passes.len());
                for p in &passes {
                    let t = std::time::Instant::now();
                    ctx.run(|enc| {
                        dispatch(enc, p, None);
                        Ok(())
                    })?;
                    times.push((p.0.pass.label(), t.elapsed().as_secs_f64() * 1e3));
                }
                Ok(times)
            }
            Timing::Timestamps => {
                if !ctx
                    .device
                    .features()
                    .contains(wgpu::Features::TIMESTAMP_QUERY)
                {
                    return Err(Error::Gpu("the device has no timestamp queries".into()));
                }
                let count = 2 * passes.len() as u32;
                let bytes = 8 * count as u64;
                let set = ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("obscura pass timestamps"),
                    ty: wgpu::QueryType::Timestamp,
                    count,
                });
                let buffer = |usage| {
                    ctx.device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some("obscura timestamps"),
                        size: bytes,
                        usage,
                        mapped_at_creation: false,
                    })
                };
                let resolved =
                    buffer(wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC);
                let readback = buffer(wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ);
                ctx.run(|enc| {
                    for (i, p) in passes.iter().enumerate() {
                        let writes = wgpu::ComputePassTimestampWrites {
                            query_set: &set,
                            beginning_of_pass_write_index: Some(2 * i as u32),
                            end_of_pass_write_index: Some(2 * i as u32 + 1),
                        };
                        dispatch(enc, p, Some(writes));
                    }
                    enc.resolve_query_set(&set, 0..count, &resolved, 0);
                    enc.copy_buffer_to_buffer(&resolved, 0, &readback, 0, bytes);
                    Ok(())
                })?;
                let ticks: Vec<u64> = bytemuck::pod_collect_to_vec(&ctx.map_read(&readback)?);
                let ns_per_tick = ctx.queue.get_timestamp_period() as f64;
                Ok(passes
                    .iter()
                    .zip(ticks.chunks_exact(2))
                    .map(|(p, t)| {
                        let ms = t[1].saturating_sub(t[0]) as f64 * ns_per_tick / 1e6;
                        (p.0.pass.label(), ms)
                    })
                    .collect())
            }
        }
    }

    /// How many GPU objects this `Ao` has created. Frames at an unchanged size with the same
    /// input views create nothing; a resize recreates only the size-dependent textures,
    /// views and bind groups; new input views cost one bind group. ([`Ao::run_timed`], for
    /// benchmarks, also creates query buffers, not counted.)
    pub fn resource_creations(&self) -> ResourceCount {
        self.created
    }

    /// The MSAA resolve's output (`R32Float`, the depth texture's size; raw depth at the
    /// viewport's texels), once a frame with a multisampled depth input was recorded.
    pub fn resolved_depth(&self) -> Option<&wgpu::Texture> {
        self.resolve.as_ref().map(|r| &r.texture)
    }

    /// The library's own AO texture (`R32Float`, viewport-sized, 1 = unoccluded), once a
    /// frame was recorded without a caller-provided [`AoInput::output`].
    pub fn output(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().and_then(|s| s.texture(Res::Output))
    }

    /// A view of [`Ao::output`].
    pub fn output_view(&self) -> Option<&wgpu::TextureView> {
        self.sized.as_ref().and_then(|s| s.view(Res::Output))
    }

    /// The full-resolution prepared `vec4(linear depth, view normal)` texture
    /// (`Rgba32Float`) when the plan has one (not in fused deinterleaved modes, nor below
    /// full resolution unless unfused or upsampled bilaterally), for debugging/tests.
    pub fn prepared_view(&self) -> Option<&wgpu::TextureView> {
        self.sized.as_ref().and_then(|s| s.view(Res::Prepared))
    }

    /// The texture behind [`Ao::prepared_view`] (`Rgba32Float`), for passes that shade
    /// from it ([`crate::Lights`]).
    pub fn prepared(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().and_then(|s| s.texture(Res::Prepared))
    }

    /// The full-resolution depth and normals of the last frame for passes that shade from
    /// them ([`crate::Lights`]): the prepared buffer, or in the fused deinterleaved modes
    /// its N×N layers. `None` below full resolution, where only the working grid's exist.
    pub fn prepared_source(&self) -> Option<crate::lights::Prepared<'_>> {
        if self.options.resolution != crate::Resolution::Full {
            return None;
        }
        let sized = self.sized.as_ref()?;
        if let Some(t) = sized.texture(Res::Prepared) {
            return Some(crate::lights::Prepared::Full(t));
        }
        sized
            .texture(Res::PreparedLayers)
            .map(|texture| crate::lights::Prepared::Layers {
                texture,
                split: self.options.mode.split(),
            })
    }

    /// Full-resolution linear view depth (`R32Float`, 0 = sky) when AO runs below full
    /// resolution with the fused prepare ([`AoOptions::fused`]) and an upsampler that needs
    /// no normals (else the prepared buffer holds it), for debugging/tests.
    pub fn linear_depth(&self) -> Option<&wgpu::Texture> {
        self.sized
            .as_ref()
            .and_then(|s| s.texture(Res::LinearDepth))
    }

    /// The depth pyramid (`Rgba32Float`, `vec4(select, min, max, 0)`, mip m = level m + 1)
    /// when the estimator or the upsampler uses one.
    pub fn pyramid(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().and_then(|s| s.texture(Res::Pyramid))
    }

    /// The depth moments pyramid (`Rgba32Float`, `vec4(valid fraction, mean, variance, 0)`
    /// of linear depth, mip m = level m + 1) when the estimator is VO's area integral.
    pub fn moments(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().and_then(|s| s.texture(Res::Moments))
    }

    /// The prepared buffer downsampled `k ≥ 1` times by the depth rule (below full
    /// resolution), `ceil(size / 2^k)`, `Rgba32Float`.
    pub fn prepared_level(&self, k: u32) -> Option<&wgpu::Texture> {
        self.sized.as_ref().and_then(|s| s.texture(Res::Level(k)))
    }

    /// The bent normals of the last frame ([`AoOptions::bent_normals`]), after the temporal
    /// pass, the denoiser and the upsampler where they run: `Rgba32Float` at full
    /// resolution (at the working resolution after the box or tent filter), `vec4(n, 0)`
    /// with n the unit bent normal in view space (+z toward the camera, as the prepared
    /// normals), zero on sky.
    pub fn bent_normals(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().and_then(|s| s.texture(Res::Bent))
    }

    /// Forgets the temporal history: the next frame starts a new one (as after a camera
    /// cut, [`CameraMotion::Cut`], or a resize).
    pub fn reset_history(&mut self) {
        self.temporal.valid = false;
    }

    /// Forgets the temporal history and restarts the frame sequence, so the next frames
    /// sample as the first ones did: accumulations that can be reproduced call by call.
    pub fn restart(&mut self) {
        self.temporal.valid = false;
        self.temporal.frame = 0;
    }

    /// The temporal history written by the last frame (`Rgba32Float` at the working
    /// resolution; with [`Resolution::Scaled`] a full-size texture whose top-left
    /// `ceil(full × scale)` texels hold it: `vec4(AO, frames accumulated (0 = sky), linear
    /// depth, packed normal)`
    /// (`reference::unpack_normal` decodes it)), when
    /// [`AoOptions::history`] is on and a frame was recorded.
    pub fn history(&self) -> Option<&wgpu::Texture> {
        let parity = self.temporal.parity;
        self.sized
            .as_ref()
            .filter(|_| self.temporal.frame > 0)
            .and_then(|s| s.texture(Res::History(parity)))
    }

    /// The bent-normal history written by the last frame (as [`Ao::bent_normals`]), when
    /// bent normals and [`AoOptions::history`] are on and a frame was recorded.
    pub fn bent_history(&self) -> Option<&wgpu::Texture> {
        let parity = self.temporal.parity;
        self.sized
            .as_ref()
            .filter(|_| self.temporal.frame > 0)
            .and_then(|s| s.texture(Res::BentHistory(parity)))
    }

    /// The AO pass's own bent normals, when a temporal pass or the denoiser follows it (for
    /// tests against the CPU mirror).
    pub fn bent_normals_raw(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().and_then(|s| s.texture(Res::BentRaw))
    }

    /// The AO at working resolution: below full resolution what the upsampler reads
    /// (after temporal accumulation and denoising), else the AO pass's own output before
    /// them, when the plan keeps one.
    pub fn working_ao(&self) -> Option<&wgpu::Texture> {
        let upsampled = self.steps.iter().find_map(|st| match st.pass {
            Pass::Upsample { .. } | Pass::UpsampleScaled => {
                st.views.iter().find(|v| v.0 == 2).map(|v| v.1)
            }
            _ => None,
        });
        let r = match upsampled {
            Some(r @ (Res::AoWork | Res::AoTmp)) => r,
            _ => Res::AoWork,
        };
        self.sized.as_ref().and_then(|s| s.texture(r))
    }

    /// The prepared buffer at the last frame's scale with [`Resolution::Scaled`]
    /// (`Rgba32Float`, created at full size; the working grid is its top-left
    /// `ceil(full × scale)` texels).
    pub fn scaled_prepared(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().and_then(|s| s.texture(Res::Scaled))
    }

    /// The AO pass's own output at working resolution when it does not write the output
    /// directly (for tests against the CPU mirrors). Below full resolution with both the
    /// temporal pass and the denoiser, the denoiser writes over it.
    pub fn raw_ao(&self) -> Option<&wgpu::Texture> {
        self.sized.as_ref().and_then(|s| s.texture(Res::AoWork))
    }

    /// The deinterleaved prepared layers (`Rgba32Float` array, N² layers) in deinterleaved modes.
    pub fn prepared_layers_view(&self) -> Option<&wgpu::TextureView> {
        self.sized
            .as_ref()
            .and_then(|s| s.view(Res::PreparedLayers))
    }
}
