//! Joint limits as data: what directions a bone may take in its parent bone's frame.
//!
//! A chain bone `i` has a *reference direction* in its parent's frame: the parent bone's own
//! direction (its rest direction, since a bone's frame carries its rest direction onto its
//! current one), or for bone 0 its own rest direction in the chain root's frame. A limit
//! compares the bone's direction `dir` (unit, parent frame) with that reference:
//!
//! * [`JointLimit::Cone`]: the angle between `dir` and the reference is at most `max_angle`.
//! * [`JointLimit::Hinge`]: `dir` lies in the plane perpendicular to `axis` (parent frame)
//!   and its signed angle about `axis` from the reference (projected onto that plane) is in
//!   `[min, max]`. Positive angles turn the reference toward `axis × reference` (right hand).
//!
//! [`JointLimit::constrain`] returns the nearest allowed direction (cone: the cone's edge on the
//! great circle toward `dir`; hinge: the projection onto the plane, its angle clamped to the
//! nearer end of the range) and [`JointLimit::violation`] measures by how much (radians) a
//! direction breaks the limit. [`crate::math::swing_twist`] splits a rotation into swing and twist about an
//! axis (the forearm twist of the arm solvers).

use core::f32::consts::PI;

use glam::{Quat, Vec3};

use crate::error::{Error, Result};
use crate::math::angle::{angle_distance, clamp_angle_nearest};
use crate::math::angle_between;

/// Directions shorter than this are treated as zero (unit-vector arithmetic).
const EPS: f32 = 1e-7;

/// A rotational limit of one chain bone, in its parent bone's frame (see the module docs).
/// Angles in radians. JS: `{ type: "cone", maxAngle }` or
/// `{ type: "hinge", axis: [x, y, z], min, max }` (every field required).
#[derive(Clone, Copy, Debug, PartialEq, serde::Deserialize)]
#[serde(
    tag = "type",
    rename_all = "camelCase",
    rename_all_fields = "camelCase",
    deny_unknown_fields
)]
pub enum JointLimit {
    /// The bone stays within `max_angle` (in `[0, pi]`) of its reference direction: the
    /// parent bone's direction, for bone 0 its own rest direction.
    Cone {
        /// Largest angle (radians) between the bone and its reference direction.
        max_angle: f32,
    },
    /// The bone turns about `axis` only (a hinge carried by the parent bone), between `min`
    /// and `max` radians (in `[-pi, pi]`) from the reference direction.
    Hinge {
        /// Hinge axis in the parent bone's frame (any non-zero length; normalized on setup).
        axis: Vec3,
        /// Smallest signed angle (radians) about `axis` from the reference direction.
        min: f32,
        /// Largest signed angle (radians).
        max: f32,
    },
}

impl JointLimit {
    /// Checks the numbers and returns the limit with a unit hinge axis. `field` is the JS
    /// path of the limit for error messages (`constraints[1]`).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the field (`constraints[1].maxAngle`,
    /// `constraints[2].axis`, ...): a non-finite number, a cone angle outside `[0, pi]`, a zero
    /// hinge axis, hinge angles outside `[-pi, pi]` or `min > max`.
    pub fn validated(&self, field: &str) -> Result<JointLimit> {
        match *self {
            JointLimit::Cone { max_angle } => {
                if !(0.0..=PI).contains(&max_angle) {
                    return Err(Error::invalid(
                        format!("{field}.maxAngle"),
                        "must be an angle in [0, pi] radians",
                    ));
                }
                Ok(*self)
            }
            JointLimit::Hinge { axis, min, max } => {
                let Some(axis) = axis.try_normalize().filter(|a| a.is_finite()) else {
                    return Err(Error::invalid(
                        format!("{field}.axis"),
                        "must be three finite numbers, not all zero",
                    ));
                };
                for (name, v) in [("min", min), ("max", max)] {
                    if !(-PI..=PI).contains(&v) {
                        return Err(Error::invalid(
                            format!("{field}.{name}"),
                            "must be an angle in [-pi, pi] radians",
                        ));
                    }
                }
                if min > max {
                    return Err(Error::invalid(
                        format!("{field}.min"),
                        "must not be greater than max",
                    ));
                }
                Ok(JointLimit::Hinge { axis, min, max })
            }
        }
    }

    /// The hinge axis (parent frame, unit after [`JointLimit::validated`]); `None` for a cone.
    #[inline]
    #[must_use]
    pub fn hinge_axis(&self) -> Option<Vec3> {
        match *self {
            JointLimit::Hinge { axis, .. } => Some(axis),
            JointLimit::Cone { .. } => None,
        }
    }

    /// The allowed direction nearest to `dir` (unit, parent frame) for reference direction
    /// `reference` (unit, parent frame). `previous` (unit, or zero when unknown) breaks ties
    /// where the nearest direction is undefined (a cone's `dir` exactly opposite the
    /// reference, a hinge's `dir` along the axis): the result then keeps to `previous`'s side.
    /// Always a finite unit vector for finite unit inputs.
    #[must_use]
    pub fn constrain(&self, dir: Vec3, reference: Vec3, previous: Vec3) -> Vec3 {
        match *self {
            JointLimit::Cone { max_angle } => {
                if angle_between(dir, reference) <= max_angle {
                    return dir;
                }
                let axis = reference
                    .cross(dir)
                    .try_normalize()
                    .or_else(|| reference.cross(previous).try_normalize())
                    .unwrap_or_else(|| reference.any_orthonormal_vector());
                Quat::from_axis_angle(axis, max_angle) * reference
            }
            JointLimit::Hinge { axis, min, max } => {
                let (x, y) = hinge_basis(axis, reference);
                let (px, py) = (dir.dot(x), dir.dot(y));
                let angle = if px * px + py * py > EPS * EPS {
                    py.atan2(px)
                } else {
                    // Along the axis: no nearest angle; keep the previous one.
                    previous.dot(y).atan2(previous.dot(x))
                };
                let a = clamp_angle_nearest(angle, min, max);
                x * a.cos() + y * a.sin()
            }
        }
    }

    /// By how much (radians) the unit direction `dir` breaks this limit for `reference`:
    /// 0 when allowed; for a cone the excess angle; for a hinge the angle out of the hinge
    /// plane plus the angle outside `[min, max]` within it.
    #[must_use]
    pub fn violation(&self, dir: Vec3, reference: Vec3) -> f32 {
        match *self {
            JointLimit::Cone { max_angle } => (angle_between(dir, reference) - max_angle).max(0.0),
            JointLimit::Hinge { axis, min, max } => {
                let (x, y) = hinge_basis(axis, reference);
                let (px, py) = (dir.dot(x), dir.dot(y));
                let in_plane = (px * px + py * py).sqrt();
                let out_of_plane = dir.dot(axis).abs().atan2(in_plane);
                let angle = py.atan2(px);
                let outside = (angle_distance(angle, clamp_angle_nearest(angle, min, max))).abs();
                out_of_plane + if in_plane > EPS { outside } else { 0.0 }
            }
        }
    }
}

/// The hinge plane's basis: `x` the reference projected onto the plane perpendicular to the
/// unit `axis` (any perpendicular if the reference lies along the axis), `y = axis × x`.
fn hinge_basis(axis: Vec3, reference: Vec3) -> (Vec3, Vec3) {
    let x = (reference - axis * axis.dot(reference))
        .try_normalize()
        .unwrap_or_else(|| axis.any_orthonormal_vector());
    (x, axis.cross(x))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cone_clamps_to_its_edge_toward_the_direction() {
        let c = JointLimit::Cone { max_angle: 0.5 };
        let d = Vec3::new(1.0, 1.0, 0.0).normalize();
        let r = c.constrain(d, Vec3::Y, Vec3::ZERO);
        assert!((angle_between(r, Vec3::Y) - 0.5).abs() < 1e-6);
        assert!(r.z.abs() < 1e-7 && r.x > 0.0);
        assert!(c.violation(r, Vec3::Y) < 1e-6);
        assert!((c.violation(d, Vec3::Y) - (PI / 4.0 - 0.5)).abs() < 1e-6);
        // Opposite: the previous direction picks the side.
        let r = c.constrain(Vec3::NEG_Y, Vec3::Y, Vec3::Z);
        assert!(r.z > 0.4 && r.is_normalized(), "{r}");
    }

    #[test]
    fn hinge_projects_and_clamps() {
        let h = JointLimit::Hinge {
            axis: Vec3::Z,
            min: -0.2,
            max: 1.0,
        }
        .validated("c")
        .unwrap();
        // From reference +X, +90 degrees about +Z is +Y: clamped to 1.0 rad.
        let r = h.constrain(Vec3::new(0.0, 1.0, 0.3).normalize(), Vec3::X, Vec3::ZERO);
        assert!(
            (r - Vec3::new(1f32.cos(), 1f32.sin(), 0.0)).length() < 1e-6,
            "{r}"
        );
        // Just below min on the other side: the nearer end, min.
        let r = h.constrain(Quat::from_rotation_z(-0.5) * Vec3::X, Vec3::X, Vec3::ZERO);
        assert!((r - Quat::from_rotation_z(-0.2) * Vec3::X).length() < 1e-6);
        let d = Quat::from_rotation_z(0.4) * Vec3::X;
        assert!((h.constrain(d, Vec3::X, Vec3::ZERO) - d).length() < 1e-6);
        assert!(h.violation(d, Vec3::X) < 1e-6);
        assert!((h.violation(Vec3::Z, Vec3::X) - PI / 2.0).abs() < 1e-6);
    }

    #[test]
    fn validation_names_the_field() {
        let e = JointLimit::Cone { max_angle: 4.0 }
            .validated("constraints[1]")
            .unwrap_err();
        assert!(e.to_string().starts_with("constraints[1].maxAngle"), "{e}");
        let e = JointLimit::Hinge {
            axis: Vec3::ZERO,
            min: 0.0,
            max: 1.0,
        }
        .validated("constraints[0]")
        .unwrap_err();
        assert!(e.to_string().starts_with("constraints[0].axis"), "{e}");
        let e = JointLimit::Hinge {
            axis: Vec3::X,
            min: f32::NAN,
            max: 1.0,
        }
        .validated("c")
        .unwrap_err();
        assert!(e.to_string().starts_with("c.min"), "{e}");
    }
}
