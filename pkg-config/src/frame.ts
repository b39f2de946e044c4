// One frame into the rig's flat input (LAYOUT.input, a Float32Array view into wasm memory),
// reading every user property once, in JavaScript: a throwing getter or a lying `length` throws
// here, with the field named, before wasm is entered, so it can never leave the rig
// half-borrowed. Accepts handrig's own frame `{ timeMs, hands?, pose?, wrists?, torso?, body?,
// face?, imageAspect? }` and MediaPipe's result shapes (frame-hands.ts, frame-body.ts), also
// passed as the frame itself.

import { at, describe, fail, finite, isFiniteNumber, isObject, isView, notFinite, tag, type Bag } from "./errors.js";
import {
  FACE_POINT_COUNT,
  TORSO_BONE_COUNT,
  packBody,
  packFace,
  packPose,
  packTorso,
  packWrists,
} from "./frame-body.js";
import { faceResultAsFace, packFaceTracking } from "./frame-face.js";
import { looksLikeOneHand, packHandList, packResultShape } from "./frame-hands.js";
import { LI } from "./layout.js";

const NOT_A_FRAME = ["Date", "Map", "Set", "WeakMap", "WeakSet", "RegExp", "Promise", "ArrayBuffer", "Function", "Error"];

/** Frames that are certainly not one frame: say what they look like. */
function checkFrameObject(frame: unknown): asserts frame is Bag {
  if (!isObject(frame)) {
    fail("frame", `must be an object { timeMs, hands?, pose?, wrists? }, got ${describe(frame)}`);
  }
  if (Array.isArray(frame)) {
    const first: unknown = frame.length > 0 ? frame[0] : undefined;
    const recording = isObject(first) && ("hands" in first || "timeMs" in first || "pose" in first);
    fail(
      "frame",
      `must be one frame object { timeMs, hands?, pose?, wrists? }, got an array of ${frame.length}` +
        (recording ? " (a whole recording? solve its frames one at a time)" : ""),
    );
  }
  const proto: unknown = Object.getPrototypeOf(frame);
  if (proto === Object.prototype || proto === null) return;
  const t = tag(frame);
  if (isView(frame) || NOT_A_FRAME.includes(t)) {
    fail("frame", `must be a frame object { timeMs, hands?, pose?, wrists? }, got a ${t}`);
  }
}

const KNOWN_FRAME_KEYS = [
  "timeMs", "hands", "pose", "wrists", "torso", "body", "face", "imageAspect", "landmarks", "worldLandmarks", "handedness",
  "handednesses", "multiHandLandmarks", "multiHandWorldLandmarks", "multiHandedness",
  "leftHandLandmarks", "rightHandLandmarks", "poseWorldLandmarks", "poseLandmarks",
  "faceLandmarks", "image", "segmentationMask",
  "leftHandWorldLandmarks", "rightHandWorldLandmarks", "faceBlendshapes", "poseSegmentationMasks",
  // Other MediaPipe results' fields (PoseLandmarker, FaceLandmarker, GestureRecognizer, legacy
  // FaceMesh): not read, but no mistake either.
  "segmentationMasks", "facialTransformationMatrixes", "gestures", "multiFaceLandmarks", "multiFaceGeometry",
];

// Fields a frame may carry by mistake for one handrig reads under another name: silently
// ignored, they would leave the frame without its time or its hands. Looked up only when the
// right name is absent. (No one-letter names: legacy MediaPipe results carry minified fields
// such as `za`.)
const TIME_ALIASES = ["timestamp", "timeStamp", "time", "timestampMs", "timems", "timeMS", "TimeMs", "time_ms"];
const HAND_ALIASES = ["hand", "Hands", "handLandmarks", "multiHands"];
const WRIST_ALIASES = ["wrist", "Wrists"];
const POSE_ALIASES = ["poses", "Pose"];

/** Fields misnamed where the right one is absent (see the lists above). */
function checkMisnamed(frame: Bag, noTime: boolean, noHands: boolean, noWrists: boolean, noPose: boolean): void {
  if (noTime) misnamed(frame, TIME_ALIASES, "handrig reads the time from frame.timeMs (milliseconds)");
  if (noHands) misnamed(frame, HAND_ALIASES, "did you mean frame.hands (an array of hands)?");
  if (noWrists) misnamed(frame, WRIST_ALIASES, "did you mean frame.wrists ({ left?, right? })?");
  if (noPose) misnamed(frame, POSE_ALIASES, "did you mean frame.pose ({ worldLandmarks, landmarks? })?");
}

function misnamed(frame: Bag, aliases: readonly string[], hint: string): void {
  for (let k = 0; k < aliases.length; k++) {
    const v = frame[aliases[k]!];
    if (v !== undefined && v !== null) fail(`frame.${aliases[k]}`, `unknown field: ${hint}`);
  }
}

/**
 * A field handrig does not read holding an object or array: a result nested under a name of the
 * app's (`{ timeMs, holistic: result }`), silently leaving the frame empty. Looked for in a rig's
 * first frames (an app's frames all have one shape) and in frames with nothing to solve; names
 * of one or two letters are a legacy result's minified fields.
 */
function checkUnknownObjects(frame: Bag): void {
  for (const key in frame) {
    if (key.length <= 2 || KNOWN_FRAME_KEYS.includes(key)) continue;
    const v = frame[key];
    if (isObject(v)) {
      fail(
        `frame.${key}`,
        `unknown field holding ${describe(v)}: handrig reads ${KNOWN_FRAME_KEYS.slice(0, 7).join(", ")} and ` +
          "MediaPipe results' own fields from the frame itself (a HolisticLandmarker result is spread into it: " +
          "rig.solve({ timeMs, ...result }); a HandLandmarker result goes in frame.hands, a PoseLandmarker result in frame.pose, " +
          "a FaceLandmarker result is spread too: rig.solve({ timeMs, hands, ...face }))",
      );
    }
  }
}

/**
 * The frame's timestamp (TIME[0]) and whether the frame had none (TIME[1] = 1: TIME[0] is then
 * 0, and the rig puts the frame one 30 fps frame after its last), kept in a typed array rather
 * than returned (a returned double is boxed: an allocation per frame).
 */
export const TIME = new Float64Array(2);

/**
 * Whether the last frame packed carried a face tracker's fields (issue 50). A rig whose frames
 * carry none looks for them only every 30th frame (`lookForFace`): V8 leaves about 30 bytes of
 * garbage per field a frame lacks (measured by tests/node's soak test on the hand video's frames),
 * and an app's frames all have one shape.
 */
export const FACE_FIELDS = { given: false };

/**
 * Packs one frame into `input` and its timestamp (ms) into TIME[0]. Throws a FieldError naming
 * the field on bad input (the input is then partly written; the rig is not called).
 * `lookAround`: also look for misnamed fields (a rig's first frames).
 */
export function packFrame(frame: unknown, input: Float32Array, lookAround: boolean, lookForFace: boolean = true): void {
  at("frame", -1, "");
  checkFrameObject(frame);
  input[LI.handCount] = 0;
  input[LI.posePresent] = 0;
  input[LI.poseHasImage] = 0;
  for (let s = 0; s < 2; s++) input[LI.wrists + s * LI.wristStride + LI.wrist.present] = 0;
  for (let b = 0; b < TORSO_BONE_COUNT; b++) input[LI.torso + b * LI.torsoStride + LI.torsoBone.present] = 0;
  input[LI.bodyPresent] = 0;
  for (let k = 0; k < FACE_POINT_COUNT; k++) input[LI.face + k * LI.faceStride + LI.facePoint.present] = 0;

  const t = frame.timeMs;
  if (t === undefined || t === null) {
    TIME[0] = 0;
    TIME[1] = 1;
  } else {
    if (!isFiniteNumber(t)) notFinite(t, "frame.timeMs");
    TIME[0] = t;
    TIME[1] = 0;
  }
  const aspect = frame.imageAspect;
  if (aspect === undefined || aspect === null) input[LI.imageAspect] = 0;
  else {
    finite(aspect, "frame.imageAspect");
    if ((aspect as number) <= 0) fail("frame.imageAspect", "must be positive (width / height)");
    input[LI.imageAspect] = aspect as number;
  }

  // Whether the frame gave anything to solve (its time aside).
  let given = false;
  const hands = frame.hands;
  let handCount = 0;
  if (hands !== undefined && hands !== null) {
    given = true;
    if (Array.isArray(hands)) handCount = packHandList(hands, input);
    else if (isObject(hands) && !isView(hands)) {
      if (looksLikeOneHand(hands)) {
        fail("frame.hands", "must be an array of hands, got a single hand object: wrap it in [ ]");
      }
      handCount = packResultShape(hands, input, "frame.hands");
      if (handCount < 0) {
        fail("frame.hands", "must be an array of hands or a HandLandmarker / legacy Hands result, got an object with none of their fields");
      }
    } else {
      fail("frame.hands", `must be an array of hands or a HandLandmarker result, got ${describe(hands)}`);
    }
  } else {
    // A MediaPipe result passed as the frame itself.
    handCount = packResultShape(frame, input, "frame");
    if (handCount < 0) handCount = 0;
    else given = true;
  }
  input[LI.handCount] = handCount;

  if (packPose(frame, input)) given = true;

  const wrists = frame.wrists;
  if (wrists !== undefined && wrists !== null) {
    given = true;
    packWrists(wrists, input);
  }
  // Misnamed fields: looked for in a rig's first frames (an app's frames all have one shape: a
  // misnamed field is in the first) and in a frame without its time or with no hand to solve;
  // looking up absent names on every frame showed up as ~60 bytes of garbage a frame in V8
  // (soak.test.mjs).
  const noTime = t === undefined;
  if (lookAround || noTime || handCount === 0) {
    checkMisnamed(frame, noTime, hands === undefined, wrists === undefined, frame.pose === undefined);
  }

  const torso = frame.torso;
  if (torso !== undefined && torso !== null) {
    given = true;
    packTorso(torso, input);
  }

  const body = frame.body;
  if (body !== undefined && body !== null) {
    given = true;
    packBody(body, input);
  }

  const face = frame.face;
  if (face !== undefined && face !== null) {
    given = true;
    if (isObject(face)) faceResultAsFace(face);
    packFace(face, input);
  }
  // A face tracker's face (issue 50): FaceLandmarker / Holistic fields spread into the frame.
  input[LI.faceTracked] = 0;
  FACE_FIELDS.given = false;
  if (lookForFace && packFaceTracking(frame, input, lookAround)) {
    given = true;
    FACE_FIELDS.given = true;
  }

  if (!given && t === undefined) {
    const keys = Object.keys(frame);
    if (keys.length > 0 && !keys.some((k) => KNOWN_FRAME_KEYS.includes(k))) {
      fail("frame", `has none of timeMs, hands, pose, wrists (nor a MediaPipe result's fields); got keys ${keys.slice(0, 8).join(", ")}`);
    }
  }
  // A result nested under a field of the app's leaves every frame with nothing to solve: looked
  // for in a rig's first frames and in any frame that gives nothing (frames with hands, a pose
  // or wrists walk no keys).
  if (lookAround || !given) checkUnknownObjects(frame);
}
