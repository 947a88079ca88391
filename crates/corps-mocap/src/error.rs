//! What can go wrong reading or streaming motion capture and retargeting it: one line each,
//! naming the file (or the stream) and the fault.

use thiserror::Error;

/// An error of motion-capture input or retargeting.
#[derive(Debug, Error)]
pub enum MocapError {
    /// A BVH file (or hierarchy) that cannot be used: the file, the line, the fault.
    #[error("{file}: line {line}: {message}")]
    Bvh {
        file: String,
        line: usize,
        message: String,
    },
    /// A file that cannot be read.
    #[error("{file}: {message}")]
    Io { file: String, message: String },
    /// A mapping file that cannot be used: the file and the fault.
    #[error("{file}: {message}")]
    Mapping { file: String, message: String },
    /// The live stream's socket failed.
    #[error("mocap stream {address}: {message}")]
    Stream { address: String, message: String },
}

/// Result of motion-capture input and retargeting.
pub type Result<T, E = MocapError> = std::result::Result<T, E>;
