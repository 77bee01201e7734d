//! The CPU reference of every pass, gathered under one name for tests. Each pass's mirror
//! lives beside its WGSL in `src/passes/<pass>/mod.rs`, written to read like the WGSL (same
//! names, same order of operations). Slow; not for production.

pub use crate::passes::denoise::*;
pub use crate::passes::estimators::*;
pub use crate::passes::lights::*;
pub use crate::passes::prepare::*;
pub use crate::passes::pyramid::*;
pub use crate::passes::ssdo::*;
pub use crate::passes::temporal::*;
pub use crate::passes::upsample::*;
