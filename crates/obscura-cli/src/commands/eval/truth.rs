//! The ray-traced truth of a view: its trace settings, and the reference traced once and
//! then read from the cache.

use super::args::{EvalArgs, FalloffArg, TruthArg};
use crate::progress::tenths;
use obscura_eval::{cache, Bvh, Falloff, PixelSampling, ReferenceAo, TraceSettings};
use obscura_scene::{Camera, Mesh};
use std::time::Instant;

/// The trace settings `a` asks for at `radius`.
pub(super) fn trace_settings(a: &EvalArgs, radius: f32) -> TraceSettings {
    TraceSettings {
        radius,
        rays: a.rays,
        falloff: match a.falloff {
            FalloffArg::None => Falloff::None,
            FalloffArg::Quadratic => Falloff::Quadratic,
        },
        sampling: match a.truth {
            TruthArg::Centre => PixelSampling::Centre,
            TruthArg::Msaa4 => PixelSampling::Msaa4,
        },
    }
}

/// The view's reference: from the cache when it holds one for the scene file's `bytes`, the
/// camera, the size and `settings`; else traced (with progress) and stored.
pub(super) fn reference(
    a: &EvalArgs,
    bytes: &[u8],
    mesh: &Mesh,
    cam: &Camera,
    settings: &TraceSettings,
) -> ReferenceAo {
    let (w, h) = (a.width, a.height);
    let key = cache::key(bytes, cam, w, h, settings);
    let cpath = cache::path(&a.cache, key);
    if let Some(r) = cache::load(&cpath, w, h) {
        eprintln!("  reference: cached ({})", cpath.display());
        return r;
    }
    let t = Instant::now();
    let bvh = Bvh::new(obscura_eval::triangles(mesh));
    let r = obscura_eval::trace_view(&bvh, cam, w, h, settings, &tenths("reference", t));
    eprintln!(
        "  reference: {}x{} × {} rays in {:.1} s, mean standard error {:.4}",
        w,
        h,
        a.rays,
        t.elapsed().as_secs_f64(),
        r.mean_std_error
    );
    if let Err(e) = cache::store(&cpath, &r) {
        eprintln!("  warning: could not cache the reference: {e}");
    }
    r
}
