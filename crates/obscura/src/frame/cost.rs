//! What an AO frame's passes cost, counted rather than timed: per pass, the invocations
//! (from the [`Plan`]), each invocation's texel fetches, special-function operations and
//! other arithmetic, and the bytes of every texture it binds; then a roofline per device
//! (Williams, Waterman & Patterson 2009): the time each pass would take at the device's
//! texel rate, memory bandwidth, arithmetic rate and special-function rate, and which of the
//! four binds. Measured times over the roofline's are what a pass loses to latency, cache
//! misses and divergence (BENCHMARKS.md sets the two side by side).
//!
//! Fetch counts are exact for a pixel whose samples all land on screen, on geometry, away
//! from the centre (the CPU mirror's reads check it below). The arithmetic is a hand count
//! of the WGSL by operation (an FMA, add, compare, select or bit operation is one; a
//! division, square root, inverse square root, exp2, log2, sin or cos is one special), good
//! to about a fifth: it ranks passes and levers, it does not time them.

use crate::frame::plan::{Plan, Res, Step};
use crate::passes::constants::AO_FORMAT;
use crate::passes::shader::Pass;
use crate::{AoOptions, Denoise, Estimator};

/// Work per invocation of a pass.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Work {
    /// Texel fetches (texture loads).
    pub fetches: f64,
    /// Special-function operations (division, sqrt, inverse sqrt, exp2, log2, sin, cos).
    pub special: f64,
    /// Other arithmetic: adds, multiplies, FMAs, compares, selects, bit operations.
    pub alu: f64,
}

impl std::ops::Add for Work {
    type Output = Work;
    fn add(self, o: Work) -> Work {
        Work {
            fetches: self.fetches + o.fetches,
            special: self.special + o.special,
            alu: self.alu + o.alu,
        }
    }
}

impl std::ops::Mul<f64> for Work {
    type Output = Work;
    fn mul(self, k: f64) -> Work {
        Work {
            fetches: self.fetches * k,
            special: self.special * k,
            alu: self.alu * k,
        }
    }
}

const fn work(fetches: f64, special: f64, alu: f64) -> Work {
    Work {
        fetches,
        special,
        alu,
    }
}

/// One pass of a frame, counted.
#[derive(Clone, Debug, PartialEq)]
pub struct PassCost {
    /// The pass's label ([`Pass::label`]).
    pub label: &'static str,
    /// Invocations (pixels or layer texels) in one frame.
    pub invocations: u64,
    /// Work per invocation; `None` where this model does not count the pass.
    pub per_invocation: Option<Work>,
    /// Bytes of every texture the pass binds, each read or written once: the compulsory
    /// memory traffic (the prepare pass's inputs counted as 4 bytes a pixel each).
    pub bytes: u64,
}

// Hand counts of the WGSL (see the module's comment). GTAO: gtao.wgsl, gtao_arcs.wgsl,
// common.wgsl (march_ray, snap_offset), ao_layered.wgsl (pixel_pattern).
/// Per pixel: centre fetch, view vector, step length, the per-pixel turn, the final mapping.
const GTAO_PIXEL: Work = work(1.0, 6.0, 50.0);
/// Per slice: the slice frame (`gtao_slice`) and the two arcs (`gtao_side`).
const GTAO_SLICE: Work = work(0.0, 12.0, 130.0);
/// Per step: where it lands (`march_ray`) and its snap to the lattice; above exponent 1 a
/// power (`march_power`): two specials for pow (exp2 and log2) or a fourth root, one for
/// t^1.5, none for t².
const MARCH_STEP: Work = work(0.0, 0.0, 16.0);

fn march_power_specials(e: f32) -> f64 {
    match e {
        1.0 | 2.0 => 0.0,
        1.5 => 1.0,
        _ => 2.0,
    }
}
/// Per side of a step: the fetch, the view position (a multiply-add from the centre's), the
/// in-slice horizon cosine (the distance from the slice plane by one dot product) and its
/// falloff beyond R (`gtao_falloff`, a mix).
const GTAO_SIDE: Work = work(1.0, 1.0, 35.0);
/// The bitmask (bitmask.wgsl) per pixel beyond GTAO's: the positions in units of R.
const BITMASK_PIXEL: Work = work(0.0, 1.0, 12.0);
/// Per slice beyond GTAO's slice frame: the hemisphere's integral and the projections onto
/// the slice's (tangent, normal, axis); per run of occluded sectors, two edges (an inverse
/// square root, a square root and a polynomial each) and their running integrals;
/// [`BITMASK_RUNS`] runs a slice.
const BITMASK_SLICE: Work = work(0.0, 9.0, 130.0);
const BITMASK_RUN: Work = work(0.0, 4.0, 64.0);
/// Per step: its offset projected once for both sides.
const BITMASK_STEP: Work = work(0.0, 0.0, 11.0);
/// Per side of a step: the sample's view ray and the solid's direction in slice
/// coordinates; per depth layer: the fetch, the solid's stretch within R (a quadratic, one
/// square root, scaled so that it needs no division), both ends' pseudo-angle sectors (one
/// division for the two), the run of bits.
const BITMASK_SIDE: Work = work(0.0, 0.0, 24.0);
const BITMASK_SOLID: Work = work(1.0, 2.0, 59.0);
/// Runs of occluded sectors per slice assumed (an open surface has none, a corner one or
/// two).
pub const BITMASK_RUNS: f64 = 1.5;
/// The spatial denoiser (denoise.wgsl, merge.wgsl) per tap: the packed AO and geometry's
/// fetch, the normal's z from its unit length, the mirror at the border, the plane and
/// normal weights (one exp), the moments; per pixel: the centre, the tolerance, the 2 × 2
/// solve.
const DENOISE_TAP: Work = work(1.0, 2.0, 62.0);
const DENOISE_PIXEL: Work = work(1.0, 4.0, 40.0);
/// The prepare pass (prepare.wgsl): linearise the depth, normals from the caller's
/// texture or from the depth's four neighbours (normals_reconstruct.wgsl; two more when
/// a neighbour is sky), store; a second layer's depth linearised too.
const PREPARE_GIVEN: Work = work(2.0, 3.0, 30.0);
const PREPARE_RECONSTRUCT: Work = work(5.0, 6.0, 90.0);
const PREPARE_SECOND: Work = work(1.0, 1.0, 6.0);

/// The work of one AO invocation of `o`'s estimator; `None` for the estimators this model
/// does not count.
pub fn ao_work(o: &AoOptions, second_layer: bool) -> Option<Work> {
    let (d, s) = (o.directions as f64, o.steps as f64);
    let step = MARCH_STEP + work(0.0, march_power_specials(o.march_exponent), 0.0);
    let layers = if second_layer { 2.0 } else { 1.0 };
    match o.estimator {
        Estimator::Gtao => Some(GTAO_PIXEL + (GTAO_SLICE + (step + GTAO_SIDE * 2.0) * s) * d),
        Estimator::Bitmask => Some(
            GTAO_PIXEL
                + BITMASK_PIXEL
                + (GTAO_SLICE
                    + BITMASK_SLICE
                    + BITMASK_RUN * BITMASK_RUNS
                    + (step + BITMASK_STEP + (BITMASK_SIDE + BITMASK_SOLID * layers) * 2.0) * s)
                    * d,
        ),
        _ => None,
    }
}

fn denoise_work(period: u32) -> Work {
    let taps = ((period + 1) * (period + 1)) as f64;
    DENOISE_PIXEL + DENOISE_TAP * taps
}

/// Every pass of `o`'s frame at `size` pixels, prepare first, counted; `normals_given`:
/// the caller gives normals (else the prepare pass reconstructs them from the depth).
pub fn frame_cost(o: &AoOptions, size: [u32; 2], normals_given: bool) -> Vec<PassCost> {
    let plan = Plan::new(o, 1);
    let pixels = |s: [u32; 2]| s[0] as u64 * s[1] as u64;
    let texture_bytes = |r: Res| -> u64 {
        if r == Res::Output {
            return pixels(size) * AO_FORMAT.block_copy_size(None).unwrap_or(4) as u64;
        }
        plan.spec(r, size).map_or(0, |t| {
            let texel = t.format.block_copy_size(None).unwrap_or(16) as u64;
            (0..t.mips)
                .map(|m| pixels([1.max(t.size.0 >> m), 1.max(t.size.1 >> m)]))
                .sum::<u64>()
                * t.layers as u64
                * texel
        })
    };
    let factor = o.resolution.factor();
    let work_pixels = pixels([size[0].div_ceil(factor), size[1].div_ceil(factor)]);
    let mut out = Vec::new();
    let second = plan.second_layer();
    let prepare = Pass::Prepare {
        depth: crate::passes::shader::DepthBinding::Depth,
        store: plan.prepare_store,
        reconstruct: !normals_given,
        fit: false,
        second_layer: second,
    };
    let mut prepare_work = if !normals_given {
        PREPARE_RECONSTRUCT
    } else {
        PREPARE_GIVEN
    };
    if second {
        prepare_work = prepare_work + PREPARE_SECOND;
    }
    let inputs = pixels(size) * 4 * (1 + normals_given as u64 + second as u64);
    let targets: u64 = crate::frame::plan::prepare_targets(plan.prepare_store, second)
        .iter()
        .map(|t| texture_bytes(t.1))
        .sum();
    out.push(PassCost {
        label: prepare.label(),
        invocations: pixels(size),
        per_invocation: (factor == 1).then_some(prepare_work),
        bytes: inputs + targets,
    });
    for st in &plan.steps {
        out.push(PassCost {
            label: st.pass.label(),
            invocations: work_pixels,
            per_invocation: step_work(o, st, second),
            bytes: st.views.iter().map(|v| texture_bytes(v.1)).sum(),
        });
    }
    out
}

fn step_work(o: &AoOptions, st: &Step, second: bool) -> Option<Work> {
    match st.pass {
        Pass::AoFull { .. } | Pass::AoLayered { .. } => ao_work(o, second),
        Pass::Denoise { .. } if o.denoise == Denoise::Spatial => {
            Some(denoise_work(o.pattern_period()))
        }
        _ => None,
    }
}

/// A device's rates for the model: seconds per unit of each kind of work at its peak.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Device {
    pub name: &'static str,
    /// Seconds per invocation beyond its work (a CPU adapter's per-invocation overhead).
    pub invocation: f64,
    pub fetch: f64,
    pub alu: f64,
    pub special: f64,
    /// Seconds per byte of memory traffic; 0 where the fetch rate stands for it.
    pub byte: f64,
    /// Whether the units run at once (a GPU: a pass takes its slowest unit's time, the
    /// roofline) or in turn (a CPU running the shader as SIMD code: the sum).
    pub overlapped: bool,
}

/// NVIDIA H200 SXM (GH100, 132 SMs at a 1.98 GHz boost clock): 4 texture units per SM
/// (528 texels a clock), 4.8 TB/s of HBM3e (NVIDIA's H200 datasheet), 128 FP32 lanes per
/// SM (the datasheet's 67 TFLOPS counts an FMA as two), 16 special-function results per SM
/// a clock (CUDA C++ Programming Guide, arithmetic instruction throughput, compute
/// capability 9.0).
pub const H200: Device = Device {
    name: "H200 (published peaks)",
    invocation: 0.0,
    fetch: 1.0 / (528.0 * 1.98e9),
    alu: 1.0 / (132.0 * 128.0 * 1.98e9),
    special: 1.0 / (132.0 * 16.0 * 1.98e9),
    byte: 1.0 / 4.8e12,
    overlapped: true,
};

/// lavapipe (llvmpipe, LLVM 15, 256-bit SIMD) on the two cores of the machines this is
/// built on, by the dispatch-cost example's probes (an extra pass over 1280×720, medians of
/// four rounds, 2026-11-29): an invocation with its one store (rgba32float) 7 ns, a fetch
/// 1.3 ns, an operation 0.033 ns, a special-function operation 0.06 ns.
pub const LAVAPIPE: Device = Device {
    name: "lavapipe, 2 cores (measured probes)",
    invocation: 7.0e-9,
    fetch: 1.3e-9,
    alu: 0.033e-9,
    special: 0.06e-9,
    byte: 0.0,
    overlapped: false,
};

/// What bounds a pass on a device.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bound {
    Fetch,
    Bytes,
    Alu,
    Special,
    /// A CPU adapter: the sum of every kind of work.
    Sum,
}

impl Bound {
    pub fn name(self) -> &'static str {
        match self {
            Bound::Fetch => "texel fetches",
            Bound::Bytes => "memory",
            Bound::Alu => "arithmetic",
            Bound::Special => "special functions",
            Bound::Sum => "all (in turn)",
        }
    }
}

impl Device {
    /// The model's time for pass `p` in seconds and what bounds it; `None` where the pass's
    /// work is not counted.
    pub fn time(&self, p: &PassCost) -> Option<(f64, Bound)> {
        let w = p.per_invocation?;
        let n = p.invocations as f64;
        let parts = [
            (n * w.fetches * self.fetch, Bound::Fetch),
            (p.bytes as f64 * self.byte, Bound::Bytes),
            (n * w.alu * self.alu, Bound::Alu),
            (n * w.special * self.special, Bound::Special),
        ];
        if !self.overlapped {
            return Some((
                n * self.invocation + parts.iter().map(|t| t.0).sum::<f64>(),
                Bound::Sum,
            ));
        }
        parts.into_iter().max_by(|a, b| a.0.total_cmp(&b.0))
    }
}

#[cfg(test)]
#[path = "cost_tests.rs"]
mod tests;
