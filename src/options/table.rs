//! The option table: one row per option of [`RigOptions`] (JS path, type, range or values,
//! default, one-line description, the field it sets). Everything else about options is
//! derived from it (see [`crate::options`]).

use crate::contact::{
    FaceAnchor, FaceAnchorsOption, ANCHORS, MAX_ANCHOR_OFFSET, MAX_COLLIDER_RADIUS,
};
use crate::hand::HandStrategy;
use crate::ik::{ArmIdle, ArmSolver};
use crate::legs::LegRest;
use crate::torso::TorsoSource;

use super::{HandednessPolicy, OptionDescription, OptionEnum, OptionKind, RigOptions};
use crate::align::AlignPoint;
use crate::error::Num;
use crate::humanoid::bones::Finger;

/// The type and accepted values of an option.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    /// `true` / `false`.
    Bool,
    /// One of these strings.
    Enum(&'static [&'static str]),
    /// A number in `min..=max`.
    Number {
        /// Smallest accepted value.
        min: f32,
        /// Largest accepted value.
        max: f32,
        /// Suggested UI step.
        step: f32,
        /// Only whole numbers.
        integer: bool,
        /// `null` (unset) is accepted, and is the default when the default is `None`.
        optional: bool,
    },
    /// An object of named points `{ name: [x, y, z] }`, each optional, every coordinate
    /// within `-limit..=limit`.
    Points {
        /// The accepted names.
        names: &'static [&'static str],
        /// Largest coordinate magnitude.
        limit: f32,
    },
    /// An array of `len` numbers, each in `min..=max`.
    Numbers {
        /// How many.
        len: usize,
        /// Smallest accepted value.
        min: f32,
        /// Largest accepted value.
        max: f32,
    },
}

/// An option's value, as the table's accessors read and write it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// [`Kind::Bool`].
    Bool(bool),
    /// [`Kind::Enum`]: the JS name.
    Enum(&'static str),
    /// [`Kind::Number`]: `None` is unset.
    Number(Option<f32>),
    /// [`Kind::Points`], in [`FaceAnchor::ALL`] order.
    Points([Option<[f32; 3]>; ANCHORS]),
    /// [`Kind::Numbers`] (at most 5).
    Numbers([f32; 5]),
}

/// One option: a row of [`OPTIONS`].
#[derive(Clone, Copy)]
pub struct OptionSpec {
    /// Dot-separated JS path (`"filter.minCutoff"`).
    pub path: &'static str,
    /// Type and accepted values.
    pub kind: Kind,
    /// Default value.
    pub default: Value,
    /// One-line description.
    pub doc: &'static str,
    /// Reads the option's field.
    pub get: fn(&RigOptions) -> Value,
    /// Writes the option's field (a value of the row's kind, already checked).
    pub set: fn(&mut RigOptions, Value),
}

/// A row's description: kept in native builds (the generated reference page and types, and
/// `pkg-config/src/option-descriptions.json`, from which the package's `optionDescriptions()`
/// takes it), left out of the `.wasm`, where it would be 4.6 KB of gzipped text no solve reads.
const fn doc(text: &'static str) -> &'static str {
    if cfg!(target_arch = "wasm32") {
        ""
    } else {
        text
    }
}

impl core::fmt::Debug for OptionSpec {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("OptionSpec")
            .field("path", &self.path)
            .field("kind", &self.kind)
            .field("default", &self.default)
            .finish_non_exhaustive()
    }
}

/// A boolean row: `flag!(path, field.path, default, doc)`.
macro_rules! flag {
    ($path:literal, $($f:ident).+, $default:expr, $doc:literal) => {
        OptionSpec {
            path: $path,
            kind: Kind::Bool,
            default: Value::Bool($default),
            doc: doc($doc),
            get: |o| Value::Bool(o.$($f).+),
            set: |o, v| {
                if let Value::Bool(b) = v {
                    o.$($f).+ = b;
                }
            },
        }
    };
}

/// An enum row: `choice!(path, field.path: Type, default, doc)`.
macro_rules! choice {
    ($path:literal, $($f:ident).+ : $ty:ty, $default:literal, $doc:literal) => {
        OptionSpec {
            path: $path,
            kind: Kind::Enum(<$ty as OptionEnum>::NAMES),
            default: Value::Enum($default),
            doc: doc($doc),
            get: |o| Value::Enum(OptionEnum::name(o.$($f).+)),
            set: |o, v| {
                if let Some(x) = match v {
                    Value::Enum(n) => <$ty as OptionEnum>::from_name(n),
                    _ => None,
                } {
                    o.$($f).+ = x;
                }
            },
        }
    };
}

/// A number row (an `f32` field): `number!(path, field.path, min..=max, step, default, doc)`.
/// `maybe` for an `Option<f32>` field (`null` accepted), `count` for an integer field.
macro_rules! number {
    ($path:literal, $($f:ident).+, $min:expr, $max:expr, $step:expr, $default:expr, $doc:literal) => {
        OptionSpec {
            path: $path,
            kind: Kind::Number { min: $min, max: $max, step: $step, integer: false, optional: false },
            default: Value::Number(Some($default)),
            doc: doc($doc),
            get: |o| Value::Number(Some(o.$($f).+)),
            set: |o, v| {
                if let Value::Number(Some(x)) = v {
                    o.$($f).+ = x;
                }
            },
        }
    };
    (maybe $path:literal, $($f:ident).+, $min:expr, $max:expr, $step:expr, $doc:literal) => {
        OptionSpec {
            path: $path,
            kind: Kind::Number { min: $min, max: $max, step: $step, integer: false, optional: true },
            default: Value::Number(None),
            doc: doc($doc),
            get: |o| Value::Number(o.$($f).+),
            set: |o, v| {
                if let Value::Number(x) = v {
                    o.$($f).+ = x;
                }
            },
        }
    };
    (count $path:literal, $($f:ident).+, $min:expr, $max:expr, $default:expr, $doc:literal) => {
        OptionSpec {
            path: $path,
            kind: Kind::Number { min: $min, max: $max, step: 1.0, integer: true, optional: false },
            default: Value::Number(Some($default)),
            doc: doc($doc),
            // Counts are small whole numbers: exact in f32.
            get: |o| Value::Number(Some(o.$($f).+ as f32)),
            set: |o, v| {
                if let Value::Number(Some(x)) = v {
                    o.$($f).+ = x as _;
                }
            },
        }
    };
}

/// Every option, in the order UIs and docs list them.
pub static OPTIONS: &[OptionSpec] = &[
    flag!("inputMirrored", input_mirrored, false,
        "The image given to MediaPipe was flipped horizontally (selfie view)."),
    flag!("mirror", mirror, false,
        "The avatar mirrors the user: the user's right hand drives the avatar's left."),
    choice!("handStrategy", hand_strategy: HandStrategy, "analytic",
        "How hands are solved: analytic = palm frame + anatomically limited joint angles; retarget = the avatar's fingertips placed where the user's are (scaled to the avatar's hand), within the same limits."),
    choice!("armSolver", arm_solver: ArmSolver, "twoBone",
        "Arm IK solver reaching the wrist target: twoBone = analytic two-bone IK with a pole; fabrik = FABRIK (seed 002); ccd = CCD with priority effectors (seed 004)."),
    number!("arm.shoulderAngle", arm.shoulder_angle, 0.0, core::f32::consts::FRAC_PI_2, 0.01, 0.26,
        "Largest angle (radians) the shoulder turns to help a far reach; 0 keeps shoulders at rest."),
    number!("arm.shoulderReach", arm.shoulder_reach, 0.5, 1.0, 0.01, 0.9,
        "Fraction of the arm's length beyond which the shoulder starts to turn toward the target."),
    number!("arm.forearmTwist", arm.forearm_twist, 0.0, 1.0, 0.05, 0.5,
        "Share of the hand's twist about the forearm that the forearm takes (the rest stays at the wrist)."),
    flag!("arm.wristLimits", arm.wrist_limits, true,
        "Clamp wrist flexion (80°), extension (70°), radial (20°) and ulnar (40°) deviation against the forearm; the hand turns about the aligned fingertip, so alignment stays exact."),
    number!("arm.maxTurnSpeed", arm.max_turn_speed, 0.0, 1000.0, 1.0, 23.0,
        "Fastest turn of an arm or hand (rad/s): a faster one (a tracking flip) is spread over frames. 0 = no limit."),
    choice!("arm.idle", arm.idle: ArmIdle, "down",
        "Where an arm with no wrist to follow rests: down = by the side, elbow slightly bent; tpose = the avatar's rest pose."),
    flag!("handsOnly.enabled", hands_only.enabled, true,
        "No pose: each arm placed from its hand's image position and size."),
    number!("handsOnly.fov", hands_only.fov, 0.1, 3.0, 0.01, 1.05,
        "Camera's vertical field of view (radians; 1.05 = 60°)."),
    number!("handsOnly.distance", hands_only.distance, 0.2, 5.0, 0.05, 0.9,
        "The user's shoulders' distance from the camera (m)."),
    number!("handsOnly.shoulderY", hands_only.shoulder_y, -1.0, 2.0, 0.05, 0.7,
        "The shoulder line's height in the image (0 top, 1 bottom)."),
    flag!("alignment.enabled", alignment.enabled, true,
        "Fingertip alignment: place the wrist so the avatar's finger lands where the user's is."),
    choice!("alignment.finger", alignment.finger: Finger, "index", "Which finger is aligned. On an avatar without its distal bone, its deepest bone, another finger or the palm stands in (reported in alignment.<side>.finger and .bone; docs/how-it-works/alignment-ik.md)."),
    choice!("alignment.point", alignment.point: AlignPoint, "dip",
        "Aligned point: dip = the distal bone's joint (exact); tip = distal bone extended by anatomical ratio."),
    number!("alignment.weight", alignment.weight, 0.0, 1.0, 0.05, 1.0,
        "Blend between the plain pose wrist (0) and the fully aligned wrist (1)."),
    number!(maybe "calibration.bodyScale", calibration.body_scale, 0.1, 10.0, 0.01,
        "Preset body scale (avatar arm / user arm) for pose input; unset = calibrate automatically."),
    number!(count "calibration.frames", calibration.frames, 1.0,
        crate::body::MAX_CALIBRATION_FRAMES as f32, 30.0,
        "Pose frames with a visible arm that automatic body-scale calibration averages (outliers beyond 20% of the median dropped)."),
    number!("calibration.minVisibility", calibration.min_visibility, 0.0, 1.0, 0.05, 0.5,
        "Pose landmarks below this visibility are ignored (arm at rest without a visible wrist; default elbow pole without a visible elbow)."),
    number!("minHandScore", min_hand_score, 0.0, 1.0, 0.05, 0.5,
        "Hands whose handedness score is below this are ignored."),
    choice!("handedness", handedness: HandednessPolicy, "reassign",
        "A hand whose label contradicts the pose wrists (needs hand and pose image landmarks): reassign = drives the side the pose says; drop = ignored; trust = MediaPipe's label decides."),
    flag!("filter.enabled", filter.enabled, true,
        "One Euro filtering of the landmarks (hands, pose, tracker wrists) before solving; alignment and IK stay exact on the filtered data."),
    number!("filter.minCutoff", filter.min_cutoff, 0.05, 1000.0, 0.05, 1.5,
        "One Euro cutoff at rest (Hz): lower is smoother, with more lag."),
    number!("filter.beta", filter.beta, 0.0, 10000.0, 0.1, 2.0,
        "One Euro speed coefficient (Hz per m/s): higher follows fast motion with less lag."),
    number!("filter.dCutoff", filter.d_cutoff, 0.05, 1000.0, 0.05, 1.0,
        "One Euro cutoff of the speed estimate (Hz)."),
    choice!("torso", torso: TorsoSource, "frame",
        "Where the torso comes from: frame = the app's frame.torso (rest where not given; handrig does not write the torso bones); pose = tracked from frame.body joints or the pose (handrig drives hips, spine, chest, upperChest, neck, head, shoulders); off = the rest torso."),
    flag!("dropout.enabled", dropout.enabled, true,
        "A lost hand or arm holds its pose, then eases to rest; a returning one blends in (otherwise both snap)."),
    number!("dropout.holdMs", dropout.hold_ms, 0.0, 10000.0, 10.0, 250.0,
        "How long a lost hand or arm keeps its last pose (ms)."),
    number!("dropout.fadeOutMs", dropout.fade_out_ms, 0.0, 10000.0, 10.0, 500.0,
        "How long it then takes to ease to rest (ms)."),
    number!("dropout.fadeInMs", dropout.fade_in_ms, 0.0, 10000.0, 10.0, 250.0,
        "How long a returning hand or arm blends from the shown pose to the solved one (ms)."),
    flag!("contact.enabled", contact.enabled, true,
        "Self-contact retargeting: a finger on the user's face lands on the avatar's face, touching hands stay touching, hands stay out of the avatar's body."),
    number!("contact.radius", contact.radius, 0.05, 3.0, 0.05, 0.5,
        "Contact blend radius in head breadths (the user's ear-to-ear distance, about 0.145 m): full contact mapping within half of it, plain alignment beyond it."),
    number!("contact.weight", contact.weight, 0.0, 1.0, 0.05, 1.0,
        "Scale of the contact blend: 0 = plain alignment, 1 = full contact mapping near the face or the other hand."),
    flag!("contact.hands", contact.hands, true,
        "Hand-to-hand contact: when the user's hands touch, both avatar targets are solved together so its hands touch too."),
    OptionSpec {
        path: "contact.faceAnchors",
        kind: Kind::Points { names: &FaceAnchor::NAMES, limit: MAX_ANCHOR_OFFSET },
        default: Value::Points([None; ANCHORS]),
        doc: doc("The avatar's face points, each [x, y, z] meters from the head bone at rest in the model's axes (e.g. raycast on its mesh); missing ones are derived from the rig (eye bones, look-at offset, an average face)."),
        get: |o| Value::Points(o.contact.face_anchors.to_array()),
        set: |o, v| {
            if let Value::Points(p) = v {
                o.contact.face_anchors = FaceAnchorsOption::from_array(p);
            }
        },
    },
    flag!("contact.colliders", contact.colliders, true,
        "Body colliders (torso and neck capsules, head sphere, derived from the rig) push hand targets out of the avatar's body."),
    number!(maybe "contact.torsoRadius", contact.torso_radius, 0.0, MAX_COLLIDER_RADIUS, 0.005,
        "Torso capsule radius (m, hips to chest); unset = 0.6 x the shoulder half-width; 0 = no torso collider."),
    number!(maybe "contact.headRadius", contact.head_radius, 0.0, MAX_COLLIDER_RADIUS, 0.005,
        "Head sphere radius (m); unset = half the head breadth; 0 = no head collider (never covers a face anchor)."),
    number!("contact.depthTrust", contact.depth_trust, 0.0, 1.0, 0.05, 0.1,
        "MediaPipe pose input: how much the tracked depth between fingertip and face counts (monocular hand depth at the face is off by 15-35 cm); where on the face comes from the image. 1 = as tracked; tracker input always uses its depth."),
    number!("contact.maxSpeed", contact.max_speed, 0.0, 20.0, 0.1, 6.0,
        "How fast (m/s) contact may move a hand's target onto the face, chest or other hand: a touch lands over a few frames instead of jerking the arm. 0 = no limit."),
    OptionSpec {
        path: "retarget.tipWeights",
        kind: Kind::Numbers { len: 5, min: 0.0, max: 1000.0 },
        default: Value::Numbers([2.0, 2.0, 1.0, 1.0, 1.0]),
        doc: doc("handStrategy retarget: fingertip weights, thumb to little (thumb and index emphasized for pinching, as the seed does)."),
        get: |o| Value::Numbers(o.retarget.tip_weights),
        set: |o, v| {
            if let Value::Numbers(w) = v {
                o.retarget.tip_weights = w;
            }
        },
    },
    number!("retarget.jointWeight", retarget.joint_weight, 0.0, 1000.0, 0.01, 0.02,
        "handStrategy retarget: weight of each intermediate joint, hung back from the fingertip target along the user's phalanges."),
    number!("retarget.pinchWeight", retarget.pinch_weight, 0.0, 10000.0, 0.5, 10.0,
        "handStrategy retarget: weight of the thumb tip relative to the index tip when the user pinches (within half of pinchDistance, fading out at it)."),
    number!("retarget.pinchDistance", retarget.pinch_distance, 0.001, 0.5, 0.001, 0.04,
        "handStrategy retarget: scaled thumb-index tip distance (m) below which the pinch term counts."),
    number!("retarget.spatialWeight", retarget.spatial_weight, 0.0, 1.0, 1e-6, 2e-6,
        "handStrategy retarget: weight (m^2/rad^2) pulling each DIP toward two thirds of its PIP."),
    number!("retarget.temporalWeight", retarget.temporal_weight, 1e-9, 1.0, 1e-3, 4e-3,
        "handStrategy retarget: weight (m^2/rad^2) toward the previous frame's angles for a finger whose target stood still."),
    number!("retarget.temporalSpeed", retarget.temporal_speed, 1e-5, 1.0, 1e-5, 3e-3,
        "handStrategy retarget: the fingertip target move (m per frame) at which the temporal weight has halved."),
    number!(count "retarget.maxIterations", retarget.settings.max_iterations, 1.0, 1000.0, 50.0,
        "handStrategy retarget: most Gauss-Newton iterations per finger and frame."),
    number!("retarget.stepTolerance", retarget.settings.step_tolerance, 0.0, 1.0, 1e-5, 1e-4,
        "handStrategy retarget: converged when a Gauss-Newton step's largest angle is at most this (radians)."),
    // The face (issue 50).
    flag!("face.enabled", face.enabled, true,
        "A tracked face (FaceLandmarker, Holistic) drives the expressions, the look-at and the head."),
    flag!("face.smoothing", face.smoothing, true,
        "One Euro smoothing of the face's weights and head, and the blink's limited opening; false = each frame's weights as tracked."),
    number!("face.minCutoff", face.min_cutoff, 0.01, 30.0, 0.01, 2.0,
        "Face smoothing: One Euro cutoff at rest (Hz); lower is smoother and slower."),
    number!("face.beta", face.beta, 0.0, 100.0, 0.1, 1.0,
        "Face smoothing: how fast the cutoff rises with a weight's speed (per unit/s); the head's is 10 times it (per rad/s)."),
    number!("face.blinkOpenTime", face.blink_open_time, 0.0, 1.0, 0.01, 0.1,
        "Shortest time (s) a closed eye takes to open (a blink closes at once)."),
    number!("face.calibrationTime", face.calibration_time, 0.0, 60.0, 0.5, 2.0,
        "Seconds of the first face frames averaged into the neutral face, a frame far above the average so far (a blink) left out (again after rig.calibrateFace())."),
    number!("face.neckShare", face.neck_share, 0.0, 1.0, 0.05, 0.3,
        "The neck's share of the head's turn from the face (the head bone takes the rest)."),
    flag!("face.head", face.head, true,
        "The face's transformation matrix turns the head and neck (over the torso's chest)."),
    // Legs (issue 51).
    flag!("legs.enabled", legs.enabled, true,
        "Legs from the pose's lower body (two-bone IK, knee and ankle limits); a leg whose hip, knee or ankle is not seen stays standing at rest."),
    number!("legs.minVisibility", legs.min_visibility, 0.0, 1.0, 0.05, 0.5,
        "A leg is tracked when its hip, knee and ankle have at least this visibility and lie inside the image (when the pose's image landmarks are given)."),
    flag!("legs.moveHips", legs.move_hips, true,
        "The hips move with the user while the legs are tracked: up and down so the lower foot stands on the avatar's floor, sideways and toward the camera from the pose's image (hipsOffset); false keeps them at rest."),
    flag!("legs.plant", legs.plant, true,
        "A foot on the floor that bears weight stays where it was planted (no sliding) until it lifts or moves off."),
    choice!("legs.rest", legs.rest: LegRest, "standing",
        "Where legs that are not seen rest: \"standing\" (the avatar's rest pose) or \"seated\" (hips and knees bent 90 degrees, feet flat, the hips in place: for a webcam that sees a seated user from the waist up)."),
    number!(maybe "camera.pitch", camera.pitch, -1.5, 1.5, 0.01,
        "How far the camera looks down (radians; negative: up; 0.5 = 29°), taken out of the pose's world landmarks (oriented with the camera) before the legs are solved; null = estimated over a few seconds from the user's straight legs."),
];

impl Value {
    /// The value as JSON text (defaults in docs and tests).
    #[must_use]
    pub fn to_json(&self) -> String {
        match self {
            Value::Bool(b) => b.to_string(),
            Value::Enum(n) => format!("\"{n}\""),
            Value::Number(None) => "null".into(),
            Value::Number(Some(x)) => Num::f32(*x).to_string(),
            Value::Points(p) => {
                let given: Vec<String> = FaceAnchor::NAMES
                    .iter()
                    .zip(p)
                    .filter_map(|(n, p)| {
                        p.map(|[x, y, z]| {
                            let [x, y, z] = [x, y, z].map(Num::f32);
                            format!("\"{n}\": [{x}, {y}, {z}]")
                        })
                    })
                    .collect();
                if given.is_empty() {
                    "null".into()
                } else {
                    format!("{{ {} }}", given.join(", "))
                }
            }
            Value::Numbers(v) => {
                let v: Vec<String> = v.iter().map(|x| Num::f32(*x).to_string()).collect();
                format!("[{}]", v.join(", "))
            }
        }
    }
}

impl OptionSpec {
    /// The row as plain data ([`super::option_descriptions`]).
    #[must_use]
    pub fn describe(&self) -> OptionDescription {
        let kind = match (self.kind, self.default) {
            (Kind::Bool, Value::Bool(default)) => OptionKind::Boolean { default },
            (Kind::Enum(values), Value::Enum(default)) => OptionKind::Enum {
                values: values.to_vec(),
                default,
            },
            (
                Kind::Number {
                    min,
                    max,
                    step,
                    integer,
                    ..
                },
                Value::Number(default),
            ) => OptionKind::Number {
                min,
                max,
                default,
                step,
                integer,
            },
            (Kind::Points { names, .. }, _) => OptionKind::Points {
                names: names.to_vec(),
            },
            (Kind::Numbers { len, min, max }, Value::Numbers(d)) => OptionKind::Numbers {
                len,
                min,
                max,
                default: d[..len].to_vec(),
            },
            // A row whose default does not match its kind (a test rules this out).
            (kind, default) => unreachable_kind(kind, default),
        };
        OptionDescription {
            path: self.path,
            kind,
            description: self.doc,
        }
    }

    /// A valid value other than the default, when the kind has one (tests).
    #[must_use]
    pub fn other_valid_value(&self) -> Option<Value> {
        Some(match (self.kind, self.default) {
            (Kind::Bool, Value::Bool(b)) => Value::Bool(!b),
            (Kind::Enum(names), Value::Enum(d)) => {
                Value::Enum(names.iter().copied().find(|n| *n != d)?)
            }
            (Kind::Number { min, max, .. }, Value::Number(d)) => {
                Value::Number(Some(if d == Some(max) { min } else { max }))
            }
            (Kind::Points { .. }, _) => {
                let mut p = [None; ANCHORS];
                p[0] = Some([0.0, 0.05, 0.1]);
                Value::Points(p)
            }
            (Kind::Numbers { .. }, Value::Numbers(mut w)) => {
                w[0] += 1.0;
                Value::Numbers(w)
            }
            _ => return None,
        })
    }
}

#[cold]
fn unreachable_kind(kind: Kind, default: Value) -> OptionKind {
    // Described as what the default says; never reached with the table as written.
    match default {
        Value::Bool(default) => OptionKind::Boolean { default },
        _ => OptionKind::Points {
            names: match kind {
                Kind::Enum(n) | Kind::Points { names: n, .. } => n.to_vec(),
                _ => Vec::new(),
            },
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A UI's range input (the demo's panel) snaps to `min + k * step`: a default off that
    /// grid could not be set back once moved.
    #[test]
    fn number_defaults_lie_on_their_step_grid() {
        for spec in OPTIONS {
            let (Kind::Number { min, step, .. }, Value::Number(Some(d))) =
                (spec.kind, spec.default)
            else {
                continue;
            };
            let k = (f64::from(d) - f64::from(min)) / f64::from(step);
            assert!(
                (k - k.round()).abs() < 1e-3,
                "{}: default {d} is not min {min} + k * step {step}",
                spec.path
            );
        }
    }

    #[test]
    fn paths_are_unique_and_defaults_match_kinds_and_ranges() {
        for (i, spec) in OPTIONS.iter().enumerate() {
            assert!(
                OPTIONS[..i].iter().all(|o| o.path != spec.path),
                "{} twice",
                spec.path
            );
            assert!(
                !OPTIONS
                    .iter()
                    .any(|o| o.path.starts_with(&format!("{}.", spec.path))),
                "{} is both an option and a group",
                spec.path
            );
            super::super::decode::check(spec, spec.default)
                .unwrap_or_else(|e| panic!("{}: default fails its own row: {e}", spec.path));
            let ok = matches!(
                (spec.kind, spec.default),
                (Kind::Bool, Value::Bool(_))
                    | (Kind::Enum(_), Value::Enum(_))
                    | (Kind::Number { .. }, Value::Number(_))
                    | (Kind::Points { .. }, Value::Points(_))
                    | (Kind::Numbers { .. }, Value::Numbers(_))
            );
            assert!(ok, "{}: default of another kind", spec.path);
            if let Kind::Number {
                optional: false, ..
            } = spec.kind
            {
                assert!(
                    matches!(spec.default, Value::Number(Some(_))),
                    "{}",
                    spec.path
                );
            }
        }
    }
}
