//! The per-frame pipeline: MediaPipe frame in, normalized-bone rotations, IK targets and
//! alignment reports out.
//!
//! Per avatar side, in order: pick the hand that drives it, solve hand orientation and finger
//! rotations ([`crate::hand`]), find the pose wrist (from `wrists` or pose landmarks via
//! [`crate::body`]), place the wrist IK target by fingertip alignment ([`crate::align`]) using
//! forward kinematics of *this* frame's hand and finger rotations, and reach it with the arm
//! solver ([`crate::ik`]). Finally forward kinematics of the whole avatar.

use glam::{Quat, Vec3};
use serde::Deserialize;

use crate::align::{self, AlignmentOptions, AlignmentReport};
use crate::body::{BodyMapper, CalibrationOptions};
use crate::bones::Finger;
use crate::bones::{HumanBone, Side, BONE_COUNT};
use crate::error::Result;
use crate::hand::{HandSolver, HandStatus, HandStrategy, RetargetReport};
use crate::ik::{ArmSolver, ArmSolverState};
use crate::mediapipe::{hand_landmark, CameraMapping, FrameInput, HAND_LANDMARKS};
use crate::skeleton::{Skeleton, WorldPose};

/// Options of a [`Rig`], set at construction (JS: the `options` argument of `new HandRig`).
/// Every field has a documented default; JS names are the camelCase field names.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(rename_all = "camelCase", default, deny_unknown_fields)]
pub struct RigOptions {
    /// The image given to MediaPipe was flipped horizontally (selfie view). Default `false`.
    pub input_mirrored: bool,
    /// The avatar mirrors the user, VTuber style: the user's right hand drives the avatar's
    /// left. Default `false`.
    pub mirror: bool,
    /// How hands are solved. Default `"analytic"`.
    pub hand_strategy: HandStrategy,
    /// Fingertip alignment.
    pub alignment: AlignmentOptions,
    /// Which arm IK solver reaches the wrist target. Default `"twoBone"`.
    pub arm_solver: ArmSolver,
    /// Body-scale calibration from pose landmarks.
    pub calibration: CalibrationOptions,
    /// Hands whose handedness score is below this are ignored. Default `0.5`.
    pub min_hand_score: f32,
}

impl Default for RigOptions {
    fn default() -> Self {
        RigOptions {
            input_mirrored: false,
            mirror: false,
            hand_strategy: HandStrategy::default(),
            alignment: AlignmentOptions::default(),
            arm_solver: ArmSolver::default(),
            calibration: CalibrationOptions::default(),
            min_hand_score: 0.5,
        }
    }
}

impl RigOptions {
    /// How MediaPipe input maps onto the avatar.
    #[must_use]
    pub fn camera(&self) -> CameraMapping {
        CameraMapping {
            input_mirrored: self.input_mirrored,
            mirror: self.mirror,
        }
    }
}

/// A wrist IK target in the internal frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IkTarget {
    /// Where the avatar's hand bone (wrist joint) should be.
    pub position: Vec3,
    /// World rotation the avatar's normalized hand bone should have.
    pub rotation: Quat,
}

/// Everything one `solve` produces, in handrig's internal frame. Fixed-size: reused frame to
/// frame without allocation.
#[derive(Clone, Debug, PartialEq)]
pub struct SolveOutput {
    /// Local rotation of every normalized bone (identity where nothing was solved).
    pub local: [Quat; BONE_COUNT],
    /// Which bones were solved this frame (only these are reported).
    pub solved: [bool; BONE_COUNT],
    /// Forward kinematics of `local`.
    pub world: WorldPose,
    /// Wrist IK targets per side (`[left, right]`), when a pose wrist was known.
    pub ik_targets: [Option<IkTarget>; 2],
    /// Fingertip-alignment reports per side.
    pub alignment: [Option<AlignmentReport>; 2],
    /// The tracked hand that drove each side this frame, if any.
    pub hands: [Option<TrackedHand>; 2],
    /// The avatar's fingertips per side (`[left, right]`), thumb to little, world positions
    /// in the internal frame, every strategy: the distal bone extended by the anatomical
    /// ratio of [`crate::align::tip_offset`] (the point `alignment.point: "tip"` aligns).
    /// `None` where the avatar lacks that finger's distal bone.
    pub fingertips: [[Option<Vec3>; 5]; 2],
    /// What `handStrategy: "retarget"` did per side this frame (`None` for other strategies
    /// and for sides not freshly solved); targets are world positions in the internal frame,
    /// like [`SolveOutput::fingertips`].
    pub retarget: [Option<RetargetReport>; 2],
}

/// Which tracked hand drove an avatar side, and whether its rotations are fresh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackedHand {
    /// [`HandStatus::Solved`] (from this frame), [`HandStatus::Held`] (this frame's hand was
    /// degenerate; the previous rotations were kept) or [`HandStatus::Skipped`] (degenerate
    /// with nothing to keep, or the avatar has no usable palm).
    pub status: HandStatus,
    /// Its handedness score.
    pub score: f32,
}

impl Default for SolveOutput {
    fn default() -> Self {
        SolveOutput {
            local: [Quat::IDENTITY; BONE_COUNT],
            solved: [false; BONE_COUNT],
            world: WorldPose::default(),
            ik_targets: [None, None],
            alignment: [None, None],
            hands: [None, None],
            fingertips: [[None; 5]; 2],
            retarget: [None, None],
        }
    }
}

/// The solver for one avatar: owns the skeleton, the options and every buffer, so
/// [`Rig::solve`] allocates nothing.
#[derive(Clone, Debug)]
pub struct Rig {
    skeleton: Skeleton,
    options: RigOptions,
    hands: HandSolver,
    body: BodyMapper,
    arms: ArmSolverState,
    landmarks: [Vec3; HAND_LANDMARKS],
}

impl Rig {
    /// Creates a rig for `skeleton`.
    ///
    /// # Errors
    /// Options out of range (field named in the message).
    pub fn new(skeleton: Skeleton, options: RigOptions) -> Result<Self> {
        options.alignment.validate()?;
        options.calibration.validate()?;
        if !(0.0..=1.0).contains(&options.min_hand_score) {
            return Err(crate::Error::invalid(
                "options.minHandScore",
                "must be a number in 0..1",
            ));
        }
        let hands = HandSolver::new(&skeleton, options.hand_strategy)?;
        let body = BodyMapper::new(&skeleton, &options.calibration);
        let arms = ArmSolverState::new(&skeleton, options.arm_solver)?;
        Ok(Rig {
            skeleton,
            options,
            hands,
            body,
            arms,
            landmarks: [Vec3::ZERO; HAND_LANDMARKS],
        })
    }

    /// The avatar's skeleton.
    #[must_use]
    pub fn skeleton(&self) -> &Skeleton {
        &self.skeleton
    }

    /// The options in force.
    #[must_use]
    pub fn options(&self) -> &RigOptions {
        &self.options
    }

    /// Body-scale calibration state.
    #[must_use]
    pub fn body(&self) -> &BodyMapper {
        &self.body
    }

    /// Restarts body-scale calibration.
    pub fn reset_calibration(&mut self) {
        self.body.reset();
    }

    /// Calibrates the hand scale of `handStrategy: "retarget"` (avatar hand over user hand)
    /// on each side from the last hand solved there, which should be an open, flat hand
    /// (the seed's bounding-box scale; see [`crate::hand::retarget`]). Until then, or after
    /// a refused calibration, the scale comes from the hand's stable lengths. Returns the new
    /// scale per side (`[left, right]`), `None` where nothing changed (no hand solved yet,
    /// fingers not straight, or no retargetable fingers). Any strategy may calibrate.
    pub fn calibrate_hand_scale(&mut self) -> [Option<f32>; 2] {
        Side::BOTH.map(|side| self.hands.calibrate_hand_scale(side))
    }

    /// Solves one frame into `out` (internal frame; see [`Rig::export_rotation`] and
    /// [`Rig::export_position`] for the model frame). Allocates nothing.
    ///
    /// # Errors
    /// Invalid input (non-finite numbers are rejected before any state changes). Degenerate
    /// hands are not errors: that hand is skipped and its previous rotations are kept.
    pub fn solve(&mut self, frame: &FrameInput, out: &mut SolveOutput) -> Result<()> {
        validate_frame(frame)?;
        let camera = self.options.camera();
        out.solved = [false; BONE_COUNT];
        out.ik_targets = [None, None];
        out.alignment = [None, None];
        out.hands = [None, None];
        out.retarget = [None, None];
        // Everything not solved this frame goes back to rest.
        out.local = [Quat::IDENTITY; BONE_COUNT];

        if let Some(pose) = &frame.pose {
            self.body.observe(&self.skeleton, pose, camera);
        }

        for side in Side::BOTH {
            self.solve_side(side, frame, camera, out);
        }
        self.skeleton.forward(&out.local, &mut out.world);
        for side in Side::BOTH {
            let s = side.index();
            for finger in Finger::ALL {
                out.fingertips[s][finger.index()] =
                    align::fingertip(&self.skeleton, &out.world, side, finger);
            }
            let fresh = out.hands[s].is_some_and(|h| h.status == HandStatus::Solved);
            if let (true, Some(report)) = (fresh, self.hands.retarget_report(side)) {
                let hand = side.hand().index();
                let (p, q) = (out.world.position[hand], out.world.rotation[hand]);
                out.retarget[s] = Some(RetargetReport {
                    targets: report.targets.map(|t| t.map(|t| p + q * t)),
                    ..*report
                });
            }
        }
        Ok(())
    }

    fn solve_side(
        &mut self,
        side: Side,
        frame: &FrameInput,
        camera: CameraMapping,
        out: &mut SolveOutput,
    ) {
        // The hand that drives this side: highest score among those mapping here.
        let hand = frame
            .hands()
            .iter()
            .filter(|h| h.score >= self.options.min_hand_score)
            .filter(|h| camera.avatar_side(h.handedness) == side)
            .max_by(|a, b| a.score.total_cmp(&b.score));

        let mut hand_rotation = None;
        if let Some(h) = hand {
            for (dst, src) in self.landmarks.iter_mut().zip(h.world.iter()) {
                *dst = camera.to_avatar(*src);
            }
            hand_rotation = self
                .hands
                .solve(&self.skeleton, side, &self.landmarks, &mut out.local);
            out.hands[side.index()] = Some(TrackedHand {
                status: self.hands.report(side).status,
                score: h.score,
            });
            if hand_rotation.is_some() {
                for b in crate::bones::Finger::ALL
                    .iter()
                    .flat_map(|f| side.finger(*f))
                    .chain([side.hand()])
                {
                    out.solved[b.index()] = self.skeleton.has(b);
                }
            }
        }

        // The pose wrist and the body scale that applies to it.
        let wrist_input = frame.wrists[side.index()];
        let (pose_wrist, scale, pole) = match (wrist_input, &frame.pose) {
            (Some(w), _) => (
                Some(self.skeleton.version().position_to_internal(w.position)),
                1.0,
                None,
            ),
            (None, Some(pose)) => {
                let mapped = self.body.map_arm(&self.skeleton, side, pose, camera);
                (
                    mapped.map(|m| m.wrist),
                    self.body.scale(),
                    mapped.and_then(|m| m.elbow),
                )
            }
            (None, None) => (None, 1.0, None),
        };
        let rotation_override = wrist_input
            .and_then(|w| w.rotation)
            .map(|q| self.skeleton.version().rotation_to_internal(q));
        let Some(hand_rot) = hand_rotation.or(rotation_override) else {
            // No hand and no wrist rotation: with a pose wrist the arm can still reach it.
            if let Some(target) = pose_wrist {
                self.reach(side, target, None, pole, out);
            }
            return;
        };

        let Some(pose_wrist) = pose_wrist else {
            // Hands only: the arm stays at rest and the hand takes the solved world rotation.
            set_hand_world_rotation(&self.skeleton, side, hand_rot, out);
            return;
        };

        // A held hand (degenerate landmarks this frame) keeps its rotations but its
        // landmarks cannot place the fingertip: align only freshly solved hands.
        let fresh = self.hands.report(side).status == HandStatus::Solved;
        let target = match hand {
            Some(_) if fresh => {
                let a = align::wrist_target(
                    &self.skeleton,
                    side,
                    &self.options.alignment,
                    pose_wrist,
                    &self.landmarks,
                    scale,
                    hand_rot,
                    &out.local,
                );
                out.alignment[side.index()] = Some(a);
                a.ik_wrist
            }
            _ => pose_wrist,
        };
        out.ik_targets[side.index()] = Some(IkTarget {
            position: target,
            rotation: hand_rot,
        });
        let reach = self.reach(side, target, Some(hand_rot), pole, out);
        if let Some(report) = out.alignment[side.index()].as_mut() {
            report.reachable = reach.reachable;
            report.error = align::alignment_error(
                &self.skeleton,
                side,
                &self.options.alignment,
                report,
                &out.local,
                &mut out.world,
            );
        }
    }

    fn reach(
        &mut self,
        side: Side,
        target: Vec3,
        hand_rotation: Option<Quat>,
        pole: Option<Vec3>,
        out: &mut SolveOutput,
    ) -> crate::ik::ArmReach {
        // World frame of the arm's parent chain (torso at rest: handrig does not move it).
        self.skeleton.forward(&out.local, &mut out.world);
        let reach = self.arms.solve(
            side,
            target,
            hand_rotation,
            pole,
            &mut out.local,
            &out.world,
        );
        for b in side.arm() {
            if b != side.arm()[0] {
                out.solved[b.index()] |= self.skeleton.has(b);
            }
        }
        reach
    }

    /// Converts a rotation from the internal frame to the model's own frame (VRM 0.x: negate
    /// x and z).
    #[inline]
    #[must_use]
    pub fn export_rotation(&self, q: Quat) -> Quat {
        self.skeleton.version().rotation_to_internal(q)
    }

    /// Converts a position from the internal frame to the model's own frame.
    #[inline]
    #[must_use]
    pub fn export_position(&self, p: Vec3) -> Vec3 {
        self.skeleton.version().position_to_internal(p)
    }
}

/// Sets the hand's local rotation so its world rotation is `hand_world`, given the arm's
/// current local rotations.
fn set_hand_world_rotation(
    skeleton: &Skeleton,
    side: Side,
    hand_world: Quat,
    out: &mut SolveOutput,
) {
    let hand = side.hand();
    let mut parent_world = Quat::IDENTITY;
    let mut chain = [HumanBone::Hips; 8];
    let mut n = 0;
    let mut b = skeleton.parent(hand);
    while let Some(p) = b {
        if n < chain.len() {
            chain[n] = p;
            n += 1;
        }
        b = skeleton.parent(p);
    }
    for link in chain[..n].iter().rev() {
        parent_world *= out.local[link.index()];
    }
    out.local[hand.index()] = (parent_world.inverse() * hand_world).normalize();
}

fn validate_frame(frame: &FrameInput) -> Result<()> {
    if !frame.time_ms.is_finite() {
        return Err(crate::Error::invalid(
            "frame.timeMs",
            "must be a finite number",
        ));
    }
    for (i, h) in frame.hands().iter().enumerate() {
        if let Some(k) = h.world.iter().position(|p| !p.is_finite()) {
            return Err(crate::Error::invalid(
                format!("frame.hands[{i}].worldLandmarks[{k}]"),
                "must be three finite numbers",
            ));
        }
        if !h.score.is_finite() {
            return Err(crate::Error::invalid(
                format!("frame.hands[{i}].score"),
                "must be a finite number",
            ));
        }
    }
    if let Some(p) = &frame.pose {
        if let Some(k) = p.world.iter().position(|p| !p.is_finite()) {
            return Err(crate::Error::invalid(
                format!("frame.pose.worldLandmarks[{k}]"),
                "must be three finite numbers",
            ));
        }
    }
    for side in Side::BOTH {
        if let Some(w) = &frame.wrists[side.index()] {
            if !w.position.is_finite() {
                return Err(crate::Error::invalid(
                    format!("frame.wrists.{}.position", side.as_str()),
                    "must be three finite numbers",
                ));
            }
            if let Some(q) = w.rotation {
                if !q.is_finite() || (q.length() - 1.0).abs() > 1e-2 {
                    return Err(crate::Error::invalid(
                        format!("frame.wrists.{}.rotation", side.as_str()),
                        "must be a unit quaternion [x, y, z, w]",
                    ));
                }
            }
        }
    }
    let _ = hand_landmark::WRIST;
    Ok(())
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

/// Every option a [`Rig`] accepts, for UIs (the demo builds its control panel from this) and
/// docs. Kept next to [`RigOptions`]; a test checks that each path and default round-trips.
#[must_use]
pub fn option_descriptions() -> Vec<OptionDescription> {
    use OptionKind::*;
    let d = RigOptions::default();
    vec![
        OptionDescription {
            path: "inputMirrored",
            kind: Boolean { default: d.input_mirrored },
            description: "The image given to MediaPipe was flipped horizontally (selfie view).",
        },
        OptionDescription {
            path: "mirror",
            kind: Boolean { default: d.mirror },
            description: "The avatar mirrors the user: the user's right hand drives the avatar's left.",
        },
        OptionDescription {
            path: "handStrategy",
            kind: Enum {
                values: vec!["analytic", "retarget"],
                default: "analytic",
            },
            description: "How hands are solved: analytic = palm frame + anatomically limited joint angles; retarget = the avatar's fingertips placed where the user's are (scaled to the avatar's hand), within the same limits.",
        },
        OptionDescription {
            path: "armSolver",
            kind: Enum {
                values: vec!["twoBone"],
                default: "twoBone",
            },
            description: "Arm IK solver reaching the wrist target: twoBone = analytic two-bone IK with a pole.",
        },
        OptionDescription {
            path: "alignment.enabled",
            kind: Boolean { default: d.alignment.enabled },
            description: "Fingertip alignment: place the wrist so the avatar's finger lands where the user's is.",
        },
        OptionDescription {
            path: "alignment.finger",
            kind: Enum {
                values: crate::bones::Finger::ALL.iter().map(|f| f.as_str()).collect(),
                default: d.alignment.finger.as_str(),
            },
            description: "Which finger is aligned.",
        },
        OptionDescription {
            path: "alignment.point",
            kind: Enum {
                values: vec!["dip", "tip"],
                default: "dip",
            },
            description: "Aligned point: dip = the distal bone's joint (exact); tip = distal bone extended by anatomical ratio.",
        },
        OptionDescription {
            path: "alignment.weight",
            kind: Number {
                min: 0.0,
                max: 1.0,
                default: Some(d.alignment.weight),
                step: 0.05,
            },
            description: "Blend between the plain pose wrist (0) and the fully aligned wrist (1).",
        },
        OptionDescription {
            path: "calibration.bodyScale",
            kind: Number {
                min: 0.1,
                max: 10.0,
                default: d.calibration.body_scale,
                step: 0.01,
            },
            description: "Preset body scale (avatar arm / user arm) for pose input; unset = calibrate automatically.",
        },
        OptionDescription {
            path: "calibration.frames",
            kind: Number {
                min: 1.0,
                max: crate::body::MAX_CALIBRATION_FRAMES as f32,
                default: Some(d.calibration.frames as f32),
                step: 1.0,
            },
            description: "Pose frames with a visible arm that automatic body-scale calibration averages (outliers beyond 20% of the median dropped).",
        },
        OptionDescription {
            path: "calibration.minVisibility",
            kind: Number {
                min: 0.0,
                max: 1.0,
                default: Some(d.calibration.min_visibility),
                step: 0.05,
            },
            description: "Pose landmarks below this visibility are ignored (arm at rest without a visible wrist; default elbow pole without a visible elbow).",
        },
        OptionDescription {
            path: "minHandScore",
            kind: Number {
                min: 0.0,
                max: 1.0,
                default: Some(d.min_hand_score),
                step: 0.05,
            },
            description: "Hands whose handedness score is below this are ignored.",
        },
    ]
}
