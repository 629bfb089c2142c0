//! What can go wrong on the GPU path, in words a person can act on.

/// The Debian packages that give a machine without a GPU driver the software Vulkan device
/// (lavapipe), named in every "no adapter" message.
pub const SOFTWARE_DRIVER_HINT: &str =
    "install a Vulkan driver (on Debian/Ubuntu, `apt-get install -y mesa-vulkan-drivers libvulkan1` gives the software device lavapipe)";

/// An error of the GPU backend.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No Vulkan adapter at all.
    #[error("no GPU adapter found (Vulkan); {SOFTWARE_DRIVER_HINT}")]
    NoAdapter,
    /// Adapters exist, none matches the requested name.
    #[error("no GPU adapter matches `{wanted}` (from {source_of_name}); adapters: {available}")]
    NoMatchingAdapter {
        /// The substring asked for.
        wanted: String,
        /// `--gpu-adapter` or `DYNRAY_GPU_ADAPTER`.
        source_of_name: &'static str,
        /// The adapters found, comma separated.
        available: String,
    },
    /// The adapter refused a device.
    #[error("GPU adapter `{adapter}` refused a device: {message}")]
    RequestDevice {
        /// Adapter name.
        adapter: String,
        /// wgpu's reason.
        message: String,
    },
    /// A buffer exceeds what the adapter can bind.
    #[error(
        "{what} needs {bytes} bytes, more than the {limit} bytes adapter `{adapter}` can bind in one storage buffer"
    )]
    TooLarge {
        /// The array.
        what: &'static str,
        /// Its size.
        bytes: u64,
        /// The adapter's `max_storage_buffer_binding_size`.
        limit: u64,
        /// Adapter name.
        adapter: String,
    },
    /// The frame or options ask for something the GPU strategies do not do.
    #[error("the GPU backend does not render {what}")]
    Unsupported {
        /// What, in words.
        what: String,
    },
    /// A kernel failed to compile or validate, or the device was lost during a command.
    #[error("GPU {what}: {message}")]
    Device {
        /// What was being done.
        what: &'static str,
        /// wgpu's message.
        message: String,
    },
}
