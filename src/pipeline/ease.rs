//! The **ease** stage: groups whose tracking was lost hold, then ease to rest (a shoulder to
//! the torso's rotation of it); returning ones blend in ([`crate::filter::dropout`]); rotations
//! keep their hemisphere.

use glam::Quat;

use crate::filter::{nlerp, Blend, Presence};
use crate::hand::HandStatus;
use crate::humanoid::bones::BONE_COUNT;
use crate::humanoid::bones::{HumanBone, Side};

use super::frame::{Context, Frame};
use super::output::SolveOutput;

/// The bone groups that come and go with tracking, per side.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Group {
    /// The fingers: tracked with a hand.
    Fingers = 0,
    /// The hand bone: tracked with a hand, or a tracker wrist's rotation.
    Hand = 1,
    /// The shoulder, upper and lower arm: tracked with a wrist (tracker or pose).
    Arm = 2,
}

/// The contact weight (face, chest or hands) from which a returning hand shows its solve at
/// once instead of blending in.
pub const TOUCH_COMPLETES_BLEND: f32 = 0.5;

/// The ease stage: per side the presence of each group, per bone the rotation shown last frame
/// and the anchor of its running blend, per shoulder the arm solver's turn as shown and its
/// blend's anchor.
#[derive(Clone, Debug)]
pub(super) struct Ease {
    presence: [[Presence; 3]; 2],
    shown: [Quat; BONE_COUNT],
    anchor: [Quat; BONE_COUNT],
    shoulder_turn_shown: [Quat; 2],
    shoulder_turn_anchor: [Quat; 2],
}

impl Default for Ease {
    fn default() -> Self {
        Ease {
            presence: [[Presence::default(); 3]; 2],
            shown: [Quat::IDENTITY; BONE_COUNT],
            anchor: [Quat::IDENTITY; BONE_COUNT],
            shoulder_turn_shown: [Quat::IDENTITY; 2],
            shoulder_turn_anchor: [Quat::IDENTITY; 2],
        }
    }
}

impl Ease {
    /// Forgets the history (what was shown is identity again; anchors are captured before
    /// they are read).
    pub(super) fn restart(&mut self) {
        let anchor = self.anchor;
        *self = Ease {
            anchor,
            ..Ease::default()
        };
    }

    /// The rotations shown last frame.
    pub(super) fn shown(&self) -> &[Quat; BONE_COUNT] {
        &self.shown
    }

    /// The rotations shown, for a later stage that changes what is shown (the turn limit).
    pub(super) fn shown_mut(&mut self) -> &mut [Quat; BONE_COUNT] {
        &mut self.shown
    }

    /// Holds and eases the groups whose tracking was lost, blend in the returning ones
    /// (see [`crate::filter::dropout`]), and keep every driven rotation in the hemisphere of
    /// last frame's (so that apps interpolating output never go the long way round). Returns,
    /// per side, whether anything shown differs from what was solved (a blend under way).
    pub(super) fn run(
        &mut self,
        cx: &Context,
        moves_shoulder: [bool; 2],
        touch_held: [bool; 2],
        f: &Frame,
        out: &mut SolveOutput,
    ) -> [bool; 2] {
        let now_ms = cx.now_ms;
        let timing = cx.options.dropout.effective();
        let mut eased = [false; 2];
        for side in Side::BOTH {
            let [shoulder, upper, lower, hand] = side.arm();
            // Where the arm rests with nothing to follow (`arm.idle`): its upper and lower
            // arm's rest in the easing.
            let idle = if out.solved[upper.index()] {
                [Quat::IDENTITY; 2]
            } else {
                crate::ik::idle_arm(cx.skeleton, side, cx.options.arm.idle)
            };
            // A hand held against the other (`touch.rs`) keeps its fingers as shown.
            let live_fingers = out.hands[side.index()]
                .is_some_and(|h| matches!(h.status, HandStatus::Solved | HandStatus::Held))
                || touch_held[side.index()];
            // The hand bone is also driven by a tracker wrist's rotation without a hand.
            let groups = [
                (Group::Fingers, live_fingers),
                (Group::Hand, out.solved[hand.index()]),
                (Group::Arm, out.solved[upper.index()]),
            ];
            // A hand returning into a touch (face, chest or the other hand) shows its solve
            // at once: contact placed the solved pose, and blending in from the pose shown
            // while it was lost would hold it off the skin (on `sister` the right hand
            // returning onto the left stayed 24-29 mm off it for the blend-in's 250 ms).
            let touching = out.contact[side.index()].is_some_and(|c| {
                c.weight.max(c.hand_weight).max(c.chest_weight) >= TOUCH_COMPLETES_BLEND
            });
            // A hand returning to an arm the pose still placed (`targets.rs`, a lost hand's
            // arm keeps its rotation as shown) shows its hand bone's solve at once too: the
            // arm reached the fingertip-aligned target for that rotation, so a blend-in would
            // move the fingertip off the user's (up to 90 mm on `eat`); the turn limit bounds
            // the hand's turn instead. The fingers still blend in.
            // Only an arm placed while the hand was lost: tracked since before the hand came
            // back (last frame's state; the arm's group is advanced after the hand's below). A
            // hand and arm back together (a hand-only recording, a body tracker's dropout) have
            // no placed arm to keep aligned with: the hand bone blends in like the fingers (on
            // the hand video's 1 s drop it turned 55 degrees in one frame).
            let aligned = out.alignment[side.index()].is_some();
            let arm_since = self.presence[side.index()][Group::Arm as usize].live_since();
            // Fingers blending in that alignment and contact already placed as shown
            // ([`Ease::fingers_blend`]) keep blending: completing them would move the
            // fingertip off what was placed.
            let placed_blending = f.fingers_blending[side.index()];
            for (group, live) in groups {
                let presence = &mut self.presence[side.index()][group as usize];
                let mut blend = presence.update(now_ms, live, &timing);
                let arm_placed = arm_since
                    .zip(presence.live_since())
                    .is_some_and(|(arm, hand)| arm < hand);
                let completes = (touching && !(group == Group::Fingers && placed_blending))
                    || (aligned && arm_placed && group == Group::Hand);
                if completes && blend.to_solved && !blend.is_exact() {
                    presence.complete();
                    blend.weight = 1.0;
                }
                eased[side.index()] |= !(blend.is_exact() && blend.to_solved);
                let mut apply = |b: HumanBone| {
                    let i = b.index();
                    if !cx.driven[i] {
                        return;
                    }
                    let rest = if b == upper {
                        idle[0]
                    } else if b == lower {
                        idle[1]
                    } else {
                        Quat::IDENTITY
                    };
                    let q = blend.show_with_rest(
                        out.local[i],
                        rest,
                        &mut self.anchor[i],
                        self.shown[i],
                    );
                    out.local[i] = q;
                    self.shown[i] = q;
                };
                match group {
                    Group::Fingers => {
                        for f in crate::humanoid::bones::Finger::ALL {
                            side.finger(f).into_iter().for_each(&mut apply);
                        }
                    }
                    Group::Hand => apply(hand),
                    Group::Arm => {
                        [upper, lower].into_iter().for_each(apply);
                        if moves_shoulder[side.index()] && cx.skeleton.has(shoulder) {
                            self.ease_shoulder(side, f.shoulder_base[side.index()], blend, out);
                        }
                    }
                }
            }
        }
        eased
    }

    /// How the easing will show the fingers of `side`'s hand, solved this frame: `None` as
    /// solved, or the blend-in of fingers returning after a loss. The targets and contact stages place the fingertip
    /// (alignment, contact points) with the fingers as they will be shown
    /// ([`Ease::show_fingers`]), so a returning hand's blend-in does not move it off the user's.
    pub(super) fn fingers_blend(&self, cx: &Context, side: Side) -> Option<Blend> {
        let now_ms = cx.now_ms;
        let timing = cx.options.dropout.effective();
        // A copy: the easing advances the state itself, to the same blend (the hand is live).
        let mut presence = self.presence[side.index()][Group::Fingers as usize];
        let blend = presence.update(now_ms, true, &timing);
        (!blend.is_exact()).then_some(blend)
    }

    /// `local` as the easing will show `side`'s fingers: `local` itself, or with `blend` a
    /// copy in `copy` (on the caller's stack, made only then) with the fingers blended.
    pub(super) fn fingers_as_shown<'a>(
        &self,
        cx: &Context,
        side: Side,
        blend: Option<Blend>,
        local: &'a [Quat; BONE_COUNT],
        copy: &'a mut Option<[Quat; BONE_COUNT]>,
    ) -> &'a [Quat; BONE_COUNT] {
        match blend {
            Some(b) => {
                let shown = copy.insert(*local);
                self.show_fingers(cx, side, b, shown);
                shown
            }
            None => local,
        }
    }

    /// `local` with `side`'s finger rotations as `blend` will show them (the easing's anchors
    /// and last shown rotations, unchanged).
    fn show_fingers(&self, cx: &Context, side: Side, blend: Blend, local: &mut [Quat; BONE_COUNT]) {
        // The side's 15 finger bones are consecutive, thumb metacarpal first.
        let first = side.finger(crate::humanoid::bones::Finger::Thumb)[0].index();
        // An index loop: the iterator form (`enumerate().skip().take()`) costs 0.2 KiB more
        // of .wasm, which sits near its size budget.
        #[allow(clippy::needless_range_loop)]
        for i in first..first + 15 {
            if cx.driven[i] {
                let mut anchor = self.anchor[i];
                local[i] = blend.show(local[i], &mut anchor, self.shown[i]);
            }
        }
    }

    /// Eases the arm's share of a shoulder: the turn the arm solver put on top of the torso's
    /// rotation of the bone (`shoulder_base`), so that a lost arm's shoulder goes back to the
    /// torso's (shrug, or the app's) while the torso keeps moving.
    fn ease_shoulder(
        &mut self,
        side: Side,
        base: Quat,
        blend: crate::filter::Blend,
        out: &mut SolveOutput,
    ) {
        let s = side.index();
        let i = side.arm()[0].index();
        if blend.capture {
            self.shoulder_turn_anchor[s] = self.shoulder_turn_shown[s];
        }
        let target = if blend.to_solved {
            (base.conjugate() * out.local[i]).normalize()
        } else {
            Quat::IDENTITY
        };
        let turn = if blend.is_exact() {
            target
        } else if blend.weight <= 0.0 {
            self.shoulder_turn_anchor[s]
        } else {
            nlerp(self.shoulder_turn_anchor[s], target, blend.weight)
        };
        let turn = if turn.dot(self.shoulder_turn_shown[s]) < 0.0 {
            -turn
        } else {
            turn
        };
        self.shoulder_turn_shown[s] = turn;
        let q = (base * turn).normalize();
        let q = if q.dot(self.shown[i]) < 0.0 { -q } else { q };
        out.local[i] = q;
        self.shown[i] = q;
    }
}
