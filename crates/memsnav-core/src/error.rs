//! The typed errors of memsnav-core.

use thiserror::Error as ThisError;

/// Everything that can go wrong in memsnav-core.
#[derive(Debug, Clone, PartialEq, ThisError)]
pub enum Error {
    /// An argument has the wrong shape, a non-finite value or an
    /// out-of-range value. `argument` is the caller-visible name.
    #[error("{argument}: {reason}")]
    InvalidArgument {
        /// The argument's name as the caller wrote it.
        argument: String,
        /// What is wrong with it.
        reason: String,
    },

    /// The data cannot determine a parameter (rank-deficient or badly
    /// conditioned least-squares problem).
    #[error("{axis} axis: {parameter} cannot be determined from the data: {reason}")]
    Unobservable {
        /// The sensor axis of the fit.
        axis: String,
        /// The parameter that cannot be determined.
        parameter: String,
        /// Why (rank, condition number).
        reason: String,
    },

    /// An estimator diverged: its covariance stopped being symmetric
    /// positive definite, or its state became non-finite.
    #[error("filter diverged at t = {time_s} s: {reason}")]
    Divergence {
        /// When it diverged, s.
        time_s: f64,
        /// What was found.
        reason: String,
    },

    /// A file could not be parsed. `line` is 1-based, 0 when unknown.
    #[error("{file}:{line}: {reason}")]
    Parse {
        /// The file's name as given.
        file: String,
        /// The line, 1-based; 0 when unknown.
        line: usize,
        /// What is wrong there.
        reason: String,
    },

    /// A binary file could not be parsed; `byte_offset` is where the bad
    /// field starts.
    #[error("{file}: byte {byte_offset}: {reason}")]
    ParseBinary {
        /// The file's name as given.
        file: String,
        /// Where the bad field starts, bytes from the file's start.
        byte_offset: u64,
        /// What is wrong there.
        reason: String,
    },

    /// The operating system refused a file operation.
    #[error("{path}: {reason}")]
    Io {
        /// The path as given.
        path: String,
        /// The operating system's reason.
        reason: String,
    },

    /// The caller asked a long computation to stop.
    #[error("interrupted")]
    Interrupted,
}

impl Error {
    /// Shorthand for [`Error::InvalidArgument`].
    pub fn invalid(argument: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::InvalidArgument {
            argument: argument.into(),
            reason: reason.into(),
        }
    }
}

/// `Result` with the memsnav [`Error`].
pub type Result<T> = std::result::Result<T, Error>;
