//! The errors physframes reports, and the exit code each maps to.

use std::path::PathBuf;

use crate::scene::{LoadError, SceneError};

/// Exit codes, documented in docs/cli.md: 0 success, 1 runtime failure, 2 bad input or
/// usage, 3 numerical blow-up, 130 stopped by Ctrl-C (143 by SIGTERM, 129 by SIGHUP).
pub mod exit {
    pub const SUCCESS: u8 = 0;
    pub const FAILURE: u8 = 1;
    pub const BAD_INPUT: u8 = 2;
    pub const BLOW_UP: u8 = 3;
    /// Set by [`crate::interrupt`]'s handler, which exits itself.
    pub const INTERRUPTED: u8 = crate::interrupt::EXIT_CODE;
    /// Set by the SIGTERM handler.
    pub const TERMINATED: u8 = crate::interrupt::TERMINATED;
    /// Set by the SIGHUP handler.
    pub const HUNG_UP: u8 = crate::interrupt::HUNG_UP;
}

/// Everything that can stop a command.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The scene file is not valid; nothing was written.
    #[error("{0}")]
    Scene(SceneError),
    /// The command line asks for something impossible; nothing was written.
    #[error("{0}")]
    Usage(String),
    /// A file could not be read or written.
    #[error("{context} {}: {source}", path.display())]
    Io {
        context: &'static str,
        path: PathBuf,
        source: std::io::Error,
    },
    /// The simulation's state stopped being finite; frames written before stay valid.
    #[error("{0}")]
    BlowUp(String),
    /// Anything else that went wrong at run time.
    #[error("{0}")]
    Runtime(String),
}

impl Error {
    /// Returns the process exit code for this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            Error::Scene(_) | Error::Usage(_) => exit::BAD_INPUT,
            Error::BlowUp(_) => exit::BLOW_UP,
            Error::Io { .. } | Error::Runtime(_) => exit::FAILURE,
        }
    }

    /// Wraps an I/O error with what was being done and to which path.
    pub fn io(context: &'static str, path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            context,
            path: path.into(),
            source,
        }
    }
}

impl From<LoadError> for Error {
    fn from(e: LoadError) -> Self {
        match e {
            // A scene file that cannot be read is bad input, like one that is invalid.
            LoadError::Io { path, source } => Error::Usage(format!(
                "cannot read scene file {}: {source}",
                path.display()
            )),
            LoadError::Invalid(e) => Error::Scene(e),
        }
    }
}

/// The result type of every command.
pub type Result<T, E = Error> = std::result::Result<T, E>;
