//! The VRM 1.0 humanoid vocabulary: 55 bones, in three-vrm's order, with the parent map.
//!
//! Names are the lowerCamelCase strings of the VRM 1.0 specification as three-vrm spells them
//! (`VRMHumanBoneName`). [`HumanBone::ALL`] is parent-first: every bone comes after its parent,
//! so a single pass over it is a valid forward-kinematics order.

use core::fmt;

macro_rules! human_bones {
    ($( $variant:ident = $name:literal, parent: $parent:expr, required: $req:literal; )*) => {
        /// One VRM 1.0 humanoid bone.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        #[repr(u8)]
        pub enum HumanBone { $( #[doc = concat!("`", $name, "`")] $variant, )* }

        impl HumanBone {
            /// All bones, parent-first, in three-vrm's `VRMHumanBoneList` order.
            pub const ALL: [HumanBone; BONE_COUNT] = [ $( HumanBone::$variant, )* ];
            const NAMES: [&'static str; BONE_COUNT] = [ $( $name, )* ];
            const PARENTS: [Option<HumanBone>; BONE_COUNT] = [ $( $parent, )* ];
            const REQUIRED: [bool; BONE_COUNT] = [ $( $req, )* ];
        }
    };
}

/// Number of VRM 1.0 humanoid bones.
pub const BONE_COUNT: usize = 55;

use crate::names::named_enum;
use HumanBone as B;

human_bones! {
    Hips = "hips", parent: None, required: true;
    Spine = "spine", parent: Some(B::Hips), required: true;
    Chest = "chest", parent: Some(B::Spine), required: false;
    UpperChest = "upperChest", parent: Some(B::Chest), required: false;
    Neck = "neck", parent: Some(B::UpperChest), required: false;
    Head = "head", parent: Some(B::Neck), required: true;
    LeftEye = "leftEye", parent: Some(B::Head), required: false;
    RightEye = "rightEye", parent: Some(B::Head), required: false;
    Jaw = "jaw", parent: Some(B::Head), required: false;
    LeftUpperLeg = "leftUpperLeg", parent: Some(B::Hips), required: true;
    LeftLowerLeg = "leftLowerLeg", parent: Some(B::LeftUpperLeg), required: true;
    LeftFoot = "leftFoot", parent: Some(B::LeftLowerLeg), required: true;
    LeftToes = "leftToes", parent: Some(B::LeftFoot), required: false;
    RightUpperLeg = "rightUpperLeg", parent: Some(B::Hips), required: true;
    RightLowerLeg = "rightLowerLeg", parent: Some(B::RightUpperLeg), required: true;
    RightFoot = "rightFoot", parent: Some(B::RightLowerLeg), required: true;
    RightToes = "rightToes", parent: Some(B::RightFoot), required: false;
    LeftShoulder = "leftShoulder", parent: Some(B::UpperChest), required: false;
    LeftUpperArm = "leftUpperArm", parent: Some(B::LeftShoulder), required: true;
    LeftLowerArm = "leftLowerArm", parent: Some(B::LeftUpperArm), required: true;
    LeftHand = "leftHand", parent: Some(B::LeftLowerArm), required: true;
    RightShoulder = "rightShoulder", parent: Some(B::UpperChest), required: false;
    RightUpperArm = "rightUpperArm", parent: Some(B::RightShoulder), required: true;
    RightLowerArm = "rightLowerArm", parent: Some(B::RightUpperArm), required: true;
    RightHand = "rightHand", parent: Some(B::RightLowerArm), required: true;
    LeftThumbMetacarpal = "leftThumbMetacarpal", parent: Some(B::LeftHand), required: false;
    LeftThumbProximal = "leftThumbProximal", parent: Some(B::LeftThumbMetacarpal), required: false;
    LeftThumbDistal = "leftThumbDistal", parent: Some(B::LeftThumbProximal), required: false;
    LeftIndexProximal = "leftIndexProximal", parent: Some(B::LeftHand), required: false;
    LeftIndexIntermediate = "leftIndexIntermediate", parent: Some(B::LeftIndexProximal), required: false;
    LeftIndexDistal = "leftIndexDistal", parent: Some(B::LeftIndexIntermediate), required: false;
    LeftMiddleProximal = "leftMiddleProximal", parent: Some(B::LeftHand), required: false;
    LeftMiddleIntermediate = "leftMiddleIntermediate", parent: Some(B::LeftMiddleProximal), required: false;
    LeftMiddleDistal = "leftMiddleDistal", parent: Some(B::LeftMiddleIntermediate), required: false;
    LeftRingProximal = "leftRingProximal", parent: Some(B::LeftHand), required: false;
    LeftRingIntermediate = "leftRingIntermediate", parent: Some(B::LeftRingProximal), required: false;
    LeftRingDistal = "leftRingDistal", parent: Some(B::LeftRingIntermediate), required: false;
    LeftLittleProximal = "leftLittleProximal", parent: Some(B::LeftHand), required: false;
    LeftLittleIntermediate = "leftLittleIntermediate", parent: Some(B::LeftLittleProximal), required: false;
    LeftLittleDistal = "leftLittleDistal", parent: Some(B::LeftLittleIntermediate), required: false;
    RightThumbMetacarpal = "rightThumbMetacarpal", parent: Some(B::RightHand), required: false;
    RightThumbProximal = "rightThumbProximal", parent: Some(B::RightThumbMetacarpal), required: false;
    RightThumbDistal = "rightThumbDistal", parent: Some(B::RightThumbProximal), required: false;
    RightIndexProximal = "rightIndexProximal", parent: Some(B::RightHand), required: false;
    RightIndexIntermediate = "rightIndexIntermediate", parent: Some(B::RightIndexProximal), required: false;
    RightIndexDistal = "rightIndexDistal", parent: Some(B::RightIndexIntermediate), required: false;
    RightMiddleProximal = "rightMiddleProximal", parent: Some(B::RightHand), required: false;
    RightMiddleIntermediate = "rightMiddleIntermediate", parent: Some(B::RightMiddleProximal), required: false;
    RightMiddleDistal = "rightMiddleDistal", parent: Some(B::RightMiddleIntermediate), required: false;
    RightRingProximal = "rightRingProximal", parent: Some(B::RightHand), required: false;
    RightRingIntermediate = "rightRingIntermediate", parent: Some(B::RightRingProximal), required: false;
    RightRingDistal = "rightRingDistal", parent: Some(B::RightRingIntermediate), required: false;
    RightLittleProximal = "rightLittleProximal", parent: Some(B::RightHand), required: false;
    RightLittleIntermediate = "rightLittleIntermediate", parent: Some(B::RightLittleProximal), required: false;
    RightLittleDistal = "rightLittleDistal", parent: Some(B::RightLittleIntermediate), required: false;
}

impl HumanBone {
    /// Position in [`HumanBone::ALL`]; the index of this bone in every per-bone array.
    #[inline]
    #[must_use]
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The bone at `index` in [`HumanBone::ALL`], if in range.
    #[inline]
    #[must_use]
    pub fn from_index(index: usize) -> Option<HumanBone> {
        Self::ALL.get(index).copied()
    }

    /// VRM 1.0 name, e.g. `"leftIndexProximal"`.
    #[inline]
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// Parses a VRM 1.0 bone name (exact, case-sensitive, as three-vrm spells it).
    #[must_use]
    pub fn from_name(name: &str) -> Option<HumanBone> {
        Self::NAMES
            .iter()
            .position(|n| *n == name)
            .map(|i| Self::ALL[i])
    }

    /// Parses a VRM 0.x bone name: identical to 1.0 except the thumb, where 0.x
    /// `thumbProximal` / `thumbIntermediate` / `thumbDistal` are 1.0 `thumbMetacarpal` /
    /// `thumbProximal` / `thumbDistal`. 1.0's `thumbMetacarpal` does not exist in 0.x.
    #[must_use]
    pub fn from_vrm0_name(name: &str) -> Option<HumanBone> {
        match name {
            "leftThumbProximal" => Some(B::LeftThumbMetacarpal),
            "leftThumbIntermediate" => Some(B::LeftThumbProximal),
            "leftThumbDistal" => Some(B::LeftThumbDistal),
            "rightThumbProximal" => Some(B::RightThumbMetacarpal),
            "rightThumbIntermediate" => Some(B::RightThumbProximal),
            "rightThumbDistal" => Some(B::RightThumbDistal),
            "leftThumbMetacarpal" | "rightThumbMetacarpal" => None,
            other => Self::from_name(other),
        }
    }

    /// Parent in the full VRM 1.0 hierarchy (`hips` has none). On a rig where the parent is
    /// absent, the effective parent is the nearest existing ancestor; see [`crate::Skeleton`].
    #[inline]
    #[must_use]
    pub const fn parent(self) -> Option<HumanBone> {
        Self::PARENTS[self as usize]
    }

    /// Whether VRM 1.0 requires this bone (15 bones: hips, spine, head, arms, legs).
    #[inline]
    #[must_use]
    pub const fn is_required(self) -> bool {
        Self::REQUIRED[self as usize]
    }

    /// The same bone on the other side (`leftHand` <-> `rightHand`); central bones map to
    /// themselves.
    #[must_use]
    pub fn mirrored(self) -> HumanBone {
        let name = self.as_str();
        let swapped = if let Some(rest) = name.strip_prefix("left") {
            format_side("right", rest)
        } else if let Some(rest) = name.strip_prefix("right") {
            format_side("left", rest)
        } else {
            return self;
        };
        Self::from_name(&swapped).unwrap_or(self)
    }

    /// Which side the bone belongs to, `None` for central bones.
    #[must_use]
    pub fn side(self) -> Option<Side> {
        let name = self.as_str();
        if name.starts_with("left") {
            Some(Side::Left)
        } else if name.starts_with("right") {
            Some(Side::Right)
        } else {
            None
        }
    }

    /// Whether this is one of the 30 finger bones.
    #[inline]
    #[must_use]
    pub fn is_finger(self) -> bool {
        self.index() >= B::LeftThumbMetacarpal.index()
    }
}

fn format_side(prefix: &str, rest: &str) -> String {
    let mut s = String::with_capacity(prefix.len() + rest.len());
    s.push_str(prefix);
    s.push_str(rest);
    s
}

impl fmt::Display for HumanBone {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A body side, as the avatar sees itself (the avatar's own left and right).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    /// The avatar's left (+X in the VRM 1.0 frame).
    Left,
    /// The avatar's right (-X in the VRM 1.0 frame).
    Right,
}

impl Side {
    /// Both sides, left first; also the index order of per-side arrays (`[left, right]`).
    pub const BOTH: [Side; 2] = [Side::Left, Side::Right];

    /// 0 for left, 1 for right.
    #[inline]
    #[must_use]
    pub const fn index(self) -> usize {
        match self {
            Side::Left => 0,
            Side::Right => 1,
        }
    }

    /// The other side.
    #[inline]
    #[must_use]
    pub const fn opposite(self) -> Side {
        match self {
            Side::Left => Side::Right,
            Side::Right => Side::Left,
        }
    }

    /// `"left"` or `"right"`.
    #[inline]
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
        }
    }

    /// The arm and hand bones of this side: `[shoulder, upperArm, lowerArm, hand]`.
    #[must_use]
    pub const fn arm(self) -> [HumanBone; 4] {
        match self {
            Side::Left => [
                B::LeftShoulder,
                B::LeftUpperArm,
                B::LeftLowerArm,
                B::LeftHand,
            ],
            Side::Right => [
                B::RightShoulder,
                B::RightUpperArm,
                B::RightLowerArm,
                B::RightHand,
            ],
        }
    }

    /// The hand bone of this side.
    #[inline]
    #[must_use]
    pub const fn hand(self) -> HumanBone {
        self.arm()[3]
    }

    /// The three bones of `finger` on this side, base first.
    #[must_use]
    pub const fn finger(self, finger: Finger) -> [HumanBone; 3] {
        let base = match self {
            Side::Left => B::LeftThumbMetacarpal as usize,
            Side::Right => B::RightThumbMetacarpal as usize,
        } + 3 * finger.index();
        [
            HumanBone::ALL[base],
            HumanBone::ALL[base + 1],
            HumanBone::ALL[base + 2],
        ]
    }
}

named_enum! {
    /// A finger, thumb first.
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
    pub enum Finger {
        /// Thumb: metacarpal (CMC joint), proximal (MCP), distal (IP).
        Thumb = "thumb",
        /// Index: proximal (MCP), intermediate (PIP), distal (DIP).
        Index = "index",
        /// Middle finger.
        Middle = "middle",
        /// Ring finger.
        Ring = "ring",
        /// Little finger.
        Little = "little",
    }
}

impl Finger {
    /// MediaPipe hand landmark indices of this finger: `[base, joint1, joint2, tip]`
    /// (thumb: CMC, MCP, IP, TIP; others: MCP, PIP, DIP, TIP).
    #[must_use]
    pub const fn landmarks(self) -> [usize; 4] {
        let b = 1 + 4 * (self as usize);
        [b, b + 1, b + 2, b + 3]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn all_is_parent_first_and_names_round_trip() {
        for (i, b) in HumanBone::ALL.iter().enumerate() {
            assert_eq!(b.index(), i);
            assert_eq!(HumanBone::from_name(b.as_str()), Some(*b));
            if let Some(p) = b.parent() {
                assert!(p.index() < i, "{b} comes before its parent {p}");
            }
        }
        assert_eq!(
            HumanBone::ALL.iter().filter(|b| b.is_required()).count(),
            15
        );
    }

    #[test]
    fn mirrored_and_fingers() {
        assert_eq!(B::LeftIndexDistal.mirrored(), B::RightIndexDistal);
        assert_eq!(B::Spine.mirrored(), B::Spine);
        assert_eq!(
            Side::Right.finger(Finger::Index),
            [
                B::RightIndexProximal,
                B::RightIndexIntermediate,
                B::RightIndexDistal
            ]
        );
        assert_eq!(Side::Left.finger(Finger::Thumb)[0], B::LeftThumbMetacarpal);
        assert_eq!(Finger::Index.landmarks(), [5, 6, 7, 8]);
        assert_eq!(
            HumanBone::from_vrm0_name("rightThumbIntermediate"),
            Some(B::RightThumbProximal)
        );
        assert_eq!(HumanBone::from_vrm0_name("rightThumbMetacarpal"), None);
        assert_eq!(HumanBone::ALL.iter().filter(|b| b.is_finger()).count(), 30);
    }
}
