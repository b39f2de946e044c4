// The recording format of ../shared/data (see ../shared/README.md): what the demo's live
// session download and tools/record-video.mjs write, and what handrig's Node and browser
// code can replay frame by frame (`rig.solve(frame)` takes its frames as they are).
//
//   { "source": "webcam" | "<video file name>", "width": 640, "height": 480, "fps": 30,
//     "mediapipe": "@mediapipe/holistic 0.5.1675471629", "mode": "holistic",
//     "frames": [{ "frame": 0, "timeMs": 0,
//                  "hands": [{ "handedness": "Left", "score": 0.97,
//                              "landmarks": [[x, y, z] x 21], "worldLandmarks": [[x, y, z] x 21] }],
//                  "pose": { "landmarks": [[x, y, z, visibility] x 33],
//                            "worldLandmarks": [[x, y, z, visibility] x 33] } }, ...] }
//
// As in the shared files: MediaPipe's own axes and units (image landmarks normalized to the
// image, x right, y down; world landmarks in meters), the image NOT mirrored, and handedness
// labelled as MediaPipe Hands labels it (it assumes a mirrored image: on an un-mirrored image
// "Left" is the subject's right hand). Differences by source, all within the shared format:
//   * Holistic gives no hand world landmarks and no handedness score: its hands carry
//     `landmarks` only, and their label comes from the side Holistic reports
//     (`rightHandLandmarks`, the subject's right hand, next to pose RIGHT_WRIST, is "Left").
//   * Hands mode has no `pose`; pose mode has no `hands`.
// `width`, `height`: the image MediaPipe saw. `fps`: the video's rate (tool) or the measured
// rate of processed frames (live). Numbers are rounded to 6 decimals (scores to 4).
// The hands-only shared file (data/hands/right-hand-video-mediapipe.json) is the bare
// `frames` array; `readRecording` accepts both.

const HAND_POINTS = 21;
const POSE_POINTS = 33;

const r6 = (v) => Math.round(v * 1e6) / 1e6 + 0; // + 0: no -0 in the JSON
const r4 = (v) => Math.round(v * 1e4) / 1e4 + 0;

/** [[x, y, z], ...] (or with visibility) from MediaPipe's [{x, y, z, visibility?}, ...]. */
function points(list, withVisibility) {
  const out = new Array(list.length);
  for (let i = 0; i < list.length; i++) {
    const p = list[i];
    out[i] = withVisibility ? [r6(p.x), r6(p.y), r6(p.z), r4(p.visibility ?? 0)] : [r6(p.x), r6(p.y), r6(p.z)];
  }
  return out;
}

/** Hands of a legacy `@mediapipe/hands` result, in the recording format. */
export function handsFromLegacyHands(results) {
  const labels = results.multiHandedness ?? [];
  const image = results.multiHandLandmarks ?? [];
  const world = results.multiHandWorldLandmarks ?? [];
  const hands = [];
  for (let i = 0; i < labels.length; i++) {
    const h = { handedness: labels[i].label, score: r4(labels[i].score), landmarks: points(image[i], false) };
    if (world[i]) h.worldLandmarks = points(world[i], false);
    hands.push(h);
  }
  return hands;
}

/**
 * Holistic's per-side hand lists as MediaPipe Hands labels: Holistic names hands by the
 * subject's body side (its `rightHandLandmarks` is the hand at pose RIGHT_WRIST), Hands labels
 * the subject's right hand "Left" on an un-mirrored image. Measured on data/asl/eat.mp4: the
 * hand Holistic reports as `rightHandLandmarks` is the one the shared recording (MediaPipe
 * Hands) labels "Left", at the pose's right wrist.
 */
export const HOLISTIC_HAND_LABELS = [
  ["rightHandLandmarks", "Left"],
  ["leftHandLandmarks", "Right"],
];

/** Hands of a legacy Holistic result, in the recording format (image landmarks only). */
export function handsFromHolistic(results) {
  const hands = [];
  for (const [key, label] of HOLISTIC_HAND_LABELS) {
    const list = results[key];
    if (list && list.length === HAND_POINTS) hands.push({ handedness: label, landmarks: points(list, false) });
  }
  return hands;
}

/** A pose in the recording format from image and world landmark lists (either may be missing). */
export function poseFrom(landmarks, worldLandmarks) {
  if (!landmarks?.length && !worldLandmarks?.length) return null;
  const pose = {};
  if (landmarks?.length) pose.landmarks = points(landmarks, true);
  if (worldLandmarks?.length) pose.worldLandmarks = points(worldLandmarks, true);
  return pose;
}

/** Hands of a tasks-vision HandLandmarkerResult, in the recording format. */
export function handsFromTasks(result) {
  const labels = result.handedness ?? result.handednesses ?? [];
  const hands = [];
  for (let i = 0; i < labels.length; i++) {
    const c = labels[i][0];
    const h = { handedness: c.categoryName, score: r4(c.score), landmarks: points(result.landmarks[i], false) };
    if (result.worldLandmarks?.[i]) h.worldLandmarks = points(result.worldLandmarks[i], false);
    hands.push(h);
  }
  return hands;
}

/** Collects frames and builds the recording object. */
export class RecordingBuilder {
  /** `meta`: { source, width, height, fps?, mediapipe, mode, ...anything else to keep }. */
  constructor(meta) {
    this.meta = { ...meta };
    this.frames = [];
  }

  get length() {
    return this.frames.length;
  }

  /** Adds one frame: `hands` (array, may be empty; omitted when null) and `pose` (or null). */
  add(frame, timeMs, hands, pose) {
    const f = { frame, timeMs: Math.round(timeMs * 1000) / 1000 };
    if (hands) f.hands = hands;
    if (pose) f.pose = pose;
    this.frames.push(f);
    return f;
  }

  /** The recording object (`fps` measured from the timestamps when the meta has none). */
  build() {
    const meta = { ...this.meta };
    if (meta.fps == null) {
      const n = this.frames.length;
      const span = n > 1 ? this.frames[n - 1].timeMs - this.frames[0].timeMs : 0;
      meta.fps = span > 0 ? Math.round(((n - 1) / span) * 1000 * 100) / 100 : null;
    }
    return { ...meta, frames: this.frames };
  }

  /** The recording as JSON text: one frame per line, so diffs and `head` stay readable. */
  toJSON() {
    const rec = this.build();
    const { frames, ...meta } = rec;
    const head = JSON.stringify(meta).slice(0, -1);
    return `${head}${Object.keys(meta).length ? "," : ""}"frames":[\n${frames.map((f) => JSON.stringify(f)).join(",\n")}\n]}\n`;
  }
}

class FormatError extends Error {
  constructor(path, message) {
    super(`${path}: ${message}`);
    this.name = "RecordingFormatError";
  }
}

function checkPoints(list, n, width, path) {
  if (!Array.isArray(list)) throw new FormatError(path, `must be an array of ${n} points`);
  if (list.length !== n) throw new FormatError(path, `must have ${n} points, got ${list.length}`);
  for (let i = 0; i < n; i++) {
    const p = list[i];
    if (!Array.isArray(p) || !width.includes(p.length)) {
      throw new FormatError(`${path}[${i}]`, `must be [${width.includes(4) ? "x, y, z, visibility" : "x, y, z"}]`);
    }
    for (let c = 0; c < p.length; c++) {
      if (typeof p[c] !== "number" || !Number.isFinite(p[c])) throw new FormatError(`${path}[${i}][${c}]`, "must be a finite number");
    }
  }
}

/**
 * Checks a recording (parsed JSON) against the format above and returns a summary
 * `{ frames, framesWithHands, hands, framesWithPose, withWorldHands, meta }`. Throws a
 * RecordingFormatError naming the first wrong field.
 */
export function readRecording(rec) {
  let frames;
  let meta = {};
  if (Array.isArray(rec)) frames = rec;
  else if (rec && typeof rec === "object" && Array.isArray(rec.frames)) {
    ({ frames, ...meta } = rec);
    for (const k of ["width", "height"]) {
      if (meta[k] != null && !(Number.isInteger(meta[k]) && meta[k] > 0)) throw new FormatError(k, "must be a positive integer");
    }
  } else throw new FormatError("recording", "must be an array of frames or an object with `frames`");
  const sum = { frames: frames.length, framesWithHands: 0, hands: 0, framesWithPose: 0, withWorldHands: 0, meta };
  let lastTime = -Infinity;
  frames.forEach((f, i) => {
    const at = `frames[${i}]`;
    if (!f || typeof f !== "object") throw new FormatError(at, "must be a frame object");
    if (!Number.isInteger(f.frame) || f.frame < 0) throw new FormatError(`${at}.frame`, "must be a frame number (integer >= 0)");
    if (typeof f.timeMs !== "number" || !Number.isFinite(f.timeMs)) throw new FormatError(`${at}.timeMs`, "must be a finite number");
    if (f.timeMs < lastTime) throw new FormatError(`${at}.timeMs`, `goes back in time (${f.timeMs} after ${lastTime})`);
    lastTime = f.timeMs;
    if (f.hands !== undefined) {
      if (!Array.isArray(f.hands)) throw new FormatError(`${at}.hands`, "must be an array");
      f.hands.forEach((h, j) => {
        const hp = `${at}.hands[${j}]`;
        if (h.handedness !== "Left" && h.handedness !== "Right") throw new FormatError(`${hp}.handedness`, 'must be "Left" or "Right"');
        if (h.score !== undefined && !(h.score >= 0 && h.score <= 1)) throw new FormatError(`${hp}.score`, "must be in 0..1");
        checkPoints(h.landmarks, HAND_POINTS, [3], `${hp}.landmarks`);
        if (h.worldLandmarks !== undefined) {
          checkPoints(h.worldLandmarks, HAND_POINTS, [3], `${hp}.worldLandmarks`);
          sum.withWorldHands++;
        }
      });
      if (f.hands.length) sum.framesWithHands++;
      sum.hands += f.hands.length;
    }
    if (f.pose !== undefined) {
      if (!f.pose || typeof f.pose !== "object") throw new FormatError(`${at}.pose`, "must be { landmarks, worldLandmarks }");
      if (f.pose.landmarks !== undefined) checkPoints(f.pose.landmarks, POSE_POINTS, [3, 4], `${at}.pose.landmarks`);
      if (f.pose.worldLandmarks !== undefined) checkPoints(f.pose.worldLandmarks, POSE_POINTS, [3, 4], `${at}.pose.worldLandmarks`);
      if (f.pose.landmarks === undefined && f.pose.worldLandmarks === undefined) {
        throw new FormatError(`${at}.pose`, "has neither landmarks nor worldLandmarks");
      }
      sum.framesWithPose++;
    }
  });
  return sum;
}
