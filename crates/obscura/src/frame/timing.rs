//! Timing one frame pass by pass, for benchmarks ([`crate::Ao::run_timed`]): the wall clock
//! around each pass's own submit + wait on adapters whose timestamps do not bracket
//! dispatches (lavapipe), GPU timestamp queries elsewhere.

use crate::gpu::pipeline::Compiled;
#[cfg(not(target_arch = "wasm32"))]
use crate::{Error, Result};

/// How [`crate::Ao::run_timed`] measures each pass.
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

/// One recorded pass: its pipeline, bind group and workgroups.
pub(crate) type PassCall<'a> = (&'a Compiled, wgpu::BindGroup, [u32; 3]);

/// Runs `passes` and returns each pass's label and milliseconds, measured as `timing` says.
/// Creates its query resources per call. Native only (it blocks).
#[cfg(not(target_arch = "wasm32"))]
pub(crate) fn time_passes(
    ctx: &crate::GpuContext,
    passes: &[PassCall<'_>],
    timing: Timing,
) -> Result<Vec<(&'static str, f64)>> {
    let dispatch = |enc: &mut wgpu::CommandEncoder,
                    (c, bg, d): &PassCall<'_>,
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
            for p in passes {
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
            let resolved = buffer(wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC);
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
