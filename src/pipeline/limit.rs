//! The **turn limit** stage: an arm (shoulder, upper arm, forearm, hand) cannot turn faster
//! than `arm.maxTurnSpeed`; a faster turn is shown over as many frames as it takes.
//!
//! What turns that fast on real video is not the user: MediaPipe's hand flipping its depth for
//! a frame or two past the hand checks (`hands.rs`), or a wrist target that self-contact moves
//! 10-20 cm while the elbow is folded (the forearm then swings 90-165 degrees in one frame on
//! short-armed avatars). Each bone's turn is measured from the chest (its local rotation
//! composed down the arm: the shoulder, shoulder x upper arm, ... x forearm, ... x hand), as
//! the avatar shows it: the shoulder bone's shrug (`arm.shoulderAngle`, up to 15 degrees in a
//! frame where the reach changes) adds to what the hand turns. When the largest of the four
//! turns faster than `maxTurnSpeed`, every bone's local rotation moves from what was shown
//! last frame toward the solve by the same fraction of its turn (about the turn's axis), the
//! fraction that brings the largest composed turn to `maxTurnSpeed x dt`: the arm keeps its
//! shape (a wrist within its range stays within it) and the next frames catch up. The limit
//! slows a jump, it never holds one (a hold released later turns by more, measured in
//! `docs/how-it-works/hands-on-video.md`). The fingers ride on the hand. Only an arm solved in this frame
//! and the one before is limited (the dropout easing handles tracking coming and going);
//! applied after the easing, to what is shown; the IK targets in the output stay as solved.
//!
//! **The body stays solid.** Self-contact keeps the solved hand out of the avatar's body, but
//! an arm shown part of the way from last frame's pose to this one's can pass through it: a
//! hand that the solve takes from the collar to in front of the chest in one frame swings
//! through the chest when slowed (on `hungry`, 2-4 frames a clip, up to 87 mm inside on
//! long-armed avatars). With the avatar's skin and contact on, a slowed hand (its contact
//! balls, turned with the hand as shown) that is more than [`SINK`] deeper inside the body
//! than the solve's is shown further along its turn, as little further as keeps it out
//! (bisection on the fraction; the solve itself is the last resort): the body wins over the
//! turn speed.
//!
//! The helpers below are kept out of line: called from the loop, inlined copies made the wasm
//! larger (its size budget, `docs/measurements/2026-12-05-size.md`).

use glam::{Quat, Vec3};

use crate::contact::skin;
use crate::contact::ContactSolver;
use crate::humanoid::bones::{Side, BONE_COUNT};

use super::contact::HandBody;
use super::frame::{Context, Frame};
use super::output::SolveOutput;

/// How much deeper (m) than the solved hand a slowed hand may go into the body before the
/// limit yields, and the least push the reach acts on after the wrist limits: a rounding
/// allowance (the solve leaves its hand balls on the skin, at depth 0), not a tuned figure.
pub(super) const SINK: f32 = 0.001;

/// Halvings of the fraction when the limit yields to the body: the shown turn within 1/256
/// of what keeps the hand out.
const YIELD_STEPS: usize = 8;

/// The arm's bones the limit turns: shoulder, upper arm, forearm, hand.
const ARM: usize = 4;

/// One side's arm as shown last frame (local rotations of the shoulder, upper arm, forearm and
/// hand), when it was solved there.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
struct TurnLimit {
    shown: Option<[Quat; ARM]>,
    /// Frames this side was slowed, since the rig was made or reset (diagnostics).
    limited: u32,
}

/// The turn limit stage: per side the arm as shown last frame, and how often it was slowed.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub(super) struct Limit {
    sides: [TurnLimit; 2],
}

impl Limit {
    /// How many frames `side`'s arm was slowed since the rig was made or reset.
    pub(super) fn limited(&self, side: Side) -> u32 {
        self.sides[side.index()].limited
    }

    /// Forgets the history.
    pub(super) fn restart(&mut self) {
        *self = Limit::default();
    }
}

/// `[shoulder, shoulder x upper, ... x lower, ... x hand]`.
fn composed(l: [Quat; ARM]) -> [Quat; ARM] {
    let mut c = l;
    for k in 1..ARM {
        c[k] = c[k - 1] * l[k];
    }
    c
}

/// Each of `from` turned by the fraction `t` of its `steps` (axis, angle).
#[inline(never)]
fn turned_by(from: [Quat; ARM], steps: [(Vec3, f32); ARM], t: f32) -> [Quat; ARM] {
    core::array::from_fn(|k| {
        (from[k] * Quat::from_axis_angle(steps[k].0, steps[k].1 * t)).normalize()
    })
}

/// The largest turn (radians) of the composed arm from locals `a` to locals `b`.
#[inline(never)]
fn largest_turn(a: [Quat; ARM], b: [Quat; ARM]) -> f32 {
    let (a, b) = (composed(a), composed(b));
    (0..ARM).fold(0.0_f32, |m, k| m.max(step(a[k], b[k]).1))
}

/// The rotation from `a` to `b` (the shorter way) as a unit axis and an angle (radians).
#[inline(never)]
fn step(a: Quat, b: Quat) -> (Vec3, f32) {
    let d = a.conjugate() * b;
    (if d.w < 0.0 { -d } else { d }).normalize().to_axis_angle()
}

impl Limit {
    /// Slows each side's arm to `arm.maxTurnSpeed` (see the module docs) in `out.local` and
    /// in `shown` (what the easing shows); nothing on a session's first frame. Returns, per
    /// side, whether it slowed the arm (what is shown then differs from the solve).
    pub(super) fn run(
        &mut self,
        cx: &Context,
        contact: &ContactSolver,
        f: &Frame,
        shown: &mut [Quat; BONE_COUNT],
        out: &mut SolveOutput,
    ) -> [bool; 2] {
        let dt = cx.dt;
        let mut limited = [false; 2];
        let speed = cx.options.arm.max_turn_speed;
        for side in Side::BOTH {
            let s = side.index();
            let arm = side.arm();
            let upper = arm[1];
            let bones = arm.map(|b| b.index());
            let now = bones.map(|i| out.local[i]);
            let state = &mut self.sides[s];
            let solved = out.solved[upper.index()];
            let last = state.shown.take();
            if !solved {
                continue;
            }
            state.shown = Some(now);
            let (Some(last), Some(dt), true) = (last, dt, speed > 0.0) else {
                continue;
            };
            let allowed = speed * dt;
            let largest = largest_turn(last, now);
            if largest <= allowed || !largest.is_finite() {
                continue;
            }
            // The same fraction of every local turn: first the one that would slow the largest
            // composed turn to the limit were the bones to turn together, then shrunk until
            // the composed turns are within it (each step continuous in the input, so two
            // nearly equal solves are shown nearly equal).
            let steps = core::array::from_fn(|k| step(last[k], now[k]));
            let mut t = allowed / largest;
            let mut slowed = now;
            for _ in 0..5 {
                slowed = turned_by(last, steps, t);
                let turned = largest_turn(last, slowed);
                if turned <= allowed * 1.001 {
                    break;
                }
                t *= allowed / turned;
            }
            if let Some(body) = HandBody::of(cx, contact, f, side) {
                if let Some(t) = body.yielded(cx, side, last, now, steps, slowed, t, out) {
                    slowed = turned_by(last, steps, t);
                }
            }
            for k in 0..ARM {
                // In the hemisphere of the solve's (which the easing kept in last frame's).
                if slowed[k].dot(now[k]) < 0.0 {
                    slowed[k] = -slowed[k];
                }
            }
            for (k, i) in bones.into_iter().enumerate() {
                if cx.driven[i] {
                    out.local[i] = slowed[k];
                    shown[i] = slowed[k];
                }
            }
            state.shown = Some(bones.map(|i| out.local[i]));
            state.limited = state.limited.saturating_add(1);
            limited[s] = true;
        }
        limited
    }
}

impl HandBody<'_> {
    /// The hand's balls and wrist with the arm's locals `arm` (shoulder, upper arm, forearm,
    /// hand; the driven ones written into `out.local`, the arm posed into `out.world`).
    fn posed(
        &self,
        cx: &Context,
        side: Side,
        arm: [Quat; ARM],
        out: &mut SolveOutput,
    ) -> (Vec3, [(Vec3, f32); skin::HAND_SPHERES]) {
        for (k, b) in side.arm().into_iter().enumerate() {
            if cx.driven[b.index()] {
                out.local[b.index()] = arm[k];
            }
        }
        cx.skeleton.forward_arm(side, &out.local, &mut out.world);
        let h = side.arm()[ARM - 1].index();
        let turn = out.world.rotation[h] * self.rotation.conjugate();
        (out.world.position[h], self.turned(turn))
    }

    /// How deep the hand with the arm's locals `arm` is inside the body (0 when out).
    fn depth(&self, cx: &Context, side: Side, arm: [Quat; ARM], out: &mut SolveOutput) -> f32 {
        self.deeper_than(cx, side, arm, 0.0, out)
    }

    /// How deep the hand with the arm's locals `arm` is inside the body, or `floor` if not
    /// deeper than that.
    fn deeper_than(
        &self,
        cx: &Context,
        side: Side,
        arm: [Quat; ARM],
        floor: f32,
        out: &mut SolveOutput,
    ) -> f32 {
        let (wrist, balls) = self.posed(cx, side, arm, out);
        self.surface
            .deepest(wrist, &balls[..self.count], &out.world, floor)
    }

    /// The fraction of the turn from `last` to `now` to show instead of `t` (whose pose is
    /// `slowed`), when the slowed hand is more than [`SINK`] deeper in the body than the
    /// solved one: the least (to 1/2^[`YIELD_STEPS`] of the rest) that keeps it within that;
    /// `None` when the slowed hand is not. Leaves `out.local` at the solve and `out.world`'s
    /// arm at some pose tried (the report poses the arm again).
    #[allow(clippy::too_many_arguments)]
    fn yielded(
        &self,
        cx: &Context,
        side: Side,
        last: [Quat; ARM],
        now: [Quat; ARM],
        steps: [(Vec3, f32); ARM],
        slowed: [Quat; ARM],
        t: f32,
        out: &mut SolveOutput,
    ) -> Option<f32> {
        let mut result = None;
        let sunk = self.depth(cx, side, slowed, out);
        if sunk > SINK {
            // Held to the solve's own depth (a hand the solve left inside, e.g. out of reach,
            // is held to that, not to the skin).
            let floor = self.depth(cx, side, now, out) + SINK;
            if sunk > floor {
                let (mut lo, mut hi) = (t, 1.0f32);
                for _ in 0..YIELD_STEPS {
                    let mid = 0.5 * (lo + hi);
                    let arm = turned_by(last, steps, mid);
                    if self.deeper_than(cx, side, arm, floor, out) > floor {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                result = Some(hi);
            }
        }
        for (k, b) in side.arm().into_iter().enumerate() {
            if cx.driven[b.index()] {
                out.local[b.index()] = now[k];
            }
        }
        result
    }
}
