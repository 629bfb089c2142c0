//! Typed errors of the renderer: every variant names the file it is about.

use std::path::PathBuf;

/// Why an image could not be written.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The output extension names no format the renderer writes.
    #[error("{path}: unknown image format (use an extension .png, .bmp or .exr)")]
    UnknownFormat {
        /// The requested output file.
        path: PathBuf,
    },
    /// An AOV was asked for in a format that cannot hold raw floats.
    #[error("{path}: the {aov} AOV is written as EXR only (use an .exr output)")]
    AovNeedsExr {
        /// The requested output file.
        path: PathBuf,
        /// The AOV's name.
        aov: &'static str,
    },
    /// The film has no pixels, which no image format can hold.
    #[error("{path}: cannot write an empty {width}x{height} image")]
    EmptyImage {
        /// The requested output file.
        path: PathBuf,
        /// Film width.
        width: u32,
        /// Film height.
        height: u32,
    },
    /// Creating, writing or renaming the file failed.
    #[error("{path}: cannot write: {source}")]
    Io {
        /// The requested output file (not the temporary name).
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The image encoder refused the data.
    #[error("{path}: cannot encode image: {message}")]
    Encode {
        /// The requested output file.
        path: PathBuf,
        /// The encoder's message.
        message: String,
    },
}
