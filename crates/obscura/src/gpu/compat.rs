//! What differs between the wgpu majors obscura builds on (the features `wgpu30` and
//! `wgpu29`, Cargo.toml): wgpu 30's changes that the library meets, one function each.

use crate::{Error, Result};

/// The bytes of a mapped buffer slice. wgpu 30 returns the mapping as a `Result`; wgpu 29
/// returns it (and panics on a bad mapping itself).
pub(crate) fn mapped_bytes(slice: &wgpu::BufferSlice<'_>) -> Result<Vec<u8>> {
    #[cfg(feature = "wgpu30")]
    let bytes = slice
        .get_mapped_range()
        .map_err(|e| Error::Gpu(e.to_string()))?
        .to_vec();
    #[cfg(not(feature = "wgpu30"))]
    let bytes = slice.get_mapped_range().to_vec();
    Ok::<_, Error>(bytes)
}
