//! The one error of reading a glTF document: a message naming the part of the file and the
//! problem (handrig turns it into its `Error::Vrm`).

use core::fmt;

/// A malformed file: what and where.
#[derive(Clone, Debug, PartialEq)]
pub enum Error {
    /// The message (handrig's `Error::Vrm` carries it unchanged).
    Vrm(String),
}

impl Error {
    /// Shorthand for [`Error::Vrm`].
    pub fn vrm(msg: impl Into<String>) -> Self {
        Error::Vrm(msg.into())
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Vrm(msg) => write!(f, "vrm: {msg}"),
        }
    }
}

impl std::error::Error for Error {}

/// `Result` with [`Error`].
pub type Result<T> = core::result::Result<T, Error>;
