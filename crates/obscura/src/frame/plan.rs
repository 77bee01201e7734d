//! The frame plan as plain data: a pure function of the options (and of the adapter's
//! pyramid build) that lists what one AO frame does. Passes: each one's shader ([`Pass`],
//! entry point `main`), the textures it binds by binding number and its invocation grid.
//! Resources: each texture's name, format, size rule, layers and lifetime. Nothing here
//! touches a device, so the plan is unit-tested without a GPU (below); the recorder
//! ([`super::resources`], [`super::ao`]) allocates what the plan names and walks it.
//!
//! ```text
//! randomized:           prepare ─▶ AO (full resolution, 4×4 per-pixel patterns)
//! deinterleaved, fused: prepare (writes N×N layers) ─▶ AO over the layers, merged on write
//! deinterleaved:        prepare ─▶ deinterleave ─▶ AO over the layers ─▶ interleave
//! half / quarter:       prepare (half-res vec4(d, n) + full-res linear depth)
//!                       ─▶ [downsample to quarter] ─▶ AO at working resolution
//!                       ─▶ [blur | box/tent] ─▶ upsample (full res)
//! scaled (any scale):   prepare ─▶ rescale ─▶ AO on the frame's working grid ─▶ [temporal]
//!                       ─▶ [denoise] ─▶ upsample_scaled (full res)
//! ```
//!
//! After the AO pass: [temporal accumulation] ─▶ [spatial denoiser] ─▶ [upsampler]. The
//! estimators that read the depth pyramid (SAO), and the classified upsampler, get its
//! levels built between prepare and the AO pass; VO's area integral gets a moments pyramid.

use crate::passes::constants::{
    AO_FORMAT, AO_PACKED_FORMAT, BENT_FORMAT, HISTORY_FORMAT, LINEAR_DEPTH_FORMAT, MOMENTS_FORMAT,
    PREPARED_FORMAT, PYRAMID_FORMAT, PYRAMID_LEVELS_PER_PASS,
};
use crate::passes::layers::layer_size;
use crate::passes::shader::{dispatch_size, Pass, PrepareStore, PyramidSource};
use crate::{AoOptions, Denoise, Resolution, Upsampler};

pub use super::plan_types::{FrameAt, Grid, Lifetime, Res, Step, TextureSpec};

/// One AO frame's passes and textures, for one [`AoOptions`].
#[derive(Clone, Debug)]
pub struct Plan {
    /// What the prepare pass (always first) stores.
    pub prepare_store: PrepareStore,
    /// The passes after prepare, in execution order.
    pub steps: Vec<Step>,
    options: AoOptions,
}

impl Plan {
    /// The plan for `options`; `pyramid_levels`: pyramid levels per pass after the first
    /// (1 on CPU adapters, [`PYRAMID_LEVELS_PER_PASS`] on GPUs; [`crate::PyramidBuild`]).
    pub fn new(options: &AoOptions, pyramid_levels: u32) -> Plan {
        let (prepare_store, steps) = plan_steps(options, pyramid_levels);
        Plan {
            prepare_store,
            steps,
            options: *options,
        }
    }

    /// Whether the prepare pass linearises a second depth layer ([`AoOptions::second_layer`]).
    pub fn second_layer(&self) -> bool {
        self.options.second_layer
    }

    /// The distinct passes after prepare, in order of first use (each compiled once).
    pub fn passes(&self) -> Vec<Pass> {
        let mut out: Vec<Pass> = Vec::new();
        for st in &self.steps {
            if !out.contains(&st.pass) {
                out.push(st.pass);
            }
        }
        out
    }

    /// The textures the library creates for a frame, in order of first use: the prepare
    /// pass's targets, then every texture a step binds (both textures of a history; the
    /// whole pyramid for a mip). The output is not among them ([`Lifetime::Caller`]).
    pub fn textures(&self) -> Vec<Res> {
        let mut used: Vec<Res> = prepare_targets(self.prepare_store, self.options.second_layer)
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
        used.retain(|&r| r != Res::Output);
        used
    }

    /// Name, size, layers, mips, format and lifetime of texture `r` for a frame of `size`
    /// pixels. `None` for the output and the per-parity history names (they resolve to
    /// [`Res::History`] and [`Res::BentHistory`]).
    pub fn spec(&self, r: Res, size: [u32; 2]) -> Option<TextureSpec> {
        let o = &self.options;
        let n = o.mode.split();
        let work_factor = o.resolution.factor();
        let at = |f: u32| (size[0].div_ceil(f), size[1].div_ceil(f));
        let work = at(work_factor);
        let lsize = layer_size(work.0, work.1, n);
        let half = (1.max(size[0] >> 1), 1.max(size[1] >> 1));
        let (label, dims, layers, format) = match r {
            Res::Prepared => ("obscura prepared", at(1), 1, PREPARED_FORMAT),
            Res::LinearDepth => ("obscura linear depth", at(1), 1, LINEAR_DEPTH_FORMAT),
            Res::SecondLayer => ("obscura second layer", at(1), 1, LINEAR_DEPTH_FORMAT),
            Res::PreparedLayers => ("obscura prepared layers", lsize, n * n, PREPARED_FORMAT),
            Res::Level(k) => ("obscura prepared level", at(1 << k), 1, PREPARED_FORMAT),
            Res::Scaled => ("obscura prepared at scale", at(1), 1, PREPARED_FORMAT),
            Res::Pyramid | Res::PyramidMip(_) => ("obscura depth pyramid", half, 1, PYRAMID_FORMAT),
            Res::Moments | Res::MomentsMip(_) => ("obscura depth moments", half, 1, MOMENTS_FORMAT),
            Res::AoWork => ("obscura ao work", work, 1, AO_FORMAT),
            Res::AoPacked => ("obscura ao packed", work, 1, AO_PACKED_FORMAT),
            Res::AoTmp => ("obscura ao blur", work, 1, AO_FORMAT),
            Res::AoLayers => ("obscura ao layers", lsize, n * n, AO_FORMAT),
            Res::AoHalf => ("obscura ao half", at(2 * work_factor), 1, AO_FORMAT),
            Res::History(_) => ("obscura ao history", work, 1, HISTORY_FORMAT),
            Res::Bent => {
                let dims = if bent_upsampled(o) { at(1) } else { work };
                ("obscura bent normals", dims, 1, BENT_FORMAT)
            }
            Res::BentRaw => ("obscura bent normals raw", work, 1, BENT_FORMAT),
            Res::BentTmp => ("obscura bent normals accumulated", work, 1, BENT_FORMAT),
            Res::BentHistory(_) => ("obscura bent normal history", work, 1, BENT_FORMAT),
            Res::Output
            | Res::HistoryPrev
            | Res::HistoryNext
            | Res::BentHistoryPrev
            | Res::BentHistoryNext => return None,
        };
        let mips = if matches!(r, Res::Pyramid | Res::Moments) {
            dims.0.max(dims.1).ilog2() + 1
        } else {
            1
        };
        let lifetime = match r {
            Res::History(_) | Res::BentHistory(_) => Lifetime::AcrossFrames,
            _ => Lifetime::Frame,
        };
        Some(TextureSpec {
            res: r,
            label,
            size: dims,
            layers,
            mips,
            format,
            lifetime,
        })
    }

    /// The workgroups of a pass over `grid` for a frame of `size` pixels (pyramid mips:
    /// mip 0's; [`Grid::PyramidMips`] dispatches once per group of mips).
    pub fn dispatch(&self, grid: Grid, size: [u32; 2]) -> Dispatch {
        let at = |f: u32| [size[0].div_ceil(f), size[1].div_ceil(f)];
        let fixed = |d: [u32; 2], z: u32| {
            let (x, y) = dispatch_size(d);
            Dispatch::Fixed([x, y, z])
        };
        match grid {
            Grid::Level(k) => fixed(at(1 << k), 1),
            Grid::Work => Dispatch::Work,
            Grid::Layers => Dispatch::WorkLayers,
            Grid::PyramidBase | Grid::PyramidMips => {
                fixed([1.max(size[0] >> 1), 1.max(size[1] >> 1)], 1)
            }
        }
    }

    /// The prepare pass's workgroups: over pixels, over layer texels when it splits, or
    /// over the first level when it downsamples.
    pub fn prepare_dispatch(&self, size: [u32; 2]) -> Dispatch {
        match self.prepare_store {
            PrepareStore::Full => self.dispatch(Grid::Level(0), size),
            PrepareStore::Layers => {
                let o = &self.options;
                let n = o.mode.split();
                let f = o.resolution.factor();
                let l = layer_size(size[0].div_ceil(f), size[1].div_ceil(f), n);
                let (x, y) = dispatch_size([l.0, l.1]);
                Dispatch::Fixed([x, y, n * n])
            }
            PrepareStore::Down { .. } => self.dispatch(Grid::Level(1), size),
        }
    }

    /// The step that writes the output (exactly one does).
    pub fn output_step(&self) -> Option<usize> {
        self.steps
            .iter()
            .position(|st| st.views.iter().any(|v| v.1 == Res::Output))
    }

    /// Whether the output step can store the viewport alone with a guard band
    /// (passes/output.wgsl): true of every plan (plan_tests.rs checks).
    pub fn output_crops(&self) -> bool {
        self.output_step()
            .is_some_and(|i| self.steps[i].pass.crops_output())
    }
}

/// A pass's workgroup counts: fixed by the frame size, or taken from each frame's working
/// grid (which [`crate::Resolution::Scaled`] changes every frame).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dispatch {
    Fixed([u32; 3]),
    Work,
    WorkLayers,
}

impl Dispatch {
    /// The workgroup counts for a working grid of `work` pixels and an `n` × `n` split.
    pub fn at(self, work: [u32; 2], n: u32) -> [u32; 3] {
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

/// What the prepare pass stores, and the textures it writes, by binding; `second_layer`:
/// the second depth layer's too.
pub fn prepare_targets(store: PrepareStore, second_layer: bool) -> Vec<(u32, Res)> {
    let mut targets = match store {
        PrepareStore::Full => vec![(3, Res::Prepared)],
        PrepareStore::Layers => vec![(3, Res::PreparedLayers)],
        PrepareStore::Down { normals: true, .. } => vec![(3, Res::Level(1)), (4, Res::Prepared)],
        PrepareStore::Down { normals: false, .. } => {
            vec![(3, Res::Level(1)), (4, Res::LinearDepth)]
        }
    };
    if second_layer {
        targets.push((6, Res::SecondLayer));
    }
    targets
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
    let (packed, temporal_packs) = packing(o);
    let ao_target = if direct {
        Res::Output
    } else if packed {
        Res::AoPacked
    } else {
        Res::AoWork
    };
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
        if o.second_layer {
            v.push((5, Res::SecondLayer));
        }
        v
    };
    let e = o.estimator;
    let second_layer = o.second_layer;
    let layers = |merge| Pass::AoLayered {
        merge,
        estimator: e,
        bent,
        second_layer,
        packed: merge && packed,
    };
    match (n > 1, fused_prepare, direct) {
        (false, ..) => steps.push(step(
            Pass::AoFull {
                estimator: e,
                bent,
                second_layer,
                packed,
            },
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
                    pyramid(vec![(1, Res::PreparedLayers), (2, ao_target)]),
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
    let mut current = ao_target;
    if o.history > 0 {
        let more = o.denoise != Denoise::None || upsample;
        let next = if temporal_packs {
            Res::AoPacked
        } else if more {
            other_ao(current)
        } else {
            Res::Output
        };
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
                packed: temporal_packs,
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
                other_ao(current)
            } else {
                Res::Output
            };
            let mut views = vec![(2, current), (3, next)];
            if filter_bent {
                let next = bent_next(bent_current, upsample_bent);
                views.extend([(4, bent_current), (5, next)]);
                bent_current = next;
            }
            steps.push(step(
                Pass::Denoise { bent: filter_bent },
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
    let (packed, temporal_packs) = packing(o);
    let ao_target = if packed { Res::AoPacked } else { Res::AoWork };
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
                second_layer: false,
                packed,
            },
            vec![(1, Res::PreparedLayers), (2, ao_target)],
            FrameAt::Work,
            Grid::Layers,
        ));
    } else {
        steps.push(step(
            Pass::AoFull {
                estimator,
                bent: false,
                second_layer: false,
                packed,
            },
            vec![(1, Res::Scaled), (2, ao_target)],
            FrameAt::Work,
            Grid::Work,
        ));
    }
    // After the AO pass: [temporal] → [denoise], alternating the two working textures.
    let mut current = ao_target;
    if o.history > 0 {
        let next = if temporal_packs {
            Res::AoPacked
        } else {
            other_ao(current)
        };
        steps.push(step(
            Pass::Temporal {
                layers: false,
                bent: false,
                packed: temporal_packs,
            },
            vec![
                (1, Res::Scaled),
                (2, current),
                (3, Res::HistoryPrev),
                (4, Res::HistoryNext),
                (5, next),
            ],
            FrameAt::Work,
            Grid::Work,
        ));
        current = next;
    }
    if o.denoise == Denoise::Spatial {
        steps.push(step(
            Pass::Denoise { bent: false },
            vec![(2, current), (3, other_ao(current))],
            FrameAt::Work,
            Grid::Work,
        ));
        current = other_ao(current);
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

/// The work-size AO texture a post-processing pass writes when it reads `r`: the other
/// of the two it alternates between (AoWork, AoTmp).
fn other_ao(r: Res) -> Res {
    if r == Res::AoWork {
        Res::AoTmp
    } else {
        Res::AoWork
    }
}

/// Which pass stores the AO packed beside the pixel's geometry for the spatial denoiser
/// (passes/estimators/ao_packed.wgsl), whose taps are then one fetch each instead of two:
/// the pass before it, the temporal pass where one runs (it reads the AO alone), else the
/// AO pass. `(the AO pass, the temporal pass)`.
fn packing(o: &AoOptions) -> (bool, bool) {
    let denoised = o.denoise == Denoise::Spatial;
    (denoised && o.history == 0, denoised && o.history > 0)
}

/// Whether the bent normals are upsampled to full resolution (below full resolution, unless
/// the box or tent filter downsampled the AO further: they stay at the working resolution).
fn bent_upsampled(o: &AoOptions) -> bool {
    o.resolution.factor() > 1 && !o.denoise.downsamples()
}
