//! The humanoid skeleton of one avatar: which bones exist, their rest positions, and forward
//! kinematics over normalized bones.
//!
//! Normalized bones (three-vrm's `VRMHumanoidRig`): every bone has identity rest rotation, and
//! its local position is its rest world offset from its *effective parent*, the nearest
//! existing humanoid ancestor. A local rotation therefore means the same thing on every avatar:
//! "rotate this bone, in the parent's frame, away from the avatar's rest pose".

use glam::{Quat, Vec3};

use super::bones::{HumanBone, Side, BONE_COUNT};
use super::skin::{SkinMesh, MAX_REST_COORDINATE};
use crate::error::{Error, Result};

/// Which VRM specification the avatar follows; decides its facing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum VrmVersion {
    /// VRM 0.x: the model faces -Z.
    V0,
    /// VRM 1.0: the model faces +Z (handrig's internal frame).
    #[default]
    V1,
}

impl VrmVersion {
    /// `"0"` or `"1"`, as `restPose.vrmVersion` spells it.
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            VrmVersion::V0 => "0",
            VrmVersion::V1 => "1",
        }
    }

    /// Converts a position from the model's own frame to handrig's internal +Z-facing frame
    /// (a 180 degree turn about +Y for VRM 0.x; identity for 1.0). Its own inverse.
    #[inline]
    #[must_use]
    pub fn position_to_internal(self, p: Vec3) -> Vec3 {
        match self {
            VrmVersion::V0 => Vec3::new(-p.x, p.y, -p.z),
            VrmVersion::V1 => p,
        }
    }

    /// Converts a rotation between the model's own frame and the internal frame (conjugation
    /// by the 180 degree Y turn: negate x and z, as three-vrm users do for VRM 0.x). Its own
    /// inverse.
    #[inline]
    #[must_use]
    pub fn rotation_to_internal(self, q: Quat) -> Quat {
        match self {
            VrmVersion::V0 => Quat::from_xyzw(-q.x, q.y, -q.z, q.w),
            VrmVersion::V1 => q,
        }
    }
}

/// World positions and rotations of every bone, indexed by [`HumanBone::index`]. Entries of
/// absent bones are unspecified (kept at rest / identity).
#[derive(Clone, Debug, PartialEq)]
pub struct WorldPose {
    /// World position of each bone's joint (meters).
    pub position: [Vec3; BONE_COUNT],
    /// World rotation of each normalized bone (identity at rest).
    pub rotation: [Quat; BONE_COUNT],
}

impl Default for WorldPose {
    fn default() -> Self {
        WorldPose {
            position: [Vec3::ZERO; BONE_COUNT],
            rotation: [Quat::IDENTITY; BONE_COUNT],
        }
    }
}

/// The message of a rest position beyond [`MAX_REST_COORDINATE`], the number spelled out:
/// formatting an `f32` would bring Rust's float formatting into the `.wasm` (over 10 KiB
/// gzipped). A test checks it against the constant.
const OUT_OF_RANGE: &str = "position out of range: every coordinate must be within 1000 m of \
                            the origin (an avatar, not a planet)";

/// An avatar's humanoid skeleton in handrig's internal frame (+Z facing, see the crate docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Skeleton {
    present: [bool; BONE_COUNT],
    parent: [Option<HumanBone>; BONE_COUNT],
    rest_world: [Vec3; BONE_COUNT],
    rest_local: [Vec3; BONE_COUNT],
    version: VrmVersion,
    /// The look-at point (between the eyes) relative to the head bone at rest, internal frame.
    look_at: Option<Vec3>,
    /// The avatar's skin at rest (internal frame), when the app or the file gave it.
    skin: Option<std::sync::Arc<SkinMesh>>,
    /// Per side, the present bones of the arm from its root (shoulder, else upper arm) down
    /// to the fingers, parent first, and how many: [`Skeleton::forward_arm`]'s walk.
    arm_order: [([HumanBone; ARM_BONES], usize); 2],
}

/// Shoulder, upper arm, lower arm, hand and 15 finger bones.
const ARM_BONES: usize = 19;

impl Skeleton {
    /// Builds a skeleton from rest world positions given **in the model's own frame** (for VRM
    /// 0.x, the -Z-facing frame three-vrm reports), converting to the internal frame.
    ///
    /// # Errors
    /// Non-finite positions, coordinates beyond [`MAX_REST_COORDINATE`], a bone given twice,
    /// or missing VRM 1.0 required bones.
    pub fn new(bones: &[(HumanBone, Vec3)], version: VrmVersion) -> Result<Self> {
        let mut present = [false; BONE_COUNT];
        let mut rest_world = [Vec3::ZERO; BONE_COUNT];
        for &(bone, p) in bones {
            if !p.is_finite() {
                return Err(Error::invalid(
                    format!("restPose.bones.{bone}"),
                    "position must be three finite numbers",
                ));
            }
            if p.abs().max_element() > MAX_REST_COORDINATE {
                return Err(Error::invalid(
                    format!("restPose.bones.{bone}"),
                    OUT_OF_RANGE,
                ));
            }
            if present[bone.index()] {
                return Err(Error::invalid(
                    format!("restPose.bones.{bone}"),
                    "bone given more than once",
                ));
            }
            present[bone.index()] = true;
            rest_world[bone.index()] = version.position_to_internal(p);
        }
        let missing: Vec<&'static str> = HumanBone::ALL
            .iter()
            .filter(|b| b.is_required() && !present[b.index()])
            .map(|b| b.as_str())
            .collect();
        if !missing.is_empty() {
            return Err(Error::MissingRequiredBones(missing));
        }
        let mut parent = [None; BONE_COUNT];
        let mut rest_local = [Vec3::ZERO; BONE_COUNT];
        for bone in HumanBone::ALL {
            if !present[bone.index()] {
                continue;
            }
            let mut p = bone.parent();
            while let Some(candidate) = p {
                if present[candidate.index()] {
                    break;
                }
                p = candidate.parent();
            }
            parent[bone.index()] = p;
            rest_local[bone.index()] = match p {
                Some(p) => rest_world[bone.index()] - rest_world[p.index()],
                None => rest_world[bone.index()],
            };
        }
        let arm_order = Side::BOTH.map(|side| {
            let [shoulder, upper, ..] = side.arm();
            let root = if present[shoulder.index()] {
                shoulder
            } else {
                upper
            };
            let mut order = ([HumanBone::Hips; ARM_BONES], 0);
            for bone in HumanBone::ALL.iter().filter(|b| present[b.index()]) {
                // Below the root: the root itself or a bone whose chain of parents meets it.
                let mut b = Some(*bone);
                while let Some(x) = b.filter(|x| *x != root) {
                    b = parent[x.index()];
                }
                if b.is_some() && order.1 < ARM_BONES {
                    order.0[order.1] = *bone;
                    order.1 += 1;
                }
            }
            order
        });
        Ok(Skeleton {
            present,
            parent,
            rest_world,
            rest_local,
            version,
            look_at: None,
            skin: None,
            arm_order,
        })
    }

    /// The same skeleton with a look-at point: `offset` from the head bone's rest position to
    /// the point between the eyes, meters, **in the model's own frame** (what
    /// [`crate::humanoid::vrm::VrmHumanoid::look_at`] reads from `VRMC_vrm.lookAt.offsetFromHeadBone`
    /// or VRM 0.x `firstPersonBoneOffset`). Self-contact uses it to place the avatar's face
    /// when the avatar has no eye bones. A non-finite offset, or one beyond
    /// [`MAX_REST_COORDINATE`], is ignored (it is a hint).
    #[must_use]
    pub fn with_look_at_offset(mut self, offset: Option<Vec3>) -> Self {
        self.look_at = offset
            .filter(|o| o.is_finite() && o.abs().max_element() <= MAX_REST_COORDINATE)
            .map(|o| self.version.position_to_internal(o));
        self
    }

    /// The same skeleton with its skin at rest ([`SkinMesh`], positions
    /// **in the model's own frame**, converted here): self-contact learns the body's surface
    /// from it ([`crate::contact::skin`]). An empty skin is ignored.
    #[must_use]
    pub fn with_skin(mut self, mut skin: SkinMesh) -> Self {
        if skin.positions.is_empty() {
            self.skin = None;
            return self;
        }
        for p in &mut skin.positions {
            *p = self.version.position_to_internal(*p);
        }
        self.skin = Some(std::sync::Arc::new(skin));
        self
    }

    /// The skin at rest (internal frame), if given.
    #[inline]
    #[must_use]
    pub fn skin(&self) -> Option<&SkinMesh> {
        self.skin.as_deref()
    }

    /// The look-at point relative to the head bone at rest (internal frame), if known.
    #[inline]
    #[must_use]
    pub fn look_at_offset(&self) -> Option<Vec3> {
        self.look_at
    }

    /// The VRM version (facing) of the model this skeleton came from.
    #[inline]
    #[must_use]
    pub fn version(&self) -> VrmVersion {
        self.version
    }

    /// Whether the avatar has `bone`.
    #[inline]
    #[must_use]
    pub fn has(&self, bone: HumanBone) -> bool {
        self.present[bone.index()]
    }

    /// The bones the avatar has, parent-first.
    pub fn bones(&self) -> impl Iterator<Item = HumanBone> + '_ {
        HumanBone::ALL.into_iter().filter(|b| self.has(*b))
    }

    /// Effective parent: the nearest existing humanoid ancestor (`None` for the root).
    #[inline]
    #[must_use]
    pub fn parent(&self, bone: HumanBone) -> Option<HumanBone> {
        self.parent[bone.index()]
    }

    /// Rest world position in the internal frame, if the bone exists.
    #[inline]
    #[must_use]
    pub fn rest_world(&self, bone: HumanBone) -> Option<Vec3> {
        self.has(bone).then(|| self.rest_world[bone.index()])
    }

    /// Rest offset from the effective parent in the internal frame (the normalized bone's
    /// local position); the root's is its world position. Zero for absent bones.
    #[inline]
    #[must_use]
    pub fn rest_local(&self, bone: HumanBone) -> Vec3 {
        self.rest_local[bone.index()]
    }

    /// Forward kinematics: world positions and rotations of every present bone from local
    /// rotations (indexed by [`HumanBone::index`]; entries of absent bones are ignored). The
    /// root stays at its rest position. Allocates nothing.
    pub fn forward(&self, local: &[Quat; BONE_COUNT], out: &mut WorldPose) {
        for bone in HumanBone::ALL {
            if self.present[bone.index()] {
                self.pose_bone(bone.index(), local, out);
            }
        }
    }

    /// [`Skeleton::forward`] of every bone but the 30 finger bones (the torso, head, legs,
    /// arms and hands); the finger entries of `out` are left as they were. What the arm
    /// solvers and self-contact read before the arms are posed, at half the cost.
    pub fn forward_body(&self, local: &[Quat; BONE_COUNT], out: &mut WorldPose) {
        for bone in HumanBone::ALL.iter().take_while(|b| !b.is_finger()) {
            if self.present[bone.index()] {
                self.pose_bone(bone.index(), local, out);
            }
        }
    }

    /// [`Skeleton::forward_body`] of `root` and the body bones below it only, assuming the rest
    /// of `out` is current (`root`'s parent in particular): the neck and head turned after the
    /// torso was posed (the face stage), without posing the torso, legs and arms again. The
    /// same values as `forward_body` where the rest is current. Allocates nothing.
    pub fn forward_subtree(
        &self,
        root: HumanBone,
        local: &[Quat; BONE_COUNT],
        out: &mut WorldPose,
    ) {
        // Bones come after their parents in `HumanBone::ALL`: one pass from the root, a bone
        // posed when its parent was (one bit a bone).
        const _: () = assert!(BONE_COUNT <= u64::BITS as usize);
        let mut posed: u64 = 0;
        for bone in HumanBone::ALL[root.index()..]
            .iter()
            .take_while(|b| !b.is_finger())
        {
            let i = bone.index();
            if !self.present[i] {
                continue;
            }
            let under =
                i == root.index() || self.parent[i].is_some_and(|p| posed & (1 << p.index()) != 0);
            if under {
                self.pose_bone(i, local, out);
                posed |= 1 << i;
            }
        }
    }

    /// Forward kinematics of the side's arm from its root (its shoulder, or its upper arm on an
    /// avatar without shoulder bones) down to the fingers, assuming the rest of `out` is
    /// current (the root's parent in particular): an arm after its IK, without recomputing the
    /// torso, the legs and the other arm. Allocates nothing.
    pub fn forward_arm(&self, side: Side, local: &[Quat; BONE_COUNT], out: &mut WorldPose) {
        let (bones, n) = &self.arm_order[side.index()];
        for bone in &bones[..*n] {
            self.pose_bone(bone.index(), local, out);
        }
    }

    /// World position and rotation of bone `i` from its parent's (already in `out`).
    #[inline]
    fn pose_bone(&self, i: usize, local: &[Quat; BONE_COUNT], out: &mut WorldPose) {
        match self.parent[i] {
            Some(p) => {
                let pr = out.rotation[p.index()];
                out.position[i] = out.position[p.index()] + pr * self.rest_local[i];
                out.rotation[i] = pr * local[i];
            }
            None => {
                out.position[i] = self.rest_local[i];
                out.rotation[i] = local[i];
            }
        }
    }
}

/// A T-pose body for tests (VRM 1.0 frame, meters, +X the avatar's left): hips, spine, head,
/// legs straight down, arms out; no shoulders, chest or fingers.
#[cfg(test)]
pub(crate) fn test_body() -> Vec<(HumanBone, Vec3)> {
    use HumanBone as B;
    vec![
        (B::Hips, Vec3::new(0.0, 1.0, 0.0)),
        (B::Spine, Vec3::new(0.0, 1.1, 0.0)),
        (B::Head, Vec3::new(0.0, 1.6, 0.0)),
        (B::LeftUpperLeg, Vec3::new(0.1, 0.9, 0.0)),
        (B::LeftLowerLeg, Vec3::new(0.1, 0.5, 0.0)),
        (B::LeftFoot, Vec3::new(0.1, 0.1, 0.0)),
        (B::RightUpperLeg, Vec3::new(-0.1, 0.9, 0.0)),
        (B::RightLowerLeg, Vec3::new(-0.1, 0.5, 0.0)),
        (B::RightFoot, Vec3::new(-0.1, 0.1, 0.0)),
        (B::LeftUpperArm, Vec3::new(0.2, 1.4, 0.0)),
        (B::LeftLowerArm, Vec3::new(0.45, 1.4, 0.0)),
        (B::LeftHand, Vec3::new(0.7, 1.4, 0.0)),
        (B::RightUpperArm, Vec3::new(-0.2, 1.4, 0.0)),
        (B::RightLowerArm, Vec3::new(-0.45, 1.4, 0.0)),
        (B::RightHand, Vec3::new(-0.7, 1.4, 0.0)),
    ]
}

#[cfg(test)]
mod tests {

    #[test]
    fn the_range_message_spells_the_constant() {
        assert_eq!(
            OUT_OF_RANGE,
            format!(
                "position out of range: every coordinate must be within \
                 {MAX_REST_COORDINATE} m of the origin (an avatar, not a planet)"
            )
        );
    }

    use super::*;
    use crate::humanoid::bones::HumanBone as B;

    fn minimal() -> Vec<(HumanBone, Vec3)> {
        super::test_body()
    }

    #[test]
    fn effective_parent_skips_missing_bones() {
        let s = Skeleton::new(&minimal(), VrmVersion::V1).unwrap();
        // leftUpperArm's parents leftShoulder, upperChest, chest are absent: spine.
        assert_eq!(s.parent(B::LeftUpperArm), Some(B::Spine));
        assert_eq!(s.parent(B::Head), Some(B::Spine));
        assert!(s
            .rest_local(B::LeftUpperArm)
            .abs_diff_eq(Vec3::new(0.2, 0.3, 0.0), 1e-6));
    }

    #[test]
    fn missing_required_is_an_error_naming_the_bones() {
        let mut bones = minimal();
        bones.retain(|(b, _)| *b != B::Head && *b != B::LeftHand);
        let err = Skeleton::new(&bones, VrmVersion::V1).unwrap_err();
        assert_eq!(err, Error::MissingRequiredBones(vec!["head", "leftHand"]));
        assert!(err.to_string().contains("head, leftHand"));
    }

    #[test]
    fn forward_at_identity_is_rest_and_rotation_moves_children() {
        let s = Skeleton::new(&minimal(), VrmVersion::V1).unwrap();
        let mut local = [Quat::IDENTITY; BONE_COUNT];
        let mut w = WorldPose::default();
        s.forward(&local, &mut w);
        for b in s.bones() {
            assert!((w.position[b.index()] - s.rest_world(b).unwrap()).length() < 1e-6);
        }
        // Bend the left elbow 90 degrees about +Y: the hand swings from +X to -Z.
        local[B::LeftLowerArm.index()] = Quat::from_rotation_y(core::f32::consts::FRAC_PI_2);
        s.forward(&local, &mut w);
        let hand = w.position[B::LeftHand.index()];
        assert!(
            (hand - Vec3::new(0.45, 1.4, -0.25)).length() < 1e-6,
            "{hand}"
        );
        // The arm alone, on a body posed at rest: the same hand, the other arm untouched.
        let mut arm = WorldPose::default();
        s.forward(&[Quat::IDENTITY; BONE_COUNT], &mut arm);
        s.forward_arm(Side::Left, &local, &mut arm);
        assert!((arm.position[B::LeftHand.index()] - hand).length() < 1e-6);
        assert_eq!(
            arm.position[B::RightHand.index()],
            s.rest_world(B::RightHand).unwrap()
        );
    }

    #[test]
    fn a_subtree_posed_again_equals_the_whole_body_posed_again() {
        use crate::humanoid::bones::HumanBone as B;
        // A body with a neck, eyes and a jaw, and shoulders on the upper chest.
        let mut body = minimal();
        body.extend([
            (B::Chest, Vec3::new(0.0, 1.25, 0.0)),
            (B::UpperChest, Vec3::new(0.0, 1.38, 0.0)),
            (B::Neck, Vec3::new(0.0, 1.5, 0.0)),
            (B::LeftEye, Vec3::new(0.03, 1.66, 0.08)),
            (B::RightEye, Vec3::new(-0.03, 1.66, 0.08)),
            (B::Jaw, Vec3::new(0.0, 1.58, 0.03)),
            (B::LeftShoulder, Vec3::new(0.05, 1.42, 0.0)),
        ]);
        let s = Skeleton::new(&body, VrmVersion::V1).unwrap();
        let mut local = [Quat::IDENTITY; BONE_COUNT];
        local[B::Spine.index()] = Quat::from_rotation_z(0.2);
        local[B::LeftLowerArm.index()] = Quat::from_rotation_y(0.7);
        let mut w = WorldPose::default();
        s.forward_body(&local, &mut w);
        // The neck and head turned after the body was posed.
        local[B::Neck.index()] = Quat::from_rotation_y(0.3);
        local[B::Head.index()] = Quat::from_rotation_x(-0.4);
        let mut whole = w.clone();
        s.forward_body(&local, &mut whole);
        s.forward_subtree(B::Neck, &local, &mut w);
        for b in s.bones() {
            let i = b.index();
            assert_eq!(w.position[i], whole.position[i], "{b:?}");
            assert_eq!(w.rotation[i], whole.rotation[i], "{b:?}");
        }
        assert_ne!(
            w.position[B::LeftEye.index()],
            s.rest_world(B::LeftEye).unwrap()
        );
    }

    #[test]
    fn vrm0_rest_is_turned_to_face_plus_z() {
        let s = Skeleton::new(&minimal(), VrmVersion::V0).unwrap();
        // Positions given in the -Z-facing model frame are turned 180 degrees about +Y.
        assert_eq!(s.rest_world(B::LeftHand), Some(Vec3::new(-0.7, 1.4, 0.0)));
        let q = Quat::from_xyzw(0.1, 0.2, 0.3, 0.9).normalize();
        let back = VrmVersion::V0.rotation_to_internal(VrmVersion::V0.rotation_to_internal(q));
        assert!(back.abs_diff_eq(q, 1e-7));
    }
}
