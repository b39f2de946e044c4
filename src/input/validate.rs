//! The one validation of a frame (`validate_frame`), shared by every input path.

use glam::Vec3;

use super::mediapipe::{hand_landmark, FrameInput, TrackerFace, MAX_HANDS};
use super::torso::{BodyJoint, TORSO_BONES};
use crate::error::Result;
use crate::humanoid::bones::Side;

/// Largest magnitude of any coordinate of a frame's points: meters for world points, wrists,
/// body joints and face points, image units for image landmarks. A body is not 1 km across, and
/// far larger (finite) numbers overflow the solvers' squares into infinities.
pub const COORDINATE_LIMIT: f32 = 1000.0;

/// What is wrong with a point of a frame, if anything.
pub(crate) fn point_problem(p: Vec3) -> Option<&'static str> {
    // One test for the common case: NaN fails every comparison, infinities the bound.
    let a = p.abs();
    if a.x <= COORDINATE_LIMIT && a.y <= COORDINATE_LIMIT && a.z <= COORDINATE_LIMIT {
        None
    } else if !p.is_finite() {
        Some("must be three finite numbers")
    } else {
        Some("must be three numbers within -1000..1000 (meters; image landmarks in image units)")
    }
}

/// The first point of `points` with a problem: its index and the problem.
pub(crate) fn points_problem(points: &[Vec3]) -> Option<(usize, &'static str)> {
    // A pass without branches first (every frame's ~150 points; NaN fails the comparisons).
    let within = points.iter().fold(true, |ok, p| {
        let a = p.abs();
        ok & (a.x <= COORDINATE_LIMIT) & (a.y <= COORDINATE_LIMIT) & (a.z <= COORDINATE_LIMIT)
    });
    if within {
        return None;
    }
    points
        .iter()
        .enumerate()
        .find_map(|(k, p)| point_problem(*p).map(|e| (k, e)))
}

/// Largest distance (m) of a hand's world landmark from its wrist landmark: five times a real
/// hand's reach.
pub const HAND_SPAN_LIMIT: f32 = 1.0;

/// Distance (m) from the origin beyond which a hand's world landmarks that lie within the image
/// (x and y near `0..=1`) are image-normalized landmarks given as world ones: MediaPipe centers a
/// hand's world landmarks on the hand (their mean is within a few centimeters of the origin),
/// while image landmarks are centered near (0.5, 0.5).
pub const HAND_CENTER_LIMIT: f32 = 0.2;

/// Largest distance (m) of a pose world landmark from the origin, which MediaPipe puts between
/// the hips: twice a tall person's height. Pixels given for meters are far beyond it.
pub const POSE_REACH_LIMIT: f32 = 4.0;

/// Whether a hand's world landmarks look image-normalized: the wrist's z is 0 (MediaPipe's
/// image landmarks give depth relative to the wrist: 0 to 1e-6 on all 1,166 image hands of the
/// shared recordings, while world landmarks centered on the hand, or placed in a room like
/// WebXR's joints, almost never have it), x and y of every point within `-0.5..=1.5` (the image,
/// give or take half of it: a hand partly out of view has image landmarks below 0 or above 1),
/// z within `-1..=1`, and their mean farther than [`HAND_CENTER_LIMIT`] from the origin.
fn looks_image_normalized(world: &[Vec3]) -> bool {
    if world
        .get(hand_landmark::WRIST)
        .is_none_or(|w| w.z.abs() > 1e-6)
    {
        return false;
    }
    let mut sum = Vec3::ZERO;
    let mut unit = true;
    for p in world {
        unit &= (-0.5..=1.5).contains(&p.x) & (-0.5..=1.5).contains(&p.y) & (p.z.abs() <= 1.0);
        sum += *p;
    }
    let n = world.len().max(1) as f32;
    unit && (sum / n).length_squared() > HAND_CENTER_LIMIT * HAND_CENTER_LIMIT
}

/// Checks a frame before any state changes: the one check every path runs ([`crate::Rig::solve`]
/// natively, and [`crate::flat::read_input`] after decoding the typed-array layout). Errors
/// name the field as the object API spells it (`frame.hands[1].worldLandmarks[7]`).
///
/// # Errors
/// Non-finite numbers, points beyond [`COORDINATE_LIMIT`], a hand's world landmarks more than
/// [`HAND_SPAN_LIMIT`] from its wrist (centimeters given for meters) or image-normalized
/// ([`HAND_CENTER_LIMIT`]), pose world landmarks beyond [`POSE_REACH_LIMIT`] (pixels given for
/// meters), scores, visibilities or
/// confidences outside `0..=1`, non-unit wrist or torso rotations.
pub(crate) fn validate_frame(frame: &FrameInput) -> Result<()> {
    // (The flat decoder checks the aspect as it reads it.)
    if !(0.01..=100.0).contains(&frame.image_aspect) {
        return Err(crate::error::Error::invalid(
            "frame.imageAspect",
            "must be a number in 0.01..100 (width / height)",
        ));
    }
    validate_frame_with(frame, [true; MAX_HANDS])
}

/// [`validate_frame`], where `metric_world[i]` says whether hand `i`'s world landmarks were
/// given as meters (the flat decoder's image-only hands carry approximate points made from
/// their image landmarks instead, which the hand span check does not apply to).
pub(crate) fn validate_frame_with(
    frame: &FrameInput,
    metric_world: [bool; MAX_HANDS],
) -> Result<()> {
    if !frame.time_ms.is_finite() {
        return Err(crate::error::Error::invalid(
            "frame.timeMs",
            "must be a finite number",
        ));
    }
    for (i, h) in frame.hands().iter().enumerate() {
        if let Some((k, e)) = points_problem(&h.world) {
            return Err(crate::error::Error::invalid(
                format!("frame.hands[{i}].worldLandmarks[{k}]"),
                e,
            ));
        }
        // MediaPipe's world landmarks are meters: a hand is about 0.2 m from wrist to
        // fingertip. Centimeters or millimeters would place the avatar's hand meters away
        // with no error.
        let wrist = h.world[hand_landmark::WRIST];
        if metric_world[i]
            && h.world
                .iter()
                .any(|p| (*p - wrist).length_squared() > HAND_SPAN_LIMIT * HAND_SPAN_LIMIT)
        {
            return Err(crate::error::Error::invalid(
                format!("frame.hands[{i}].worldLandmarks"),
                "the hand is more than 1 m across: world landmarks are meters (centimeters given?)",
            ));
        }
        if metric_world[i] && looks_image_normalized(&h.world) {
            return Err(crate::error::Error::invalid(
                format!("frame.hands[{i}].worldLandmarks"),
                "these look like image-normalized landmarks (within the image's 0..1, centered \
                 far from the origin): world landmarks are meters centered on the hand, MediaPipe's \
                 result.worldLandmarks (its result.landmarks go in landmarks)",
            ));
        }
        if let Some((k, e)) = h.image.as_ref().and_then(|p| points_problem(p)) {
            return Err(crate::error::Error::invalid(
                format!("frame.hands[{i}].landmarks[{k}]"),
                e,
            ));
        }
        if !(0.0..=1.0).contains(&h.score) {
            return Err(crate::error::Error::invalid(
                format!("frame.hands[{i}].score"),
                "must be a number in 0..1",
            ));
        }
    }
    if let Some(p) = &frame.pose {
        if let Some((k, e)) = points_problem(&p.world) {
            return Err(crate::error::Error::invalid(
                format!("frame.pose.worldLandmarks[{k}]"),
                e,
            ));
        }
        // Points within the coordinate limit but beyond a body's reach: pixels for meters.
        let reach = p
            .world
            .iter()
            .fold(0.0f32, |m, q| m.max(q.length_squared()));
        if reach > POSE_REACH_LIMIT * POSE_REACH_LIMIT {
            return Err(crate::error::Error::invalid(
                "frame.pose.worldLandmarks",
                "a point is more than 4 m from the hips: pose world landmarks are meters \
                 centered between the hips (pixels given? MediaPipe's result.worldLandmarks go \
                 here, its result.landmarks in frame.pose.landmarks)",
            ));
        }
        for (k, v) in p.visibility.iter().enumerate() {
            if !(0.0..=1.0).contains(v) {
                return Err(crate::error::Error::invalid(
                    format!("frame.pose.worldLandmarks[{k}].visibility"),
                    "must be a number in 0..1",
                ));
            }
        }
    }
    if let Some((k, e)) = frame.pose_image.as_ref().and_then(|p| points_problem(p)) {
        return Err(crate::error::Error::invalid(
            format!("frame.pose.landmarks[{k}]"),
            e,
        ));
    }
    for side in Side::BOTH {
        if let Some(w) = &frame.wrists[side.index()] {
            if let Some(e) = point_problem(w.position) {
                return Err(crate::error::Error::invalid(
                    format!("frame.wrists.{}.position", side.as_str()),
                    e,
                ));
            }
            if let Some(q) = w.rotation {
                if !q.is_finite() || (q.length() - 1.0).abs() > 1e-2 {
                    return Err(crate::error::Error::invalid(
                        format!("frame.wrists.{}.rotation", side.as_str()),
                        "must be a unit quaternion [x, y, z, w]",
                    ));
                }
            }
        }
    }
    for (bone, q) in TORSO_BONES.iter().zip(frame.torso.iter()) {
        if let Some(q) = q {
            if !q.is_finite() || (q.length() - 1.0).abs() > 1e-2 {
                return Err(crate::error::Error::invalid(
                    format!("frame.torso.{bone}"),
                    "must be a unit quaternion [x, y, z, w]",
                ));
            }
        }
    }
    if let Some(body) = &frame.body {
        for j in BodyJoint::ALL {
            let k = j.index();
            if let Some(e) = point_problem(body.position[k]) {
                return Err(crate::error::Error::invalid(
                    format!("frame.body.{}", j.as_str()),
                    e,
                ));
            }
            if !(0.0..=1.0).contains(&body.confidence[k]) {
                return Err(crate::error::Error::invalid(
                    format!("frame.body.{}.confidence", j.as_str()),
                    "must be a number in 0..1",
                ));
            }
        }
    }
    if let Some(face) = &frame.face {
        for k in 0..TrackerFace::POINTS {
            if let Some(e) = face.point(k).and_then(point_problem) {
                return Err(crate::error::Error::invalid(
                    format!("frame.face.{}", TrackerFace::NAMES[k]),
                    e,
                ));
            }
        }
    }
    if let Some(face) = &frame.face_tracking {
        validate_face(face)?;
    }
    Ok(())
}

/// The face tracker's face: scores in 0..1, a finite column-major matrix with a rotation in it,
/// landmarks within the coordinate limit. (The npm package names the blendshape or landmark
/// before this runs.)
fn validate_face(face: &crate::face::FaceObservation) -> Result<()> {
    use crate::error::Error;
    if face
        .shapes
        .is_some_and(|s| s.iter().any(|v| !(0.0..=1.0).contains(v)))
    {
        return Err(Error::invalid(
            "frame.faceBlendshapes",
            "scores must be in 0..1",
        ));
    }
    if let Some(m) = &face.matrix {
        // Column-major: elements 3, 7, 11 (the bottom row) are 0; row-major puts the
        // translation there. A rotation has no zero column.
        let c0 = m[0] * m[0] + m[1] * m[1] + m[2] * m[2];
        if !(m[3] == 0.0 && m[7] == 0.0 && m[11] == 0.0 && c0 > 1e-12)
            || m.iter().any(|v| !v.is_finite())
        {
            return Err(Error::invalid(
                "frame.facialTransformationMatrixes[0].data",
                "must be a finite 4x4 rotation and translation, column-major (elements 3, 7, 11 \
                 are 0): row-major given?",
            ));
        }
    }
    if face
        .mesh
        .as_ref()
        .is_some_and(|p| points_problem(p).is_some())
    {
        return Err(Error::invalid(
            "frame.faceLandmarks",
            "must be finite numbers within -1000..1000",
        ));
    }
    Ok(())
}
