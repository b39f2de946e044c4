//! Errors. Every message names the offending field and the problem, so the wasm layer can pass
//! it to JS unchanged as an `Error` message.

use core::fmt;

/// What went wrong, with the path of the offending input field (e.g. `hands[0].worldLandmarks[7]`).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// A field is missing, has the wrong type, wrong length or a non-finite number.
    InvalidInput {
        /// Path of the field, JS-style (`frame.hands[1].worldLandmarks`).
        field: String,
        /// What is wrong with it.
        problem: String,
    },
    /// A bone name is not one of the 55 VRM 1.0 humanoid bone names.
    UnknownBone(String),
    /// A bone VRM 1.0 requires is not in the rest pose.
    MissingRequiredBones(Vec<&'static str>),
    /// A `.vrm` file could not be read.
    Vrm(String),
    /// A glTF humanoid (`HandRig.fromGltf`: `.glb` or `.vrm`) could not be read or bound.
    Gltf(String),
    /// The input is well-formed but geometrically unusable (e.g. a collapsed palm).
    Degenerate {
        /// Path of the field.
        field: String,
        /// What is degenerate.
        problem: String,
    },
}

impl Error {
    /// Shorthand for [`Error::InvalidInput`].
    pub fn invalid(field: impl Into<String>, problem: impl Into<String>) -> Self {
        Error::InvalidInput {
            field: field.into(),
            problem: problem.into(),
        }
    }

    /// Shorthand for [`Error::Vrm`]: a `.vrm` / GLB file that cannot be read.
    pub fn vrm(msg: impl Into<String>) -> Self {
        Error::Vrm(msg.into())
    }

    /// Shorthand for [`Error::Degenerate`].
    pub fn degenerate(field: impl Into<String>, problem: impl Into<String>) -> Self {
        Error::Degenerate {
            field: field.into(),
            problem: problem.into(),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::InvalidInput { field, problem } => write!(f, "{field}: {problem}"),
            Error::UnknownBone(name) => write!(
                f,
                "restPose.bones: unknown bone name \"{name}\" (expected a VRM 1.0 humanoid bone name such as \"leftHand\")"
            ),
            Error::MissingRequiredBones(names) => write!(
                f,
                "restPose.bones: missing required bone(s) {}",
                names.join(", ")
            ),
            Error::Vrm(msg) => write!(f, "vrm: {msg}"),
            Error::Gltf(msg) => write!(f, "gltf: {msg}"),
            Error::Degenerate { field, problem } => write!(f, "{field}: degenerate input: {problem}"),
        }
    }
}

impl std::error::Error for Error {}

/// Result alias.
pub type Result<T, E = Error> = core::result::Result<T, E>;

impl From<handrig_gltf::error::Error> for Error {
    fn from(e: handrig_gltf::error::Error) -> Self {
        match e {
            handrig_gltf::error::Error::Vrm(msg) => Error::Vrm(msg),
        }
    }
}
