//! The **legs** stage: each leg from the pose's lower body ([`crate::legs`]) when its hip,
//! knee and ankle are seen (`legs.minVisibility`, inside the image), held then eased to the
//! standing rest pose when they are not, blended back in when they return (the dropout
//! timings of the arms, [`crate::filter::dropout`]). A head-and-shoulders webcam sees no legs:
//! they stay exactly at rest. Runs after the torso stage (the hips as posed); the observe stage
//! filtered the leg landmarks.

use glam::Quat;

use crate::filter::dropout::Presence;
use crate::humanoid::bones::Side;
use crate::humanoid::skeleton::Skeleton;
use crate::input::mediapipe::PoseObservation;
use crate::legs::{leg_bones, leg_landmarks, Leg, LegTarget};

use super::frame::{Context, Frame};
use super::output::SolveOutput;

/// The legs stage: per side the leg solver, its presence, the rotations shown last frame and
/// the blend's anchors.
#[derive(Clone, Debug)]
pub(super) struct Legs {
    legs: [Option<Leg>; 2],
    presence: [Presence; 2],
    shown: [[Quat; 4]; 2],
    anchor: [[Quat; 4]; 2],
}

impl Legs {
    pub(super) fn new(skeleton: &Skeleton) -> Self {
        Legs {
            legs: Side::BOTH.map(|side| Leg::new(skeleton, side)),
            presence: [Presence::default(); 2],
            shown: [[Quat::IDENTITY; 4]; 2],
            anchor: [[Quat::IDENTITY; 4]; 2],
        }
    }

    pub(super) fn restart(&mut self) {
        for leg in self.legs.iter_mut().flatten() {
            leg.reset();
        }
        self.presence = [Presence::default(); 2];
        self.shown = [[Quat::IDENTITY; 4]; 2];
        self.anchor = [[Quat::IDENTITY; 4]; 2];
    }

    /// Each leg's bones into `out.local` (solved, held, easing or at rest); the legs' world
    /// pose when any leg is off rest.
    pub(super) fn run(&mut self, cx: &Context, f: &Frame, out: &mut SolveOutput) {
        if !cx.options.legs.enabled {
            return;
        }
        let timing = cx.options.dropout.effective();
        let mut moved = false;
        for side in Side::BOTH {
            let s = side.index();
            let Some(leg) = self.legs[s].as_mut() else {
                continue;
            };
            let bones = leg_bones(side);
            let hips = out.world.rotation[cx.skeleton.parent(bones[0]).map_or(0, |p| p.index())];
            let target = f
                .pose
                .as_ref()
                .and_then(|pose| target(cx, f, pose, side, leg.lengths(), out));
            let mut solved = [Quat::IDENTITY; 4];
            if let Some(t) = &target {
                let p = leg.solve(hips, t);
                solved[..3].copy_from_slice(&p.local);
            }
            let blend = self.presence[s].update(cx.now_ms, target.is_some(), &timing);
            for (k, bone) in bones.iter().enumerate() {
                let q = blend.show(solved[k], &mut self.anchor[s][k], self.shown[s][k]);
                self.shown[s][k] = q;
                if cx.skeleton.has(*bone) {
                    out.local[bone.index()] = q;
                    out.solved[bone.index()] = target.is_some();
                    moved |= q != Quat::IDENTITY;
                }
            }
        }
        if moved {
            cx.skeleton.forward_body(&out.local, &mut out.world);
        }
    }
}

/// Where the tracked leg of the avatar's `side` puts it (the user's thigh and shin directions,
/// turned with the torso, with the avatar's thigh and shin `lengths`), or `None` when the hip,
/// knee or ankle is not seen.
fn target(
    cx: &Context,
    f: &Frame,
    pose: &PoseObservation,
    side: Side,
    lengths: (f32, f32),
    out: &SolveOutput,
) -> Option<LegTarget> {
    let [hip, knee, ankle, heel, toe] = leg_landmarks(cx.camera.pose_side_for(side));
    let min = cx.options.legs.min_visibility;
    // Seen: visible enough and inside the image (MediaPipe guesses a leg below the frame's
    // edge with a visibility up to 0.84 on the ASL clips).
    let inside = |x: f32| (0.0..=1.0).contains(&x);
    let seen = |i: usize| {
        pose.visibility[i] >= min
            && cx
                .input
                .pose_image
                .is_none_or(|im| inside(im[i].x) && inside(im[i].y))
    };
    if !(seen(hip) && seen(knee) && seen(ankle)) {
        return None;
    }
    let at_hip = out.world.position[leg_bones(side)[0].index()];
    let w = &pose.world;
    let turn = f.turn.unwrap_or(Quat::IDENTITY);
    let vector = |v| turn * cx.camera.to_avatar(v);
    // Each of the user's segments along its direction with the avatar's length: the knee's
    // angle and the leg's direction are the user's.
    let (thigh, shin) = lengths;
    let knee_at = at_hip + thigh * vector(w[knee] - w[hip]).try_normalize()?;
    let ankle_at = knee_at + shin * vector(w[ankle] - w[knee]).try_normalize()?;
    let t = LegTarget {
        hip: at_hip,
        knee: knee_at,
        ankle: ankle_at,
        foot: (seen(heel) && seen(toe)).then(|| vector(w[toe] - w[heel])),
    };
    (t.knee.is_finite() && t.ankle.is_finite()).then_some(t)
}
