//! Why the GPU tracer could not run.

/// Why the GPU tracer could not run.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No adapter at all (no Vulkan/Metal/DX12 driver; on Debian install
    /// `mesa-vulkan-drivers` for the software one).
    #[error("no GPU adapter found ({0}); on Debian, `apt-get install mesa-vulkan-drivers` gives a software one")]
    NoAdapter(String),
    /// The adapter would not give a device.
    #[error("the GPU adapter '{adapter}' refused a device: {message}")]
    NoDevice {
        /// The adapter's name.
        adapter: String,
        /// wgpu's message.
        message: String,
    },
    /// The shader failed to compose (a bug in the shader or its defs).
    #[error("the tracer shader does not compose with defs {defs:?}: {message}")]
    Shader {
        /// The defs that were on.
        defs: Vec<&'static str>,
        /// The composer's message.
        message: String,
    },
    /// wgpu reported a validation error.
    #[error("wgpu validation error: {0}")]
    Validation(String),
    /// Settings no tracer takes (see `TraceSettings::check`), or a buffer
    /// past the device's limits.
    #[error("{0}")]
    Settings(String),
    /// Reading the image back failed.
    #[error("reading the image back from the GPU failed: {0}")]
    Readback(String),
}
