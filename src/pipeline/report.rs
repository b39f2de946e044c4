//! The **report** stage: forward kinematics of the whole avatar, its fingertips, the
//! retargeting reports, and the whole output turned into the model's own frame.

use crate::align;
use crate::hand::{HandStatus, RetargetReport};
use crate::humanoid::bones::{Finger, Side};

use super::frame::Context;
use super::hands::Hands;
use super::output::SolveOutput;
use super::targets::Targets;

/// The report stage (no history of its own; it hands the hand as shown to the targets stage).
pub(super) struct Report;

impl Report {
    /// Forward kinematics of what is shown, the avatar's fingertips, and the
    /// retargeting reports placed on the avatar. `eased[side]`: the easing blended that side's
    /// arm, hand or fingers away from what was solved, so its alignment error (measured on the
    /// solve) is measured again on what is shown.
    pub(super) fn run(
        cx: &Context,
        hands: &Hands,
        targets: &mut Targets,
        eased: [bool; 2],
        out: &mut SolveOutput,
    ) {
        // The torso stage posed the body, which nothing has turned since (the later stages turn
        // the arms, hands and fingers, the easing also the shoulders): the arms from their roots.
        for side in Side::BOTH {
            cx.skeleton.forward_arm(side, &out.local, &mut out.world);
            // The hand as shown, for the arm should the hand be lost next frame (`targets.rs`).
            let [_, upper, _, hand] = side.arm();
            targets.remember_shown(
                side,
                out.solved[upper.index()].then(|| out.world.rotation[hand.index()]),
            );
        }
        for side in Side::BOTH {
            let s = side.index();
            if let (true, Some(report)) = (eased[s], out.alignment[s].as_mut()) {
                let hand = side.hand().index();
                let a = align::part_offset(
                    cx.skeleton,
                    side,
                    report.part,
                    cx.options.alignment.point,
                    out.world.rotation[hand],
                    &out.local,
                );
                report.error = (out.world.position[hand] + a - report.target_dip).length();
            }
            for finger in Finger::ALL {
                out.fingertips[s][finger.index()] =
                    align::fingertip(cx.skeleton, &out.world, side, finger);
            }
            let fresh = out.hands[s].is_some_and(|h| h.status == HandStatus::Solved);
            if let (true, Some(report)) = (fresh, hands.solver().retarget_report(side)) {
                let hand = side.hand().index();
                let (p, q) = (out.world.position[hand], out.world.rotation[hand]);
                out.retarget[s] = Some(RetargetReport {
                    targets: report.targets.map(|t| t.map(|t| p + q * t)),
                    ..*report
                });
            }
        }
        // Last: everything in the model's own frame, for every caller.
        out.turn_to_model_frame(cx.skeleton.version());
    }
}
