//! Stage 3, **torso**: the torso bones from the app (`frame.torso`) or tracked from `body`
//! joints or the pose, eased over tracking loss ([`crate::torso`]); the user's upper-torso
//! frame measured on the pose; forward kinematics of the posed torso places each arm's anchor
//! (its upper-arm joint and torso frame).

use glam::Quat;

use crate::body::ArmAnchor;
use crate::humanoid::bones::Side;
use crate::mediapipe::{CameraMapping, FrameInput};
use crate::torso::{self, TorsoPoints, TorsoSource, TORSO_BONES};

use super::{Rig, SolveOutput};

impl Rig {
    /// Stage 3: the torso bones into `out.local` (see [`crate::torso`]): the app's
    /// (`frame.torso`), tracked (`torso: "pose"`, from `body` joints or the pose) with the
    /// app's bones winning, or rest (`"off"`). Then each arm's anchor for the pose mapping:
    /// the posed upper-arm joint, and the turn from the user's upper-torso frame (measured on
    /// the pose) to the avatar's.
    pub(super) fn torso_stage(
        &mut self,
        frame: &FrameInput,
        camera: CameraMapping,
        dt: Option<f32>,
        out: &mut SolveOutput,
    ) {
        let source = self.options.torso;
        let min_visibility = self.options.calibration.min_visibility;
        let version = self.skeleton.version();
        // The user's torso on the pose (also what the pose arms are measured against).
        let pose_measure = match (source, &self.scratch.pose) {
            (TorsoSource::Off, _) | (_, None) => None,
            (_, Some(pose)) => Some(torso::measure(&TorsoPoints::from_pose(
                pose,
                camera,
                min_visibility,
            ))),
        };
        if source == TorsoSource::Pose {
            let measure = match frame.body {
                Some(mut body) => {
                    if self.options.filter.enabled {
                        let o = self.options.filter.one_euro();
                        self.body_filters
                            .apply(&mut body.position, frame.time_ms, dt, &o);
                    }
                    torso::measure(&TorsoPoints::from_body(&body, version, min_visibility))
                }
                None => pose_measure.unwrap_or_default(),
            };
            let timing = self.options.dropout.effective();
            self.torso.track(
                &self.skeleton,
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
                    out.solved[bone.index()] = self.skeleton.has(*bone);
                }
            }
        }
        for side in Side::BOTH {
            self.scratch.shoulder_base[side.index()] = out.local[side.arm()[0].index()];
        }
        // Anchors: forward kinematics of the torso alone (arms at rest). The fingers are posed
        // with their arm (`align::alignment_error`, the contact stage) or in the report.
        self.skeleton.forward_body(&out.local, &mut out.world);
        let top = self.torso.top();
        let avatar_frame = out.world.rotation[top.index()] * self.torso.rest_upper();
        self.scratch.turn = pose_measure
            .and_then(|m| m.upper)
            .map(|user| (avatar_frame * user.conjugate()).normalize())
            .filter(|q| q.is_finite());
        for side in Side::BOTH {
            let upper = side.arm()[1];
            self.scratch.anchors[side.index()] = self.skeleton.has(upper).then(|| ArmAnchor {
                shoulder: out.world.position[upper.index()],
                rotation: self.scratch.turn.unwrap_or(Quat::IDENTITY),
            });
        }
    }
}
