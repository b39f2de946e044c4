//! Rotations measured and split: the angle between directions, swing-twist decomposition.

use glam::{Quat, Vec3};

use super::angle::angle_distance;

/// Below this squared length a twist is taken as none.
const EPS: f32 = 1e-7;

/// Angle (radians, `[0, pi]`) between unit vectors; accurate near 0 and pi, unlike `acos`.
#[inline]
#[must_use]
pub fn angle_between(a: Vec3, b: Vec3) -> f32 {
    2.0 * (a - b).length().atan2((a + b).length())
}

/// Splits `q` into `swing * twist` with `twist` a rotation about the unit `axis` and `swing`
/// a rotation about an axis perpendicular to it (`q = swing * twist`: the twist acts first,
/// in the frame where `axis` is the bone's direction). At a half-turn swing, where the
/// twist is undefined, the twist is identity.
#[must_use]
pub fn swing_twist(q: Quat, axis: Vec3) -> (Quat, Quat) {
    let v = Vec3::new(q.x, q.y, q.z);
    let p = axis * v.dot(axis);
    let twist = Quat::from_xyzw(p.x, p.y, p.z, q.w);
    let twist = if twist.length_squared() > EPS {
        twist.normalize()
    } else {
        Quat::IDENTITY
    };
    ((q * twist.conjugate()).normalize(), twist)
}

/// The signed angle (radians, `(-pi, pi]`) of `q`'s twist about the unit `axis` (see
/// [`swing_twist`]).
#[must_use]
pub fn twist_angle(q: Quat, axis: Vec3) -> f32 {
    let (_, twist) = swing_twist(q, axis);
    let s = Vec3::new(twist.x, twist.y, twist.z).dot(axis);
    let a = 2.0 * s.atan2(twist.w);
    angle_distance(a, 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn swing_twist_recomposes() {
        let q = Quat::from_euler(glam::EulerRot::XYZ, 0.3, -1.2, 2.0);
        let (s, t) = swing_twist(q, Vec3::X);
        assert!((s * t).dot(q).abs() > 1.0 - 1e-6);
        // The swing has no component about the axis.
        assert!(s.x.abs() < 1e-6);
        let a = twist_angle(Quat::from_rotation_x(2.5) * Quat::IDENTITY, Vec3::X);
        assert!((a - 2.5).abs() < 1e-5);
        let a = twist_angle(Quat::from_rotation_x(-3.0), Vec3::X);
        assert!((a + 3.0).abs() < 1e-5, "{a}");
    }
}
