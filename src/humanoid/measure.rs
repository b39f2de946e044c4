//! Measurements of the avatar at rest that the methods scale by: its arm length and palm
//! length.

use super::bones::{Finger, Side};
use super::skeleton::Skeleton;

/// Mean rest arm length (upper + lower) over the avatar's two arms, m (0 if it has none).
#[must_use]
pub fn avatar_arm_length(skeleton: &Skeleton) -> f32 {
    let mut total = 0.0;
    let mut n = 0.0;
    for side in Side::BOTH {
        let [_, upper, lower, hand] = side.arm();
        if skeleton.has(upper) && skeleton.has(lower) && skeleton.has(hand) {
            total += skeleton.rest_local(lower).length() + skeleton.rest_local(hand).length();
            n += 1.0;
        }
    }
    if n > 0.0 {
        total / n
    } else {
        0.0
    }
}

/// The avatar's palm length: mean over its hands of the hand joint to middle proximal joint
/// distance; without finger bones, arm length x 0.09 / 0.54 (adult proportions).
#[must_use]
pub fn avatar_palm_length(skeleton: &Skeleton) -> f32 {
    let mut sum = 0.0;
    let mut n = 0.0;
    for side in Side::BOTH {
        let middle = side.finger(Finger::Middle)[0];
        if let (Some(h), Some(m)) = (
            skeleton.rest_world(side.hand()),
            skeleton.rest_world(middle),
        ) {
            sum += (m - h).length();
            n += 1.0;
        }
    }
    if n > 0.0 && sum > 0.0 {
        return sum / n;
    }
    avatar_arm_length(skeleton) * 0.09 / 0.54
}
