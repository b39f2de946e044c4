//! Small geometry helpers the IK tests share: directions from angles, components across an
//! axis, rotation angles.

use glam::{Quat, Vec3};

/// Unit vector from two angles (radians): `phi` from +Y, `theta` about +Y from +X.
pub fn dir(theta: f32, phi: f32) -> Vec3 {
    Vec3::new(phi.sin() * theta.cos(), phi.cos(), phi.sin() * theta.sin())
}

/// Component of `v` across (perpendicular to) the unit `axis`.
pub fn across(v: Vec3, axis: Vec3) -> Vec3 {
    v - axis * axis.dot(v)
}

/// Angle (radians) of the rotation between `a` and `b`, accurate near 0 (q and -q equal).
pub fn angle(a: Quat, b: Quat) -> f32 {
    let d = a * b.conjugate();
    2.0 * d.xyz().length().atan2(d.w.abs())
}
