// The bench's MediaPipe Tasks tracker page (issue 47), driven by tasks.mjs: HandLandmarker and
// PoseLandmarker (@mediapipe/tasks-vision from www's node_modules, the .task models of
// ../shared/data/models, CPU, VIDEO mode) on frames handed in as RGBA pixels; the frames go
// into the shared recording format with the demo's own converters (www/src/recording-format.js).

import { FilesetResolver, HandLandmarker, PoseLandmarker } from "@mediapipe/tasks-vision";
import { RecordingBuilder, handsFromTasks, poseFrom } from "/www/src/recording-format.js";

const fileset = await FilesetResolver.forVisionTasks("/node_modules/@mediapipe/tasks-vision/wasm");
const SETTINGS = { numHands: 2, numPoses: 1, minHandDetectionConfidence: 0.5, minHandPresenceConfidence: 0.5, minTrackingConfidence: 0.5, delegate: "CPU", runningMode: "VIDEO" };

let hand = null;
let pose = null;
let rec = null;
let width = 0;
let height = 0;
const ms = [];

window.__tasks = {
  /** A new clip: fresh landmarkers (no tracking state carried over from the last clip). */
  async start({ source, w, h, fps, version, hands = true }) {
    hand?.close();
    pose?.close();
    hand = null;
    const base = (file) => ({ modelAssetPath: `/models/${file}`, delegate: "CPU" });
    if (hands) {
      hand = await HandLandmarker.createFromOptions(fileset, {
        baseOptions: base("hand_landmarker.task"), runningMode: "VIDEO", numHands: 2,
        minHandDetectionConfidence: 0.5, minHandPresenceConfidence: 0.5, minTrackingConfidence: 0.5,
      });
    }
    pose = await PoseLandmarker.createFromOptions(fileset, { baseOptions: base("pose_landmarker_full.task"), runningMode: "VIDEO", numPoses: 1 });
    width = w;
    height = h;
    ms.length = 0;
    rec = new RecordingBuilder({
      source, width: w, height: h, fps, mediapipe: `@mediapipe/tasks-vision ${version} (${hands ? "hand_landmarker.task, " : ""}pose_landmarker_full.task)`,
      mode: "tasks", inference: "cpu", settings: SETTINGS,
    });
  },
  /** Frame `i` (base64 RGBA, top row first) at `timeMs`. */
  frame(i, timeMs, b64) {
    const bin = atob(b64);
    const px = new Uint8ClampedArray(bin.length);
    for (let k = 0; k < bin.length; k++) px[k] = bin.charCodeAt(k);
    const image = new ImageData(px, width, height);
    const t0 = performance.now();
    const hr = hand ? hand.detectForVideo(image, timeMs) : { handedness: [], landmarks: [] };
    const pr = pose.detectForVideo(image, timeMs);
    ms.push(performance.now() - t0);
    const f = rec.add(i, timeMs, handsFromTasks(hr), poseFrom(pr.landmarks?.[0], pr.worldLandmarks?.[0]));
    return { hands: f.hands.length, pose: !!f.pose };
  },
  finish() {
    const s = [...ms].sort((a, b) => a - b);
    rec.meta.mediapipeMsMedian = Math.round(s[Math.floor(s.length / 2)] * 10) / 10;
    return rec.toJSON();
  },
};
window.__benchReady = true;
