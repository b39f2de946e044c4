//! The **reach** stage, per side: the arm solver ([`crate::ik`]) reaches the target from the
//! posed torso, and the reports that need the result.

use glam::{Quat, Vec3};

use crate::align;
use crate::contact::ContactSolver;
use crate::error::Result;
use crate::humanoid::bones::{HumanBone, Side};
use crate::humanoid::skeleton::Skeleton;
use crate::ik::{ArmSolverState, ArmTarget};
use crate::options::RigOptions;

use super::frame::{Context, Frame, Plan};
use super::output::{IkTarget, SolveOutput};

/// The reach stage: the arm solvers (their warm starts and elbow swivels are history).
#[derive(Clone, Debug)]
pub(super) struct Reach {
    pub(super) arms: ArmSolverState,
}

impl Reach {
    pub(super) fn new(skeleton: &Skeleton, options: &RigOptions) -> Result<Self> {
        Ok(Reach {
            arms: ArmSolverState::with_options(skeleton, options.arm_solver, &options.arm)?,
        })
    }

    /// The side's arm reaches its plan (`f.plans`) into `out.local`; the IK target, the
    /// alignment's error and the contact distance reported.
    pub(super) fn run(
        &mut self,
        cx: &Context,
        contact: &ContactSolver,
        side: Side,
        f: &Frame,
        out: &mut SolveOutput,
    ) {
        let (target, hand_rot, pole) = match f.plans[side.index()] {
            Plan::Rest => return,
            Plan::HandOnly(q) => {
                // The hand's world rotation on the arm as it will rest (`arm.idle`, eased to
                // by the easing).
                let [_, upper, lower, _] = side.arm();
                let idle = crate::ik::idle_arm(cx.skeleton, side, cx.options.arm.idle);
                out.local[upper.index()] = idle[0];
                out.local[lower.index()] = idle[1];
                set_hand_world_rotation(cx.skeleton, side, q, out);
                return;
            }
            Plan::Reach {
                target,
                hand_rotation: Some(q),
                pole,
                carried: false,
            } => (target, q, pole),
            Plan::Reach {
                target,
                hand_rotation,
                pole,
                carried,
            } => {
                // No hand this frame: the arm reaches the wrist with the rotation it has (a
                // lost hand's as shown, which keeps the forearm's twist), and the hand bone is
                // the easing's (held, then eased to rest). Nothing aligned to report.
                self.reach(
                    cx,
                    side,
                    &ArmTarget {
                        target,
                        hand_rotation,
                        pole,
                        finger: None,
                    },
                    out,
                );
                if carried {
                    out.solved[side.hand().index()] = false;
                }
                return;
            }
        };
        out.ik_targets[side.index()] = Some(IkTarget {
            position: target,
            rotation: hand_rot,
        });
        // The aligned finger point (CCD's first-priority effector; the wrist limits turn the
        // hand about it). With `alignment.weight` w the IK wrist moves by w times the avatar
        // offset, so the point that stays put is w of the way along it.
        let weight = cx.options.alignment.effective_weight();
        let finger = out.alignment[side.index()]
            .filter(|a| a.aligned && weight > 0.0)
            .map(|a| a.avatar_offset * weight);
        // In contact, the touching point is what must stay put, so the wrist limits turn the
        // hand about it (as far as the blends go): the point touching the other hand, then a
        // fingertip on the face (which wins).
        let finger = match (out.contact[side.index()], f.points[side.index()]) {
            (Some(c), Some(p)) => {
                let mut pivot = finger;
                let mut toward = |point: Option<Vec3>, weight: f32| {
                    if let Some(point) = point.filter(|_| weight > 0.0) {
                        pivot = Some(pivot.unwrap_or(Vec3::ZERO).lerp(point, weight));
                    }
                };
                toward(c.hand_meet, c.hand_weight);
                let touch =
                    cx.aligned_parts[side.index()].touch_finger(cx.options.alignment.finger);
                toward(c.face_meet.or(p.avatar[1 + touch.index()]), c.weight);
                pivot
            }
            _ => finger,
        };
        let to = ArmTarget {
            target,
            hand_rotation: Some(hand_rot),
            pole,
            finger,
        };
        let mut reach = self.reach(cx, side, &to, out);
        if let (Some(first), Some(body)) = (
            reach.wrist,
            super::contact::HandBody::of(cx, contact, f, side),
        ) {
            // The wrist limits turned the hand about its touching point, which can take the
            // rest of it into the body (a fingertip on the collar, the wrist swung into the
            // chest): the target moves by the push that takes the hand as reached out, and
            // the arm reaches again (the same request moved, so that a push fading to nothing
            // gives the first solve back; a few rounds, as the limits turn the moved hand).
            let mut limited = first;
            let mut shift = Vec3::ZERO;
            for _ in 0..LIFT_ROUNDS {
                let lift = body.push(limited.target, limited.hand_rotation, &out.world);
                // Under a millimeter is left (the turn limit's allowance): reaching again is
                // not free of history (the arm solver's warm start and twist branch), and a
                // 0.4 mm push turned the primitive figure's hanging arm 33 mm in on `hungry`.
                if lift.length() <= super::limit::SINK {
                    break;
                }
                shift += lift;
                let again = ArmTarget {
                    target: to.target + shift,
                    ..to
                };
                let next = self.reach(cx, side, &again, out);
                limited = next.wrist.unwrap_or(crate::ik::WristLimited {
                    target: again.target,
                    hand_rotation: hand_rot,
                    ..first
                });
                reach = crate::ik::ArmReach {
                    wrist: Some(limited),
                    ..next
                };
            }
        }
        if let Some(limited) = reach.wrist {
            // The wrist limits turned the hand: report the target and rotation reached.
            let turn = limited.hand_rotation * hand_rot.conjugate();
            if let Some(t) = out.ik_targets[side.index()].as_mut() {
                t.position = limited.target;
                t.rotation = limited.hand_rotation;
            }
            if let Some(report) = out.alignment[side.index()].as_mut() {
                report.ik_wrist = limited.target;
                report.avatar_offset = turn * report.avatar_offset;
            }
        }
        if let Some(report) = out.alignment[side.index()].as_mut() {
            report.reachable = reach.reachable;
            report.error = align::alignment_error(
                cx.skeleton,
                side,
                &cx.options.alignment,
                report,
                &out.local,
                &mut out.world,
            );
        }
        if let Some(c) = out.contact[side.index()].as_mut() {
            if let Some(anchor) = c.anchor {
                // Forward kinematics of the arm just solved (alignment_error ran it when
                // there was a report; run it here otherwise).
                if out.alignment[side.index()].is_none() {
                    cx.skeleton.forward_arm(side, &out.local, &mut out.world);
                }
                // The touching point: the aligned finger's tip, or what stands in for it.
                let part = cx.aligned_parts[side.index()];
                let tip = match part {
                    align::AlignedPart::Finger { finger, depth: 2 } => {
                        align::fingertip(cx.skeleton, &out.world, side, finger)
                    }
                    _ => Some(align::part_world(
                        cx.skeleton,
                        &out.world,
                        &out.local,
                        side,
                        part,
                        align::AlignPoint::Tip,
                    )),
                };
                c.distance = tip.map_or(f32::NAN, |tip| {
                    (tip - contact.anchor_world(anchor, &out.world)).length()
                });
            }
        }
    }

    // Out of line: called from two places a side, inlined at each (.wasm size).
    #[inline(never)]
    fn reach(
        &mut self,
        cx: &Context,
        side: Side,
        to: &ArmTarget,
        out: &mut SolveOutput,
    ) -> crate::ik::ArmReach {
        // `out.world` holds the arm's parent chain (posed once per frame in `solve`; neither
        // side's arm moves it).
        let reach = self.arms.solve(side, to, &mut out.local, &out.world);
        for b in side.arm() {
            if b != side.arm()[0] || self.arms.moves_shoulder(side) {
                out.solved[b.index()] |= cx.skeleton.has(b);
            }
        }
        reach
    }
}

/// Rounds of pushing a hand the wrist limits turned into the body out and reaching again.
const LIFT_ROUNDS: usize = 3;

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
