//! The rig's options: [`RigOptions`] and the one table every option is described in
//! ([`table::OPTIONS`]).
//!
//! Each option is one row of the table: its JS path (`filter.minCutoff`), type, range or
//! values, default, a one-line description and the struct field it sets. From the table come
//!
//! * [`RigOptions::default`] (every row's default),
//! * decoding from JSON text or a JS object ([`RigOptions::from_json`], [`RigOptions::from_value`];
//!   serde reads the value, the table checks and places it; errors name the path),
//! * validation of options built in Rust ([`RigOptions::validate`], which [`crate::Rig::new`]
//!   calls),
//! * [`option_descriptions`] (the npm package's `optionDescriptions()`, the demo's panel),
//! * the TypeScript `HandRigOptions` type and the options reference page
//!   ([`generated`]; tests fail when the committed files are stale).
//!
//! The option structs themselves (`FilterOptions`, `ContactOptions`, ...) live with the code
//! that reads them; they carry no defaults, ranges or names of their own.

mod decode;
pub mod generated;
pub mod table;

use crate::align::{AlignPoint, AlignmentOptions};
use crate::body::CalibrationOptions;
use crate::contact::{ContactOptions, FaceAnchorsOption};
use crate::error::{Error, Result};
pub use crate::face::FaceOptions;
use crate::filter::{DropoutOptions, FilterOptions};
use crate::hand::{HandStrategy, RetargetOptions};
use crate::humanoid::bones::Finger;
use crate::ik::{ArmIdle, ArmOptions, ArmSolver};
pub use crate::input::hand_wrist::HandsOnlyOptions;
use crate::input::mediapipe::CameraMapping;
pub use crate::input::mediapipe::CameraOptions;
pub use crate::legs::{LegOptions, LegRest};
use crate::solve::least_squares::Settings;
use crate::torso::TorsoSource;

pub(crate) use decode::describe;
pub use table::{Kind, OptionSpec, Value, OPTIONS};

/// Everything a [`crate::Rig`] can be told (JS: the `options` object; see [`table::OPTIONS`]
/// for each field's path, range, default and meaning).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigOptions {
    /// The image given to MediaPipe was flipped horizontally (selfie view).
    pub input_mirrored: bool,
    /// The avatar mirrors the user, VTuber style: the user's right hand drives the avatar's
    /// left.
    pub mirror: bool,
    /// How hands are solved.
    pub hand_strategy: HandStrategy,
    /// Fingertip alignment.
    pub alignment: AlignmentOptions,
    /// Which arm IK solver reaches the wrist target.
    pub arm_solver: ArmSolver,
    /// Options every arm solver shares: the shoulder's help on far reaches, the forearm's
    /// share of the hand's twist, the wrist limits.
    pub arm: ArmOptions,
    /// Body-scale calibration from pose landmarks.
    pub calibration: CalibrationOptions,
    /// Hands whose handedness score is below this are ignored.
    pub min_hand_score: f32,
    /// What to do with a hand whose label contradicts the pose.
    pub handedness: HandednessPolicy,
    /// One Euro filtering of the landmarks.
    pub filter: FilterOptions,
    /// Holding and easing over tracking loss.
    pub dropout: DropoutOptions,
    /// Where the torso comes from (see [`crate::torso`]).
    pub torso: TorsoSource,
    /// Self-contact retargeting: face, hand-to-hand, body colliders.
    pub contact: ContactOptions,
    /// The objective of `handStrategy: "retarget"` (seed 003).
    pub retarget: RetargetOptions,
    /// Arms from hands alone: the camera and framing assumed (see
    /// [`crate::input::hand_wrist`]).
    pub hands_only: HandsOnlyOptions,
    /// The face: expressions, look-at and head from a face tracker (issue 50).
    pub face: FaceOptions,
    /// Legs from the pose's lower body (see [`crate::legs`]).
    pub legs: LegOptions,
    /// The camera's orientation to gravity (its pitch).
    pub camera: CameraOptions,
}

/// How a hand whose MediaPipe label contradicts the pose is treated (JS:
/// `options.handedness`). A label contradicts the pose when the hand's wrist, in the image,
/// is nearer the other side's pose wrist than half its distance to its own side's (both pose
/// wrists visible; needs the hands' and the pose's image landmarks of the same image).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HandednessPolicy {
    /// `"reassign"`: the hand drives the side the pose says (read as that hand).
    Reassign,
    /// `"drop"`: the hand is ignored this frame.
    Drop,
    /// `"trust"`: MediaPipe's label decides (no pose check).
    Trust,
}

/// An enum option: its JS names, in the order the option lists them.
pub trait OptionEnum: Sized + Copy {
    /// Every value's JS name.
    const NAMES: &'static [&'static str];
    /// The JS name.
    fn name(self) -> &'static str;
    /// The value of a JS name.
    fn from_name(name: &str) -> Option<Self>;
}

/// `impl OptionEnum` from `Type { Variant = "name", ... }`.
macro_rules! option_enum {
    ($($ty:ty { $($variant:ident = $name:literal),+ $(,)? })+) => {$(
        impl OptionEnum for $ty {
            const NAMES: &'static [&'static str] = &[$($name),+];
            fn name(self) -> &'static str {
                match self {
                    $(<$ty>::$variant => $name,)+
                    #[allow(unreachable_patterns)]
                    _ => Self::NAMES[0],
                }
            }
            fn from_name(name: &str) -> Option<Self> {
                match name {
                    $($name => Some(<$ty>::$variant),)+
                    _ => None,
                }
            }
        }
    )+};
}

option_enum! {
    HandStrategy { Analytic = "analytic", Retarget = "retarget" }
    ArmSolver { TwoBone = "twoBone", Fabrik = "fabrik", Ccd = "ccd" }
    ArmIdle { Down = "down", TPose = "tpose" }
    LegRest { Standing = "standing", Seated = "seated" }
    AlignPoint { Dip = "dip", Tip = "tip" }
    Finger { Thumb = "thumb", Index = "index", Middle = "middle", Ring = "ring", Little = "little" }
    HandednessPolicy { Reassign = "reassign", Drop = "drop", Trust = "trust" }
    TorsoSource { Off = "off", Frame = "frame", Pose = "pose" }
}

impl HandednessPolicy {
    /// The JS name.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        self.name()
    }
}

impl RigOptions {
    /// Every field at a neutral value, before the table's defaults: what
    /// [`RigOptions::default`] starts from (each field is then set by its row).
    const UNSET: RigOptions = RigOptions {
        input_mirrored: false,
        mirror: false,
        hand_strategy: HandStrategy::Analytic,
        alignment: AlignmentOptions {
            enabled: false,
            finger: Finger::Index,
            point: AlignPoint::Dip,
            weight: 0.0,
        },
        arm_solver: ArmSolver::TwoBone,
        arm: ArmOptions {
            shoulder_angle: 0.0,
            shoulder_reach: 0.0,
            forearm_twist: 0.0,
            wrist_limits: false,
            max_turn_speed: 0.0,
            idle: ArmIdle::Down,
        },
        calibration: CalibrationOptions {
            body_scale: None,
            frames: 0,
            min_visibility: 0.0,
        },
        min_hand_score: 0.0,
        handedness: HandednessPolicy::Reassign,
        filter: FilterOptions {
            enabled: false,
            min_cutoff: 0.0,
            beta: 0.0,
            d_cutoff: 0.0,
        },
        dropout: DropoutOptions {
            enabled: false,
            hold_ms: 0.0,
            fade_out_ms: 0.0,
            fade_in_ms: 0.0,
        },
        torso: TorsoSource::Frame,
        contact: ContactOptions {
            enabled: false,
            radius: 0.0,
            weight: 0.0,
            hands: false,
            face_anchors: FaceAnchorsOption::NONE,
            colliders: false,
            torso_radius: None,
            head_radius: None,
            depth_trust: 0.0,
            max_speed: 0.0,
        },
        retarget: RetargetOptions {
            tip_weights: [0.0; 5],
            joint_weight: 0.0,
            pinch_weight: 0.0,
            pinch_distance: 0.0,
            spatial_weight: 0.0,
            temporal_weight: 0.0,
            temporal_speed: 0.0,
            settings: Settings {
                max_iterations: 0,
                step_tolerance: 0.0,
            },
        },
        hands_only: HandsOnlyOptions {
            enabled: false,
            fov: 0.0,
            distance: 0.0,
            shoulder_y: 0.0,
        },
        face: FaceOptions {
            enabled: false,
            smoothing: false,
            min_cutoff: 0.0,
            beta: 0.0,
            blink_open_time: 0.0,
            calibration_time: 0.0,
            neck_share: 0.0,
            head: false,
        },
        legs: LegOptions {
            enabled: false,
            min_visibility: 0.0,
            move_hips: false,
            plant: false,
            rest: LegRest::Standing,
        },
        camera: CameraOptions { pitch: None },
    };

    /// Reads options from JSON text: an object of the camelCase paths of [`table::OPTIONS`]
    /// (JS: `{ mirror: true, arm: { shoulderAngle: 0.3 } }`), nested or dotted
    /// (`"arm.shoulderAngle"`), each optional (missing ones keep their defaults), enums as
    /// their JS strings, `null` for an unset optional number, `false`/`true` for a group with
    /// an `enabled` switch (`filter: false`).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the field (`options.arm.shoulderAngle`): text that is
    /// not JSON, a wrong type, an unknown name (with a suggestion), an unknown enum value, a
    /// number out of range, a path given twice.
    pub fn from_json(text: &str) -> Result<RigOptions> {
        let value: serde_json::Value = serde_json::from_str(text)
            .map_err(|e| Error::invalid("options", format!("not valid JSON: {e}")))?;
        RigOptions::from_value(&value)
    }

    /// Reads options from a JSON value (the wasm binding reads the JS options object into one
    /// with serde-wasm-bindgen). `null` is the defaults. See [`RigOptions::from_json`].
    ///
    /// # Errors
    /// As [`RigOptions::from_json`].
    pub fn from_value(value: &serde_json::Value) -> Result<RigOptions> {
        let mut options = RigOptions::default();
        decode::apply(value, &mut options)?;
        Ok(options)
    }

    /// Checks every field against its row of the table (ranges, whole numbers, finite
    /// numbers): what [`crate::Rig::new`] runs on options built in Rust.
    ///
    /// # Errors
    /// The first field out of range, named by its JS path (`options.filter.minCutoff`).
    pub fn validate(&self) -> Result<()> {
        for spec in OPTIONS {
            decode::check(spec, (spec.get)(self))?;
        }
        Ok(())
    }

    /// The defaults with no filtering, no dropout easing, no limit on how fast contact moves a
    /// hand and none on how fast an arm turns: every frame is solved on its own, exactly from
    /// its input (offline processing, evaluations, tests with exact answers).
    #[must_use]
    pub fn per_frame() -> Self {
        let mut o = RigOptions::default();
        o.filter.enabled = false;
        o.dropout.enabled = false;
        o.contact.max_speed = 0.0;
        o.arm.max_turn_speed = 0.0;
        o.face.smoothing = false;
        o
    }

    /// How MediaPipe input maps onto the avatar.
    #[must_use]
    pub fn camera(&self) -> CameraMapping {
        CameraMapping {
            input_mirrored: self.input_mirrored,
            mirror: self.mirror,
        }
    }
}

impl Default for RigOptions {
    /// Every row's default ([`table::OPTIONS`]).
    fn default() -> Self {
        let mut o = RigOptions::UNSET;
        for spec in OPTIONS {
            (spec.set)(&mut o, spec.default);
        }
        o
    }
}

/// `impl Default` for a group of options: its part of [`RigOptions::default`].
macro_rules! group_default {
    ($($ty:ty => $($field:ident).+),+ $(,)?) => {$(
        impl Default for $ty {
            /// This one's part of [`RigOptions::default`] (from [`table::OPTIONS`]).
            fn default() -> Self {
                RigOptions::default().$($field).+
            }
        }
    )+};
}

group_default! {
    AlignmentOptions => alignment,
    ArmOptions => arm,
    CalibrationOptions => calibration,
    FilterOptions => filter,
    DropoutOptions => dropout,
    ContactOptions => contact,
    RetargetOptions => retarget,
    HandsOnlyOptions => hands_only,
    FaceOptions => face,
    LegOptions => legs,
    CameraOptions => camera,
    HandStrategy => hand_strategy,
    ArmSolver => arm_solver,
    AlignPoint => alignment.point,
    HandednessPolicy => handedness,
    TorsoSource => torso,
}

/// Checks the rows under `prefix` (`"arm."`) of the options `place` builds from the defaults.
fn validate_group(prefix: &str, place: impl FnOnce(&mut RigOptions)) -> Result<()> {
    let mut o = RigOptions::default();
    place(&mut o);
    for spec in OPTIONS.iter().filter(|s| s.path.starts_with(prefix)) {
        decode::check(spec, (spec.get)(&o))?;
    }
    Ok(())
}

impl ArmOptions {
    /// Checks every field against its row of the table (the arm solvers' own setup check).
    ///
    /// # Errors
    /// A field out of range, named `options.arm.<field>`.
    pub fn validate(&self) -> Result<()> {
        validate_group("arm.", |o| o.arm = *self)
    }
}

/// The type of one option, for building UIs and docs from [`option_descriptions`].
#[derive(Clone, Debug, PartialEq)]
pub enum OptionKind {
    /// `true` / `false`.
    Boolean {
        /// Default value.
        default: bool,
    },
    /// One of a fixed set of strings.
    Enum {
        /// The accepted values.
        values: Vec<&'static str>,
        /// Default value.
        default: &'static str,
    },
    /// A number in `min..=max`; `default` absent means "unset" (e.g. automatic calibration).
    Number {
        /// Smallest accepted value.
        min: f32,
        /// Largest accepted value.
        max: f32,
        /// Default value, if any.
        default: Option<f32>,
        /// Suggested UI step.
        step: f32,
        /// Only whole numbers are accepted.
        integer: bool,
    },
    /// An object of named points, `{ name: [x, y, z] }` (meters), each optional; no default
    /// (derived values apply where a point is not given).
    Points {
        /// The accepted names.
        names: Vec<&'static str>,
    },
    /// A fixed-length array of numbers, each in `min..=max`.
    Numbers {
        /// How many numbers.
        len: usize,
        /// Smallest accepted value.
        min: f32,
        /// Largest accepted value.
        max: f32,
        /// Default values.
        default: Vec<f32>,
    },
}

/// One option of [`RigOptions`]: its JS path (dot-separated, e.g. `alignment.weight`), type,
/// range, default and a one-line description.
#[derive(Clone, Debug, PartialEq)]
pub struct OptionDescription {
    /// Dot-separated JS path, e.g. `"alignment.finger"`.
    pub path: &'static str,
    /// Type, accepted values and default.
    pub kind: OptionKind,
    /// What it does.
    pub description: &'static str,
}

/// Every option a [`crate::Rig`] accepts, for UIs (the demo builds its control panel from
/// this) and docs: [`table::OPTIONS`] as plain data.
#[must_use]
pub fn option_descriptions() -> Vec<OptionDescription> {
    OPTIONS.iter().map(OptionSpec::describe).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_pass_their_own_validation_and_round_trip_through_json() {
        let d = RigOptions::default();
        d.validate().expect("defaults are valid");
        let mut text = String::from("{");
        for (k, spec) in OPTIONS.iter().enumerate() {
            if k > 0 {
                text.push(',');
            }
            text.push_str(&format!("\"{}\": {}", spec.path, spec.default.to_json()));
        }
        text.push('}');
        assert_eq!(RigOptions::from_json(&text).expect("defaults as JSON"), d);
    }

    #[test]
    fn every_row_sets_its_own_field() {
        // Each row, set to a non-default valid value, changes what it reads back and nothing
        // any other row reads.
        let d = RigOptions::default();
        for spec in OPTIONS {
            let Some(other) = spec.other_valid_value() else {
                continue;
            };
            let mut o = d;
            (spec.set)(&mut o, other);
            assert_eq!((spec.get)(&o), other, "{}", spec.path);
            for rest in OPTIONS.iter().filter(|r| r.path != spec.path) {
                assert_eq!(
                    (rest.get)(&o),
                    (rest.get)(&d),
                    "{} moved {}",
                    spec.path,
                    rest.path
                );
            }
        }
    }

    #[test]
    fn enum_names_agree_with_the_types_own_names() {
        for s in ArmSolver::ALL {
            assert_eq!(s.name(), s.as_str());
        }
        for s in TorsoSource::ALL {
            assert_eq!(s.name(), s.as_str());
        }
        for f in Finger::ALL {
            assert_eq!(f.name(), f.as_str());
            assert_eq!(<Finger as OptionEnum>::from_name(f.as_str()), Some(f));
        }
    }

    #[test]
    fn out_of_range_options_built_in_rust_are_rejected_by_path() {
        let mut o = RigOptions::default();
        o.filter.min_cutoff = 0.0;
        let e = o.validate().unwrap_err().to_string();
        assert!(e.starts_with("options.filter.minCutoff:"), "{e}");
        let mut o = RigOptions::default();
        o.calibration.frames = 0;
        let e = o.validate().unwrap_err().to_string();
        assert!(e.starts_with("options.calibration.frames:"), "{e}");
        let mut o = RigOptions::default();
        o.retarget.tip_weights[2] = f32::NAN;
        let e = o.validate().unwrap_err().to_string();
        assert!(e.starts_with("options.retarget.tipWeights[2]:"), "{e}");
    }
}
