//! The **hands** stage, per side: the hand orientation and finger rotations ([`crate::hand`])
//! from the landmarks the observe stage mapped, checked and filtered; a hand the checks hold
//! keeps its last solved rotations and is placed by the landmarks it was solved from.

use glam::Vec3;

use crate::error::Result;
use crate::hand::{HandSolver, HandStatus};
use crate::humanoid::bones::{Finger, Side};
use crate::humanoid::skeleton::Skeleton;
use crate::input::mediapipe::HAND_LANDMARKS;
use crate::options::RigOptions;

use super::frame::{Context, Frame};
use super::output::{HandCheck, SolveOutput, TrackedHand};

/// [`TrackedHand::confidence`]: the handedness score times how the hand was solved.
fn confidence(check: HandCheck, status: HandStatus, score: f32) -> f32 {
    let how = match (status, check) {
        (HandStatus::Solved, HandCheck::Good) => 1.0,
        (HandStatus::Held, _) | (HandStatus::Solved, HandCheck::Mirrored) => 0.3,
        (HandStatus::Skipped | HandStatus::NotSolved, _) => 0.0,
    };
    how * score.clamp(0.0, 1.0)
}

/// The hands stage: the hand solver, and per side the landmarks of the last hand solved (what
/// a held hand's later stages, alignment and contact, read instead of the rejected ones).
#[derive(Clone, Debug)]
pub(super) struct Hands {
    solver: HandSolver,
    last: [Option<[Vec3; HAND_LANDMARKS]>; 2],
}

impl Hands {
    pub(super) fn new(skeleton: &Skeleton, options: &RigOptions) -> Result<Self> {
        let mut solver = HandSolver::new(skeleton, options.hand_strategy)?;
        solver.set_retarget_options(options.retarget)?;
        Ok(Hands {
            solver,
            last: [None; 2],
        })
    }

    /// The hand solver (its reports).
    pub(super) fn solver(&self) -> &HandSolver {
        &self.solver
    }

    /// See [`super::Rig::calibrate_hand_scale`].
    pub(super) fn calibrate_hand_scale(&mut self, side: Side) -> Option<f32> {
        self.solver.calibrate_hand_scale(side)
    }

    /// Forgets the history (the solver's and the last solved landmarks).
    pub(super) fn restart(&mut self) {
        self.solver.reset();
        self.last = [None; 2];
    }

    /// The side's hand solved (or held) into `out.local`, its world rotation into
    /// `f.hand_rotation`, whether its landmarks place its fingertip into `f.placed`.
    pub(super) fn run(&mut self, cx: &Context, side: Side, f: &mut Frame, out: &mut SolveOutput) {
        let s = side.index();
        f.placed[s] = false;
        f.hand_rotation[s] = None;
        let Some(pick) = f.picks[s] else { return };
        let h = &cx.input.hands()[pick.index];
        let verdict = f.check[s];
        let hand_rotation = if verdict.holds() {
            // The rejected landmarks would place the fingertip (alignment, contact) where the
            // mirrored hand has it: the held hand is placed by its own, the last solved.
            if let Some(last) = self.last[s] {
                f.landmarks[s] = last;
                f.placed[s] = true;
            }
            self.solver.hold(cx.skeleton, side, &mut out.local)
        } else {
            self.solver
                .solve(cx.skeleton, side, &f.landmarks[s], &mut out.local)
        };
        let status = self.solver.report(side).status;
        // (A hand held above always has `last`: it was set by the solve the hand solver holds.)
        if status == HandStatus::Solved {
            self.last[s] = Some(f.landmarks[s]);
            f.placed[s] = true;
        }
        out.hands[s] = Some(TrackedHand {
            status,
            confidence: confidence(verdict, status, h.score),
            score: h.score,
            index: pick.index,
            reassigned: pick.reassigned,
            resolved: pick.resolved,
            check: verdict,
        });
        if hand_rotation.is_some() {
            for b in Finger::ALL
                .iter()
                .flat_map(|f| side.finger(*f))
                .chain([side.hand()])
            {
                out.solved[b.index()] = cx.skeleton.has(b);
            }
        }
        f.hand_rotation[s] = hand_rotation;
    }
}
