//! Anatomical joint limits of the hand model, with their sources.
//!
//! Every finger has seven degrees of freedom in the report ([`Dof`]); the table gives, per
//! finger and DOF, the range the *tracked* angle is clamped to. Angles are defined on the
//! tracked hand itself (see [`crate::hand`] for the exact geometry), so the limits mean the
//! same thing on every avatar.
//!
//! | finger | DOF | range (deg) | definition | source |
//! | --- | --- | --- | --- | --- |
//! | index..little | MCP flexion | -45 .. 100 | elevation of the proximal phalanx out of the palm plane, palmar + | flexion: Hume et al. 1990 (active MCP flexion about 100); extension: AAOS 1965 (45) |
//! | index..little | MCP abduction | -30 .. 30 | deviation from the wrist-to-MCP line in the palm plane, radial + | AAOS 1965 (20 each way) plus 10 for the wrist-to-MCP line standing in for the metacarpal axis |
//! | index..little | PIP flexion | -10 .. 110 | hinge angle | Hume et al. 1990 (active 105); AAOS 1965 (100/0); 10 of tracking tolerance in extension |
//! | index..little | DIP flexion | -30 .. 90 | hinge angle | AAOS 1965 (90); Kapandji 2007 (passive DIP extension up to about 30) |
//! | index..little | PIP deviation, DIP deviation | -15 .. 15 | sideways bend of the middle (distal) phalanx out of the flexion plane, relative to the phalanx before it, toward the hinge axis + | Minamikawa et al. 1993 (intact PIP under lateral stress: 5 on average, 15 at most) |
//! | ring, little | cupping | 0 .. 30 | tilt of the ray's local palm plane against the palm | El-Shennawy et al. 2001 (CMC IV arcs: 20 flexion, 27 rotation; CMC V: 27, 22) |
//! | thumb | CMC abduction | 0 .. 80 | angle between the 1st metacarpal and the wrist-to-index-MCP line | Barakat et al. 2013 (radial abduction 63 (53..71), anteposition 61 (50..71)) plus 9 for the landmark lines |
//! | thumb | CMC opposition | -30 .. 150 | rotation about the index metacarpal line, from the palm plane (radial) toward palmar | handrig's bounds around Kapandji's opposition cone: retroposition behind the palm plane to grade-10 opposition |
//! | thumb | MCP flexion | -15 .. 70 | hinge angle | Barakat et al. 2013 (flexion 60 (43..70), extension 8 (0..15)); Hume et al. 1990 (active 56) |
//! | thumb | IP flexion | -45 .. 90 | hinge angle | Barakat et al. 2013 (flexion 88 (80..90), extension 12 (0..45)); Hume et al. 1990 (active 73) |
//! | thumb | MCP deviation, IP deviation | -15 .. 15 | as the fingers' PIP and DIP deviation | as the fingers' (the thumb MCP's radial and ulnar deviation is larger; kept at the IP joints' bound) |
//!
//! The joint structure (MCP 2 DOF, PIP and DIP hinges, thumb CMC 2 DOF) follows Cobos et al.
//! 2008; the thumb MCP is a hinge here. The hinges' sideways *deviation* is the collateral
//! ligaments' play, not an active motion: a resting PIP or DIP stands 1-5 degrees off straight
//! (the 2021 radiograph survey below), and under load an intact PIP gives up to 15 (Minamikawa et al.
//! 1993). Tracked fingers whose phalanges are not coplanar take it, within that play, instead
//! of being flattened into one plane. Index and middle rays have no cupping DOF: CMC II and
//! III are nearly immobile (El-Shennawy et al. 2001: 11 and 7 degrees of flexion).
//!
//! Sources:
//! * Hume M.C., Gellman H., McKellop H., Brumfield R.H. "Functional range of motion of the
//!   joints of the hand." J Hand Surg Am 15(2):240-243, 1990.
//! * American Academy of Orthopaedic Surgeons. "Joint Motion: Method of Measuring and
//!   Recording." 1965 (normal values: finger MCP 90/45, PIP 100/0, DIP 90/0, MCP abduction 20).
//! * Kapandji A.I. "The Physiology of the Joints", vol. 1, upper limb, 6th ed., 2007 (finger
//!   joints; the thumb's cone of opposition).
//! * El-Shennawy M., Nakamura K., Patterson R.M., Viegas S.F. "Three-dimensional kinematic
//!   analysis of the second through fifth carpometacarpal joints." J Hand Surg Am
//!   26(6):1030-1035, 2001.
//! * Barakat M.J., Field J., Taylor J. "The range of movement of the thumb." Hand 8(2):179-182,
//!   2013.
//! * Cooney W.P. et al. "The kinesiology of the thumb trapeziometacarpal joint." J Bone Joint
//!   Surg Am 63(9):1371-1381, 1981 (the trapezium's frame sits 80 degrees pronated from the
//!   third metacarpal's: the thumb flexes across, not into, the palm).
//! * Minamikawa Y., Horii E., Amadio P.C., Cooney W.P., Linscheid R.L., An K.N. "Stability and
//!   constraint of the proximal interphalangeal joint." J Hand Surg Am 18(2):198-204, 1993.
//! * Radioulnar interphalangeal joint angles measured on 6236 fingers in radiographs, ages 0
//!   to 19. J Hand Surg Eur Vol, 2021, doi 10.1177/1753193420986122 (mean PIP deviation 1.3-2.5,
//!   DIP 2.1-5.1 degrees, index to little).
//! * Cobos S., Ferre M., Sanchez Uran M.A., Ortego J., Pena C. "Efficient human hand
//!   kinematics for manipulation tasks." IEEE/RSJ IROS 2008.

use crate::humanoid::bones::Finger;

/// One degree of freedom of a finger in [`crate::hand::HandReport`]; the index into its
/// per-finger arrays.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Dof {
    /// Fingers: MCP flexion. Thumb: CMC abduction (angle from the index metacarpal line).
    Base0 = 0,
    /// Fingers: MCP abduction (radial +). Thumb: CMC opposition (rotation about the index
    /// metacarpal line).
    Base1 = 1,
    /// Fingers: PIP flexion. Thumb: MCP flexion.
    Hinge1 = 2,
    /// Fingers: DIP flexion. Thumb: IP flexion.
    Hinge2 = 3,
    /// Ring and little: cupping of the palm at that ray (CMC IV/V). Always 0 elsewhere.
    Cupping = 4,
    /// Fingers: PIP deviation (the middle phalanx's sideways bend out of the flexion plane).
    /// Thumb: MCP deviation.
    Deviation1 = 5,
    /// Fingers: DIP deviation (the distal phalanx's, relative to the middle). Thumb: IP
    /// deviation.
    Deviation2 = 6,
}

/// Number of [`Dof`]s per finger.
pub const DOF_COUNT: usize = 7;

impl Dof {
    /// All seven, in index order.
    pub const ALL: [Dof; DOF_COUNT] = [
        Dof::Base0,
        Dof::Base1,
        Dof::Hinge1,
        Dof::Hinge2,
        Dof::Cupping,
        Dof::Deviation1,
        Dof::Deviation2,
    ];

    /// Index into per-finger arrays.
    #[inline]
    #[must_use]
    pub const fn index(self) -> usize {
        self as usize
    }

    /// Anatomical name of this DOF on `finger` (e.g. "MCP flexion", "CMC opposition").
    #[must_use]
    pub const fn name(self, finger: Finger) -> &'static str {
        match (finger, self) {
            (Finger::Thumb, Dof::Base0) => "CMC abduction",
            (Finger::Thumb, Dof::Base1) => "CMC opposition",
            (Finger::Thumb, Dof::Hinge1) => "MCP flexion",
            (Finger::Thumb, Dof::Hinge2) => "IP flexion",
            (Finger::Thumb, Dof::Cupping) => "(none)",
            (Finger::Thumb, Dof::Deviation1) => "MCP deviation",
            (Finger::Thumb, Dof::Deviation2) => "IP deviation",
            (_, Dof::Base0) => "MCP flexion",
            (_, Dof::Base1) => "MCP abduction",
            (_, Dof::Hinge1) => "PIP flexion",
            (_, Dof::Hinge2) => "DIP flexion",
            (Finger::Ring | Finger::Little, Dof::Cupping) => "cupping",
            (_, Dof::Cupping) => "(none)",
            (_, Dof::Deviation1) => "PIP deviation",
            (_, Dof::Deviation2) => "DIP deviation",
        }
    }
}

/// A closed range in degrees (the table is written in degrees; use [`JointRange::radians`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointRange {
    /// Lower bound, degrees.
    pub min_deg: f32,
    /// Upper bound, degrees.
    pub max_deg: f32,
}

impl JointRange {
    const fn new(min_deg: f32, max_deg: f32) -> Self {
        JointRange { min_deg, max_deg }
    }

    /// `(min, max)` in radians.
    #[inline]
    #[must_use]
    pub fn radians(self) -> (f32, f32) {
        (self.min_deg.to_radians(), self.max_deg.to_radians())
    }

    /// Whether `angle` (radians) is inside, with `slack` radians of tolerance.
    #[inline]
    #[must_use]
    pub fn contains(self, angle: f32, slack: f32) -> bool {
        let (lo, hi) = self.radians();
        angle >= lo - slack && angle <= hi + slack
    }
}

/// The hinges' sideways play (see the module docs).
const DEVIATION: JointRange = JointRange::new(-15.0, 15.0);

const FINGER: [JointRange; DOF_COUNT] = [
    JointRange::new(-45.0, 100.0),
    JointRange::new(-30.0, 30.0),
    JointRange::new(-10.0, 110.0),
    JointRange::new(-30.0, 90.0),
    JointRange::new(0.0, 0.0),
    DEVIATION,
    DEVIATION,
];
const MOBILE_RAY: [JointRange; DOF_COUNT] = [
    FINGER[0],
    FINGER[1],
    FINGER[2],
    FINGER[3],
    JointRange::new(0.0, 30.0),
    DEVIATION,
    DEVIATION,
];
const THUMB: [JointRange; DOF_COUNT] = [
    JointRange::new(0.0, 80.0),
    JointRange::new(-30.0, 150.0),
    JointRange::new(-15.0, 70.0),
    JointRange::new(-45.0, 90.0),
    JointRange::new(0.0, 0.0),
    DEVIATION,
    DEVIATION,
];

/// The limits table, `[finger][dof]` (thumb first; see the module docs for sources).
pub const LIMITS: [[JointRange; DOF_COUNT]; 5] = [THUMB, FINGER, FINGER, MOBILE_RAY, MOBILE_RAY];

/// The range of `dof` on `finger`.
#[inline]
#[must_use]
pub fn limit(finger: Finger, dof: Dof) -> JointRange {
    LIMITS[finger.index()][dof.index()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_are_ordered_and_rest_pose_is_inside() {
        for finger in Finger::ALL {
            for dof in Dof::ALL {
                let r = limit(finger, dof);
                assert!(r.min_deg <= r.max_deg, "{finger:?} {dof:?}");
                // A flat hand with the thumb in the palm plane is anatomically possible.
                assert!(r.contains(0.0, 0.0), "{finger:?} {dof:?}");
            }
        }
        assert_eq!(Dof::Cupping.name(Finger::Little), "cupping");
        assert_eq!(Dof::Base1.name(Finger::Thumb), "CMC opposition");
    }
}
