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

/// A number in an error message, written without `core::fmt`'s float formatting (`f32`'s and
/// `f64`'s `Display` link Grisu and Dragon, about 8 KB of the gzipped `.wasm`): the shortest
/// digits that read back as the same number, by zmij (the float writer serde_json already
/// brings into the `.wasm`), as Rust's `{}` writes the numbers messages show (`1.5`, `0.01`,
/// `-3`, `3.1415927`: no `.0` on a whole number); very large and very small numbers in
/// exponent form as JavaScript writes them (`1e+20`, `1e-6`); `NaN`, `inf` and `-inf`.
#[derive(Clone, Copy, Debug)]
pub struct Num {
    x: f64,
    single: bool,
}

impl Num {
    /// An `f32`, written with the digits that read back as the same `f32`.
    pub fn f32(x: f32) -> Self {
        Num {
            x: x as f64,
            single: true,
        }
    }

    /// An `f64`, written with the digits that read back as the same `f64`.
    pub fn f64(x: f64) -> Self {
        Num { x, single: false }
    }
}

impl From<f32> for Num {
    fn from(x: f32) -> Self {
        Num::f32(x)
    }
}

impl From<f64> for Num {
    fn from(x: f64) -> Self {
        Num::f64(x)
    }
}

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut buffer = zmij::Buffer::new();
        let text = if self.single {
            buffer.format(self.x as f32)
        } else {
            buffer.format(self.x)
        };
        // `{}` writes a whole number without the point.
        f.write_str(text.strip_suffix(".0").unwrap_or(text))
    }
}

#[cfg(test)]
mod tests {
    use super::Num;

    #[test]
    fn numbers_read_as_rust_writes_them() {
        let f32s = [
            0.0f32,
            -0.0,
            1.0,
            -1.0,
            1.5,
            0.1,
            0.01,
            0.3,
            2.5e-3,
            100.0,
            1e6,
            123456.7,
            -3.0,
            core::f32::consts::PI,
            -core::f32::consts::FRAC_PI_2,
            0.123_456_79,
            16.0 / 9.0,
            99.99,
            0.05,
        ];
        for x in f32s {
            assert_eq!(Num::f32(x).to_string(), format!("{x}"), "f32 {x:?}");
        }
        let f64s = [
            0.0f64,
            1.0,
            1.5,
            0.1,
            0.3,
            0.1 + 0.2,
            -2.75,
            1234.5678,
            9.999_999_999e15,
            core::f64::consts::E,
            4.0e-3,
            12345678901234.5,
        ];
        for x in f64s {
            assert_eq!(Num::f64(x).to_string(), format!("{x}"), "f64 {x:?}");
        }
    }

    /// serde's own type errors (serde-wasm-bindgen's among them) write their float with zmij
    /// in the patched serde_core (vendor/serde_core/PATCHED.md), as serde's `{}` did.
    #[test]
    fn serde_type_errors_still_show_the_float() {
        use serde::de::{value::Error as DeError, Error as _, Unexpected};
        let msg = |x| DeError::invalid_type(Unexpected::Float(x), &"a string").to_string();
        assert_eq!(
            msg(1.5),
            "invalid type: floating point `1.5`, expected a string"
        );
        assert_eq!(
            msg(-2.0),
            "invalid type: floating point `-2.0`, expected a string"
        );
        assert_eq!(
            msg(0.1),
            "invalid type: floating point `0.1`, expected a string"
        );
        assert!(msg(f64::NAN).contains("`NaN`"), "{}", msg(f64::NAN));
        assert!(msg(1e300).contains("`1e"), "{}", msg(1e300));
    }

    #[test]
    fn numbers_out_of_the_plain_range_and_not_finite() {
        assert_eq!(Num::f64(1e20).to_string(), "1e+20");
        assert_eq!(Num::f64(-2.5e-9).to_string(), "-2.5e-9");
        assert_eq!(Num::f32(f32::MAX).to_string(), "3.4028235e+38");
        assert_eq!(Num::f32(1e15).to_string(), "1e+15");
        assert_eq!(Num::f64(1e-6).to_string(), "1e-6");
        assert_eq!(
            Num::f64(f64::MIN_POSITIVE).to_string(),
            "2.2250738585072014e-308"
        );
        assert_eq!(Num::f64(5e-324).to_string(), "5e-324");
        assert_eq!(Num::f32(f32::NAN).to_string(), "NaN");
        assert_eq!(Num::f32(f32::INFINITY).to_string(), "inf");
        assert_eq!(Num::f64(f64::NEG_INFINITY).to_string(), "-inf");
    }
}
