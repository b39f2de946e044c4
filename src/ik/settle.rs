//! The wrist limits applied by the arm solvers with the fingertip kept where alignment put it
//! ([`settle`]; the method is in [`super::wrist`]'s module docs).

use core::f32::consts::PI;

use glam::{Quat, Vec3};

use super::arm::ArmGoal;
use super::wrist::{
    positive, WristFrame, WristLimited, SETTLE_ITERATIONS, SETTLE_TOLERANCE, WRIST_RANGE,
};
use crate::math::clamp;

/// The turn the wrist search scans outward by: 30 degrees of hand rotation per step.
const SCAN_STEP: f32 = 30.0 * PI / 180.0;

/// The furthest the wrist search turns the hand, in multiples of the turn that fits the first
/// forearm.
const MAX_TURN: f32 = 4.0;

/// Limits the goal's hand rotation against the forearm the arm ends on (see the module
/// docs).
///
/// `place` solves the arm for a goal and returns the forearm's world rotation; `lower` is its
/// result for `goal` as given. When the hand is beyond [`WRIST_RANGE`] there, the hand is
/// turned toward the range about the point `goal.target + goal.finger` (the aligned finger
/// point; the wrist itself without one) and the arm solved again for the moved wrist, see
/// the module docs; `goal` is updated (target, hand rotation, finger offset). Returns what
/// changed, `None` when nothing did. The last `place` call is always for the final `goal`.
/// Allocates nothing.
pub(crate) fn settle(
    frame: &WristFrame,
    goal: &mut ArmGoal,
    lower: Quat,
    place: &mut dyn FnMut(&ArmGoal) -> Quat,
) -> Option<WristLimited> {
    let hand0 = goal
        .hand_rotation
        .filter(|q| q.is_finite() && q.length_squared() > 0.5)?
        .normalize();
    let range = &WRIST_RANGE;
    let (local, excess) = frame.limit(lower.inverse() * hand0, range)?;
    let original = *goal;
    let finger0 = goal.finger.filter(|f| f.is_finite()).unwrap_or(Vec3::ZERO);
    let pivot = goal.target + finger0;
    // The path: the hand turned about the pivot by t times the turn that brings it within the
    // range of the first forearm (t = 1 with that forearm kept).
    let step = positive((lower * local).normalize() * hand0.conjugate()).to_scaled_axis();
    let theta = step.length();
    let at = |t: f32, goal: &mut ArmGoal, place: &mut dyn FnMut(&ArmGoal) -> Quat| {
        let turn = Quat::from_scaled_axis(step * t);
        let hand = (turn * hand0).normalize();
        let finger = turn * finger0;
        *goal = ArmGoal {
            hand_rotation: Some(hand),
            finger: original.finger.map(|_| finger),
            target: pivot - finger,
            ..original
        };
        frame.margin(place(goal).inverse() * hand, range)
    };
    let mut result = WristLimited {
        target: goal.target,
        hand_rotation: hand0,
        excess,
        residual: excess,
        iterations: 0,
    };
    if finger0 == Vec3::ZERO || theta <= 0.0 {
        // The wrist stays put, so the forearm does too: one turn is exact.
        goal.hand_rotation = Some((lower * local).normalize());
        result.hand_rotation = goal.hand_rotation.unwrap_or(hand0);
        result.residual = 0.0;
        return Some(result);
    }
    // Scan outward for a t whose hand is within the range of the forearm it gets (margin <=
    // 0), then narrow the bracket down to the boundary by regula falsi (Illinois), keeping the
    // side within the range.
    let dt = (SCAN_STEP / theta).min(0.5);
    let (mut lo, mut g_lo) = (0.0f32, excess);
    let mut hi: Option<(f32, f32)> = None;
    let (mut best_t, mut best_g) = (0.0f32, excess);
    let mut last_t = 0.0;
    let mut t = 0.0;
    while hi.is_none() && result.iterations < SETTLE_ITERATIONS {
        t += dt;
        if t * theta > PI || t > MAX_TURN {
            break;
        }
        let g = at(t, goal, place);
        result.iterations += 1;
        last_t = t;
        if g <= 0.0 {
            hi = Some((t, g));
        } else {
            (lo, g_lo) = (t, g);
            if g < best_g {
                (best_t, best_g) = (t, g);
            }
        }
    }
    let final_t = match hi {
        Some((mut b, mut g_b)) => {
            let mut side = 0i8;
            while g_b < -SETTLE_TOLERANCE
                && (b - lo) * theta > SETTLE_TOLERANCE
                && result.iterations < SETTLE_ITERATIONS
            {
                // The secant's root, kept off the bracket's ends.
                let w = b - lo;
                let c = clamp(b - g_b * w / (g_b - g_lo), lo + 0.05 * w, b - 0.05 * w);
                let g = at(c, goal, place);
                result.iterations += 1;
                last_t = c;
                if g <= 0.0 {
                    (b, g_b) = (c, g);
                    if side < 0 {
                        g_lo *= 0.5;
                    }
                    side = -1;
                } else {
                    (lo, g_lo) = (c, g);
                    if side > 0 {
                        g_b *= 0.5;
                    }
                    side = 1;
                }
            }
            best_g = 0.0;
            b
        }
        // Nowhere within the range along the path: the least excess found.
        None => best_t,
    };
    if last_t != final_t {
        let g = at(final_t, goal, place);
        result.iterations += 1;
        best_g = g.max(0.0);
    }
    result.target = goal.target;
    result.hand_rotation = goal.hand_rotation.unwrap_or(hand0);
    result.residual = best_g;
    Some(result)
}
