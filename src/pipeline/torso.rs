//! The **torso** stage: the torso bones from the app (`frame.torso`) or tracked from `body`
//! joints or the pose, eased over tracking loss ([`crate::torso`]); the user's upper-torso
//! frame measured on the pose; forward kinematics of the posed torso places each arm's anchor
//! (its upper-arm joint and torso frame).

use glam::Quat;

use crate::body::ArmAnchor;
use crate::humanoid::bones::Side;
use crate::humanoid::skeleton::Skeleton;
use crate::torso::{self, TorsoPoints, TorsoSolver, TorsoSource, TORSO_BONES};

use super::frame::{Context, Frame};
use super::output::SolveOutput;

/// The torso stage: the avatar's torso, the shrug's neutral, the torso's easing.
#[derive(Clone, Debug)]
pub(super) struct Torso {
    pub(super) solver: TorsoSolver,
}

impl Torso {
    pub(super) fn new(skeleton: &Skeleton, calibration_frames: usize) -> Self {
        Torso {
            solver: TorsoSolver::new(skeleton, calibration_frames),
        }
    }

    /// The torso bones into `out.local` (see [`crate::torso`]): the app's (`frame.torso`),
    /// tracked (`torso: "pose"`, from `body` joints or the pose) with the app's bones winning,
    /// or rest (`"off"`). Then each arm's anchor for the pose mapping (`f.anchors`): the posed
    /// upper-arm joint, and the turn from the user's upper-torso frame (measured on the pose)
    /// to the avatar's (`f.turn`).
    pub(super) fn run(&mut self, cx: &Context, f: &mut Frame, out: &mut SolveOutput) {
        let (frame, skeleton) = (cx.input, cx.skeleton);
        let source = cx.options.torso;
        let min_visibility = cx.options.calibration.min_visibility;
        let version = skeleton.version();
        // The user's torso on the pose (also what the pose arms are measured against).
        let pose_measure = match (source, &f.pose) {
            (TorsoSource::Off, _) | (_, None) => None,
            (_, Some(pose)) => Some(torso::measure(&TorsoPoints::from_pose(
                pose,
                cx.camera,
                min_visibility,
            ))),
        };
        if source == TorsoSource::Pose {
            let measure = match &f.body {
                Some(body) => {
                    torso::measure(&TorsoPoints::from_body(body, version, min_visibility))
                }
                None => pose_measure.unwrap_or_default(),
            };
            let timing = cx.options.dropout.effective();
            self.solver.track(
                skeleton,
                &measure,
                frame.time_ms,
                &timing,
                &mut out.local,
                &mut out.solved,
            );
        }
        if source != TorsoSource::Off {
            // The app's bones (in "pose" mode they win over the tracked ones).
            for (bone, q) in TORSO_BONES.iter().zip(frame.torso.iter()) {
                if let Some(q) = q {
                    out.local[bone.index()] = version.rotation_to_internal(*q).normalize();
                    out.solved[bone.index()] = skeleton.has(*bone);
                }
            }
        }
        for side in Side::BOTH {
            f.shoulder_base[side.index()] = out.local[side.arm()[0].index()];
        }
        // Anchors: forward kinematics of the torso alone (arms at rest). The fingers are posed
        // with their arm (`align::alignment_error`, the contact stage) or in the report.
        skeleton.forward_body(&out.local, &mut out.world);
        let top = self.solver.top();
        let avatar_frame = out.world.rotation[top.index()] * self.solver.rest_upper();
        f.turn = pose_measure
            .and_then(|m| m.upper)
            .map(|user| (avatar_frame * user.conjugate()).normalize())
            .filter(|q| q.is_finite());
        for side in Side::BOTH {
            let upper = side.arm()[1];
            f.anchors[side.index()] = skeleton.has(upper).then(|| ArmAnchor {
                shoulder: out.world.position[upper.index()],
                rotation: f.turn.unwrap_or(Quat::IDENTITY),
            });
        }
    }
}
