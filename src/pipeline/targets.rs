//! The **targets** stage, per side: the wrist IK target by fingertip alignment
//! ([`crate::align`]) from forward kinematics of *this* frame's hand as the easing will show
//! it; the contact stage then moves both sides' targets together, before any IK.
//!
//! A hand lost while the wrist source still places the arm ([`LostHand`]) leaves the arm what
//! it had: the aligned target's offset from the wrist source, and the hand's world rotation as
//! shown, which keeps the forearm's share of the twist. Both are held and eased out with the
//! dropout timings (`options.dropout`), as the lost hand's own rotation is (the easing stage
//! holds the hand bone, then eases it to rest). So a hand MediaPipe drops
//! for a frame neither turns the forearm by its whole twist share nor jumps to the bare wrist
//! (`tests/it/hand_loss.rs`). A hand solved again is aligned in that frame: its hand bone shows
//! the solve at once (`ease.rs`), its fingers blend in.

use glam::{Quat, Vec3};

use crate::align;
use crate::filter::{DropoutOptions, Presence};
use crate::humanoid::bones::Side;

use super::ease::Ease;
use super::frame::{Context, Frame, Plan};
use super::output::SolveOutput;

/// What a side's lost hand leaves to its arm (history; see the module docs): the fingertip
/// alignment's offset from the wrist source and the hand's world rotation as shown, held and
/// then eased out with the dropout timings.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct LostHand {
    /// The last aligned frame's wrist target (after contact) minus the wrist source's
    /// position.
    offset: Vec3,
    /// This frame's wrist source position.
    wrist: Vec3,
    /// The hand present (live) or lost, and since when: the hold and the fade.
    presence: Presence,
    /// The hand's world rotation shown last frame (internal frame), when the arm was solved
    /// in it (written after the report stage's forward kinematics).
    shown: Option<Quat>,
}

impl LostHand {
    /// Advances to `now_ms` with the hand `present` or not: how far a lost hand's carry has
    /// eased out (0 while present or holding, 1 once gone).
    fn update(&mut self, now_ms: f64, present: bool, timing: &DropoutOptions) -> f32 {
        let blend = self.presence.update(now_ms, present, timing);
        if present {
            0.0
        } else {
            blend.weight
        }
    }
}

/// The targets stage: per side what a lost hand leaves to its arm.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Targets {
    lost: [LostHand; 2],
}

impl Targets {
    /// Forgets the history.
    pub(super) fn restart(&mut self) {
        *self = Targets::default();
    }

    /// After the IK: each aligned side's wrist target as reached (contact and the wrist
    /// limits applied) as an offset from its wrist source, for when the hand is lost
    /// ([`LostHand`]).
    pub(super) fn remember_offsets(&mut self, out: &SolveOutput) {
        for side in Side::BOTH {
            let s = side.index();
            if let (Some(t), true) = (out.ik_targets[s], out.alignment[s].is_some()) {
                let lost = &mut self.lost[s];
                lost.offset = t.position - lost.wrist;
            }
        }
    }

    /// After the report's forward kinematics: the side's hand as shown (world rotation, when
    /// its arm was solved), for the arm should the hand be lost next frame.
    pub(super) fn remember_shown(&mut self, side: Side, shown: Option<Quat>) {
        self.lost[side.index()].shown = shown;
    }

    /// The side's plan (`f.plans`): its wrist IK target by fingertip alignment from this
    /// frame's hand (no IK yet).
    // Out of line: LLVM inlined it once per side, 0.8 KiB of .wasm (docs/measurements/2026-12-05-size.md).
    #[inline(never)]
    pub(super) fn plan(
        &mut self,
        cx: &Context,
        ease: &Ease,
        side: Side,
        f: &mut Frame,
        out: &mut SolveOutput,
    ) {
        let s = side.index();
        f.fingers_blending[s] = false;
        let (hand_rotation, source) = (f.hand_rotation[s], f.sources[s]);
        let timing = cx.options.dropout.effective();
        let present = hand_rotation.or(source.and_then(|s| s.rotation));
        let lost = &mut self.lost[s];
        let gone = lost.update(cx.now_ms, present.is_some(), &timing);
        let Some(source) = source else {
            // Nothing places the arm: a hand alone keeps it at rest and takes the solved world
            // rotation.
            *lost = LostHand::default();
            f.plans[s] = present.map_or(Plan::Rest, Plan::HandOnly);
            return;
        };
        lost.wrist = source.position;
        if gone >= 1.0 {
            // Eased out: a hand held by the solver on its first frame back starts from the
            // bare wrist, not from an offset of long ago.
            lost.offset = Vec3::ZERO;
        }
        let carried = source.position + lost.offset * (1.0 - gone);
        // A lost hand: the arm keeps the hand's rotation as shown (the forearm keeps its share
        // of the twist) until the hand has eased to rest, and then reaches the wrist.
        let Some(hand_rot) = present.or(lost.shown.filter(|_| gone < 1.0)) else {
            f.plans[s] = Plan::Reach {
                target: carried,
                hand_rotation: None,
                pole: source.pole,
                carried: false,
            };
            return;
        };

        // A hand held by the solver (degenerate landmarks this frame) keeps its rotations but
        // its landmarks cannot place the fingertip: align freshly solved hands, and hands the
        // checks held with the landmarks they were solved from (the hands stage).
        let fresh = f.placed[s];
        // The fingers as shown: a returning hand's blend in (the easing), so that the
        // fingertip shown lands on the user's (a copy of the rotations, on the stack, only
        // then).
        let blend = ease.fingers_blend(cx, side).filter(|_| fresh);
        f.fingers_blending[s] = blend.is_some();
        let target = if fresh {
            let mut copy = None;
            let local = ease.fingers_as_shown(cx, side, blend, &out.local, &mut copy);
            let a = align::wrist_target(
                cx.skeleton,
                side,
                &cx.options.alignment,
                cx.aligned_parts[s],
                &align::UserHand {
                    wrist: source.position,
                    landmarks: &f.landmarks[s],
                    scale: source.scale,
                },
                hand_rot,
                local,
            );
            out.alignment[s] = Some(a);
            a.ik_wrist
        } else {
            carried
        };
        f.plans[s] = Plan::Reach {
            target,
            hand_rotation: Some(hand_rot),
            pole: source.pole,
            carried: present.is_none(),
        };
    }
}
