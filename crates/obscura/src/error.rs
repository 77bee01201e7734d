//! The library's error type: one variant per kind of misuse, so callers can match on it.

/// Everything that can go wrong in obscura. New variants may be added in minor releases.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// No adapter could be found (no GPU driver and no software Vulkan driver).
    #[error("no graphics adapter found: {0}")]
    NoAdapter(String),
    /// The adapter refused to create a device.
    #[error("could not create a device on adapter `{adapter}`: {reason}")]
    DeviceCreation { adapter: String, reason: String },
    /// A settings field is outside its documented range.
    #[error("invalid setting `{field}` = {value}: {expected}")]
    InvalidSetting {
        field: &'static str,
        value: String,
        expected: &'static str,
    },
    /// The projection cannot describe a camera (zero or negative extent, NaN, near >= far, ...).
    #[error("invalid projection: {0}")]
    InvalidProjection(String),
    /// The depth convention does not fit the projection (for example an infinite far plane with an
    /// orthographic camera).
    #[error("depth convention {convention:?} cannot be used with {projection}")]
    ConventionMismatch {
        convention: crate::DepthConvention,
        projection: &'static str,
    },
    /// The viewport is empty, or does not fit inside the input textures.
    #[error("invalid viewport: {0}")]
    InvalidViewport(String),
    /// A requested size is beyond what the adapter supports.
    #[error("size {width}x{height} exceeds the adapter's maximum texture dimension {max}")]
    TooLarge { width: u32, height: u32, max: u32 },
    /// A caller's texture has the wrong size, usage, sample count or dimensions.
    #[error("invalid {what} texture: {reason}")]
    InvalidTexture { what: &'static str, reason: String },
    /// An input texture has a format the library cannot read.
    #[error("unsupported {what} texture format {format:?}; expected {expected}")]
    UnsupportedFormat {
        what: &'static str,
        format: wgpu::TextureFormat,
        expected: &'static str,
    },
    /// A depth map or its intrinsics cannot be used (see [`crate::depth_map`]).
    #[error("{0}")]
    InvalidDepthMap(String),
    /// wgpu reported a validation or internal error while recording or running obscura's work.
    #[error("GPU error: {0}")]
    Gpu(String),
    /// The device ran out of memory creating obscura's textures or running its passes
    /// (a smaller size, a lower resolution or fewer layers need less).
    #[error("GPU out of memory: {0}")]
    OutOfMemory(String),
    /// The device was lost (driver reset, out of memory, ...).
    #[error("GPU device lost: {0}")]
    DeviceLost(String),
}

impl From<wgpu::Error> for Error {
    fn from(e: wgpu::Error) -> Self {
        match e {
            wgpu::Error::OutOfMemory { .. } => Error::OutOfMemory(e.to_string()),
            _ => Error::Gpu(e.to_string()),
        }
    }
}

/// Shorthand for results whose error is [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
