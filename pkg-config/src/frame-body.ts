// Packing the rest of a frame into the rig's flat input: the pose (handrig's shape,
// PoseLandmarker results, legacy Pose / Holistic top-level landmarks), tracker wrists, the app's
// torso rotations, body-tracker joints and face points.

import {
  COORDINATE_LIMIT,
  at,
  describe,
  fail,
  isFiniteNumber,
  isObject,
  isView,
  notFinite,
  outOfBounds,
  within,
  type Bag,
} from "./errors.js";
import { isListOfLists } from "./frame-hands.js";
import { LAYOUT, LI, POSE_POINTS, SIDES } from "./layout.js";
import { packPoints, readQuat, readVec3 } from "./points.js";

/** Whether a pose was given (it may be empty: nobody detected). */
export function packPose(frame: Bag, input: Float32Array): boolean {
  at("frame.pose", -1, "");
  const pose = frame.pose;
  let list: unknown;
  let name: string;
  let image: unknown;
  let imageName = "";
  if (pose !== undefined && pose !== null) {
    if (Array.isArray(pose) || isView(pose)) {
      list = pose;
      name = "frame.pose";
    } else if (isObject(pose)) {
      list = pose.worldLandmarks;
      name = "frame.pose.worldLandmarks";
      if (list === undefined || list === null) {
        // Holistic results name their pose fields pose*: a whole result here would lose its
        // hands (looked at only when the PoseLandmarker field is absent).
        if (pose.leftHandLandmarks !== undefined || pose.rightHandLandmarks !== undefined) holisticAsPose();
        list = pose.poseWorldLandmarks;
        name = "frame.pose.poseWorldLandmarks";
      }
      if (list === undefined || list === null) {
        fail("frame.pose.worldLandmarks", "is missing (33 world landmarks, meters)");
      }
      image = pose.landmarks;
      imageName = "frame.pose.landmarks";
    } else {
      fail("frame.pose", `must be { worldLandmarks } or a PoseLandmarker result, got ${describe(pose)}`);
    }
  } else {
    list = frame.poseWorldLandmarks;
    name = "frame.poseWorldLandmarks";
    image = frame.poseLandmarks;
    imageName = "frame.poseLandmarks";
    if ((list === undefined || list === null) && image !== undefined && image !== null) {
      list = legacyHolisticPoseWorld(frame);
      name = list === frame.za ? "frame.za" : "frame.ea";
    }
    if (list === undefined || list === null) return false;
  }
  // The pose's image landmarks (optional): with the hands' they check handedness.
  if (image !== undefined && image !== null) {
    let person = -1;
    if (isListOfLists(image)) {
      image = (image as unknown[])[0];
      person = 0;
    }
    if (!(Array.isArray(image) && image.length === 0)) {
      at(imageName, person, "");
      packPoints(image, input, LI.poseImage, POSE_POINTS, 3, imageName, person, "", true);
      input[LI.poseHasImage] = 1;
    }
  }
  // PoseLandmarker: one list per person; the first person drives the avatar.
  let person = -1;
  if (isListOfLists(list)) {
    list = (list as unknown[])[0];
    person = 0;
  }
  if (Array.isArray(list) && list.length === 0) return true; // nobody detected
  at(name, person, "");
  packPoints(list, input, LI.pose, POSE_POINTS, LI.poseStride, name, person, "");
  input[LI.posePresent] = 1;
  return true;
}

/** A Holistic result given as frame.pose: its hands would be dropped without a word. */
function holisticAsPose(): never {
  return fail(
    "frame.pose",
    "is a Holistic result (it has leftHandLandmarks / rightHandLandmarks): as frame.pose its hands would be ignored. " +
      "Spread it into the frame instead: rig.solve({ timeMs, ...holisticResult })",
  );
}

/**
 * A legacy @mediapipe/holistic result passed as it comes: its 0.5 build exports the world
 * landmarks under a minified name (`za`; `ea` in earlier builds), taken when it is a list of 33
 * points.
 */
function legacyHolisticPoseWorld(frame: Bag): unknown[] | undefined {
  return minifiedPoseWorld(frame.za) ?? minifiedPoseWorld(frame.ea);
}

/** `v` if it looks like 33 world landmarks ({x, y, z} objects), else undefined. */
function minifiedPoseWorld(v: unknown): unknown[] | undefined {
  if (!Array.isArray(v) || v.length !== POSE_POINTS) return undefined;
  const p: unknown = v[0];
  return isObject(p) && typeof p.x === "number" ? v : undefined;
}

const WRIST_FIELDS = SIDES.map((side) => ({
  side: `frame.wrists.${side}`,
  position: `frame.wrists.${side}.position`,
  rotation: `frame.wrists.${side}.rotation`,
}));

/** Misspellings of `frame.wrists.left` / `.right` that would otherwise be ignored. */
const WRIST_MISNAMED = ["Left", "Right"] as const;

export function packWrists(wrists: unknown, input: Float32Array): void {
  at("frame.wrists", -1, "");
  if (!isObject(wrists) || Array.isArray(wrists)) {
    fail("frame.wrists", `must be { left?: { position, rotation? }, right?: ... }, got ${describe(wrists)}`);
  }
  for (let s = 0; s < 2; s++) {
    const F = WRIST_FIELDS[s]!;
    at(F.side, -1, "");
    const w = wrists[SIDES[s]!];
    if (w === undefined || w === null) {
      if (w === undefined && wrists[WRIST_MISNAMED[s]!] !== undefined) {
        fail(`frame.wrists.${WRIST_MISNAMED[s]}`, `unknown field: did you mean frame.wrists.${SIDES[s]}?`);
      }
      continue;
    }
    const o = LI.wrists + s * LI.wristStride;
    if (!isObject(w)) fail(F.side, `must be { position: [x, y, z], rotation?: [x, y, z, w] }, got ${describe(w)}`);
    const position = w.position;
    if (position === undefined || position === null) fail(F.position, "is missing (expected [x, y, z])");
    readVec3(position, F.position, input, o + LI.wrist.position, COORDINATE_LIMIT);
    const rotation = w.rotation;
    const hasRotation = rotation !== undefined && rotation !== null;
    if (hasRotation) readQuat(rotation, F.rotation, input, o + LI.wrist.rotation);
    input[o + LI.wrist.hasRotation] = hasRotation ? 1 : 0;
    input[o + LI.wrist.present] = 1;
  }
}

// The torso section's bones and the body section's joints, in their flat order.
const TORSO_BONES: readonly string[] = LAYOUT.torsoBones;
const TORSO_INDEX = new Map(TORSO_BONES.map((name, i) => [name, i]));
const TORSO_FIELDS = TORSO_BONES.map((name) => `frame.torso.${name}`);
const BODY_JOINTS: readonly string[] = LAYOUT.bodyJoints;
const BODY_INDEX = new Map(BODY_JOINTS.map((name, i) => [name, i]));
const BODY_FIELDS = BODY_JOINTS.map((name) => ({
  joint: `frame.body.${name}`,
  confidence: `frame.body.${name}.confidence`,
  confidenceAt: `frame.body.${name}[3]`,
}));

/** The number of torso bones (`LAYOUT.torsoBones`). */
export const TORSO_BONE_COUNT = TORSO_BONES.length;

/**
 * frame.torso: { hips?, spine?, chest?, upperChest?, neck?, head?, leftShoulder?,
 * rightShoulder? }, each a local rotation [x, y, z, w] or { x, y, z, w } (model frame). Keys are
 * walked with for..in (no key array per frame); each value is read once.
 */
export function packTorso(torso: unknown, input: Float32Array): void {
  at("frame.torso", -1, "");
  if (!isObject(torso) || Array.isArray(torso) || isView(torso)) {
    fail("frame.torso", `must be { ${TORSO_BONES.join("?, ")}? } of local rotations [x, y, z, w], got ${describe(torso)}`);
  }
  for (const key in torso) {
    const slot = TORSO_INDEX.get(key);
    if (slot === undefined) {
      fail(`frame.torso.${key}`, `unknown torso bone (expected one of ${TORSO_BONES.join(", ")})`);
    }
    const field = TORSO_FIELDS[slot]!;
    at(field, -1, "");
    const q = torso[key];
    if (q === undefined || q === null) continue;
    const o = LI.torso + slot * LI.torsoStride;
    readQuat(q, field, input, o + LI.torsoBone.rotation);
    input[o + LI.torsoBone.present] = 1;
  }
}

/**
 * frame.body: body-tracker joints { hips?, leftUpperLeg?, ... }, each [x, y, z],
 * [x, y, z, confidence] or { x, y, z, confidence? } (model frame; confidence default 1).
 */
export function packBody(body: unknown, input: Float32Array): void {
  at("frame.body", -1, "");
  if (!isObject(body) || Array.isArray(body) || isView(body)) {
    fail("frame.body", `must be { ${BODY_JOINTS.join("?, ")}? } of joints [x, y, z] or [x, y, z, confidence], got ${describe(body)}`);
  }
  for (let j = 0; j < BODY_JOINTS.length; j++) input[LI.body + j * LI.bodyStride + 3] = 0;
  for (const key in body) {
    const j = BODY_INDEX.get(key);
    if (j === undefined) {
      fail(`frame.body.${key}`, `unknown body joint (expected one of ${BODY_JOINTS.join(", ")})`);
    }
    const F = BODY_FIELDS[j]!;
    at(F.joint, -1, "");
    const v = body[key];
    if (v === undefined || v === null) continue;
    const o = LI.body + j * LI.bodyStride;
    let confidence: unknown = 1;
    let confidenceField = F.confidence;
    if (Array.isArray(v) || isView(v)) {
      const a = v as Bag;
      const m = a.length;
      if (m !== 3 && m !== 4) fail(F.joint, `must be [x, y, z] or [x, y, z, confidence], got ${String(m)} numbers`);
      for (let c = 0; c < 3; c++) {
        const x = a[c];
        if (!within(x, COORDINATE_LIMIT)) outOfBounds(x, COORDINATE_LIMIT, `${F.joint}[${c}]`);
        input[o + c] = x;
      }
      if (m === 4) {
        confidence = a[3];
        confidenceField = F.confidenceAt;
      }
    } else if (isObject(v)) {
      readVec3(v, F.joint, input, o, COORDINATE_LIMIT);
      const c = v.confidence;
      if (c !== undefined && c !== null) confidence = c;
    } else {
      fail(F.joint, `must be [x, y, z], [x, y, z, confidence] or { x, y, z, confidence? }, got ${describe(v)}`);
    }
    if (!isFiniteNumber(confidence)) notFinite(confidence, confidenceField);
    if (confidence < 0 || confidence > 1) fail(confidenceField, `must be in 0..1, got ${confidence}`);
    input[o + 3] = confidence;
  }
  input[LI.bodyPresent] = 1;
}

// Face points from the body tracker that gives `wrists` (the model's own frame), for
// self-contact: `frame.face = { nose?, leftEye?, rightEye?, leftEar?, rightEar?, mouth? }`, in
// the order of the layout's face section (src/flat/layout.rs, `LAYOUT.facePoints`).
const FACE_POINTS: readonly string[] = LAYOUT.facePoints;
const FACE_FIELDS = FACE_POINTS.map((n) => `frame.face.${n}`);

/** The number of face points (the layout's face section). */
export const FACE_POINT_COUNT = FACE_POINTS.length;

export function packFace(face: unknown, input: Float32Array): void {
  at("frame.face", -1, "");
  if (!isObject(face) || Array.isArray(face)) {
    fail("frame.face", `must be { nose?, leftEye?, rightEye?, leftEar?, rightEar?, mouth? } of [x, y, z], got ${describe(face)}`);
  }
  for (const key of Object.keys(face)) {
    if (!FACE_POINTS.includes(key)) {
      fail("frame.face", `unknown point ${JSON.stringify(key)} (expected ${FACE_POINTS.join(", ")})`);
    }
  }
  for (let k = 0; k < FACE_POINTS.length; k++) {
    at(FACE_FIELDS[k]!, -1, "");
    const p = face[FACE_POINTS[k]!];
    if (p === undefined || p === null) continue;
    const o = LI.face + k * LI.faceStride;
    readVec3(p, FACE_FIELDS[k]!, input, o + LI.facePoint.position, COORDINATE_LIMIT);
    input[o + LI.facePoint.present] = 1;
  }
}
