//! Stage 1, **select hands**: which tracked hand drives each avatar side; low scores ignored,
//! labels that contradict the pose wrists reassigned (`options.handedness`), two hands on one
//! side resolved.

use crate::bones::Side;
use crate::mediapipe::{hand_landmark, pose_landmark, CameraMapping, FrameInput};
use crate::options::HandednessPolicy;

use super::{HandUse, Rig, SolveOutput};

/// A hand's label contradicts the pose when its wrist is nearer the other side's pose wrist
/// than this fraction of its distance to its own side's (in the image).
pub const CONTRADICTION_RATIO: f32 = 0.5;

/// The hand picked for a side by [`Rig::select_hands`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Pick {
    pub(super) index: usize,
    pub(super) reassigned: bool,
    /// Image distance from the hand's wrist to this side's pose wrist, when known.
    pub(super) distance: Option<f32>,
    pub(super) score: f32,
}

impl Rig {
    /// Stage 1: which tracked hand drives each side (`[left, right]`), recording what became
    /// of every hand in `out.hand_use`.
    pub(super) fn select_hands(
        &self,
        frame: &FrameInput,
        camera: CameraMapping,
        out: &mut SolveOutput,
    ) -> [Option<Pick>; 2] {
        // The pose wrists in the image, per avatar side, when both are visible.
        let pose_wrists = match (&frame.pose, &frame.pose_image) {
            (Some(pose), Some(image)) if self.options.handedness != HandednessPolicy::Trust => {
                let at = |side: Side| {
                    let k = match camera.pose_side_for(side) {
                        Side::Left => pose_landmark::LEFT_WRIST,
                        Side::Right => pose_landmark::RIGHT_WRIST,
                    };
                    (pose.visibility[k] >= self.options.calibration.min_visibility)
                        .then(|| image[k].truncate())
                };
                at(Side::Left).zip(at(Side::Right)).map(|(l, r)| [l, r])
            }
            _ => None,
        };
        let mut picks: [Option<Pick>; 2] = [None, None];
        for (index, h) in frame.hands().iter().enumerate() {
            if h.score < self.options.min_hand_score {
                out.hand_use[index] = HandUse::LowScore;
                continue;
            }
            let mut side = camera.avatar_side(h.handedness);
            let mut reassigned = false;
            let wrist = h.image.map(|img| img[hand_landmark::WRIST].truncate());
            let distance_to = |side: Side| {
                pose_wrists
                    .zip(wrist)
                    .map(|(pw, w)| (w - pw[side.index()]).length())
            };
            if let (Some(own), Some(other)) = (distance_to(side), distance_to(side.opposite())) {
                if other < CONTRADICTION_RATIO * own {
                    match self.options.handedness {
                        HandednessPolicy::Reassign => {
                            side = side.opposite();
                            reassigned = true;
                        }
                        HandednessPolicy::Drop => {
                            out.hand_use[index] = HandUse::Contradicted;
                            continue;
                        }
                        HandednessPolicy::Trust => {}
                    }
                }
            }
            let pick = Pick {
                index,
                reassigned,
                distance: distance_to(side),
                score: h.score,
            };
            let slot = &mut picks[side.index()];
            let loser = match *slot {
                None => {
                    *slot = Some(pick);
                    None
                }
                Some(current) => {
                    // Nearer the side's pose wrist wins when known, else the higher score.
                    let better = match (pick.distance, current.distance) {
                        (Some(a), Some(b)) => a < b,
                        _ => pick.score > current.score,
                    };
                    if better {
                        *slot = Some(pick);
                        Some(current.index)
                    } else {
                        Some(index)
                    }
                }
            };
            if let Some(l) = loser {
                out.hand_use[l] = HandUse::Duplicate;
            }
        }
        for side in Side::BOTH {
            if let Some(p) = picks[side.index()] {
                out.hand_use[p.index] = HandUse::Drove(side);
            }
        }
        picks
    }
}
