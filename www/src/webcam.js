// Live webcam mode: MediaPipe on the camera video, each result turned into one handrig frame.
//
// Modes (WEBCAM_MODES):
//   holistic  @mediapipe/holistic from npm: pose and both hands of the same camera frame, one
//             model. The default: nothing to fetch, it drives the arms and the fingers.
//   hands     @mediapipe/hands from npm: both hands, with world landmarks; the arms stay at
//             rest. Lighter, and the better choice for a camera that sees only the hands.
//   tasks     @mediapipe/tasks-vision HandLandmarker (+ optional PoseLandmarker) with model
//             files (.task) the user gives as a URL or a file; the wasm runtime is served from
//             the npm package.
// The npm models run on the page's own server (www/node_modules), offline.
//
// Input mapping. The camera image goes to MediaPipe as the camera delivers it, NOT mirrored
// (legacy `selfieMode: false`; tasks-vision never mirrors), so handrig's `inputMirrored` must
// stay false: MediaPipe labels the user's right hand "Left", and handrig sends it, and the
// pose's right arm, to the avatar's right side. Only the preview <video> is shown mirrored.
// For a VTuber-style avatar that mirrors the user (raise your right hand, the avatar raises
// the hand on the same side of the screen), turn on handrig's `mirror` option instead.
//
// What each mode gives handrig (`rig.solve(frame)`, frame = { timeMs, hands, pose, imageAspect }):
//   holistic  hands: [{ handedness, landmarks }] image landmarks only (Holistic has no hand
//             world landmarks: handrig's image-only path, which needs `imageAspect`), labelled
//             as MediaPipe Hands labels (see HOLISTIC_HAND_LABELS); pose: { worldLandmarks }.
//   hands     hands: the legacy Hands result as is (multiHandWorldLandmarks, multiHandedness...).
//   tasks     hands: the HandLandmarkerResult as is; pose: the PoseLandmarkerResult.
// The frame object and its hand entries are reused from frame to frame (handrig reads them
// during solve and keeps nothing).

import { LegacySolution, holisticPoseWorld } from "./mediapipe-solutions.js";
import { HOLISTIC_HAND_LABELS, handsFromHolistic, handsFromLegacyHands, handsFromTasks, poseFrom } from "./recording-format.js";

export const WEBCAM_MODES = {
  holistic: "Holistic: pose + both hands (built in)",
  hands: "Hands only (built in)",
  tasks: "tasks-vision with your .task models",
};

/** Where the local copy of the tasks-vision wasm runtime is served. */
export const LOCAL_WASM_BASE = new URL("../node_modules/@mediapipe/tasks-vision/wasm", import.meta.url).href;

/** A model source from a URL field and a file input: { modelAssetPath } | { modelAssetBuffer } | null. */
export async function modelSource(url, file) {
  if (file) return { modelAssetBuffer: new Uint8Array(await file.arrayBuffer()) };
  const u = (url || "").trim();
  return u ? { modelAssetPath: u } : null;
}

const NO_HANDS = Object.freeze([]);

/** Thrown by start() when stop() was called before it finished. */
export class WebcamStopped extends Error {
  constructor() {
    super("the webcam was stopped while starting");
    this.name = "WebcamStopped";
  }
}

/** What went wrong opening the camera, in words (getUserMedia's DOMException names). */
export function cameraError(e) {
  switch (e?.name) {
    case "NotFoundError":
    case "OverconstrainedError":
      return "no camera found (connect one, or check that no other setting hides it)";
    case "NotAllowedError":
    case "SecurityError":
      return "camera access was denied (allow the camera for this page and try again)";
    case "NotReadableError":
    case "AbortError":
      return "the camera could not be started (another application may be using it)";
    default:
      return `the camera could not be opened: ${e?.message ?? e}`;
  }
}

export class Webcam {
  /**
   * `onFrame(frame, info)` is called once per processed camera frame with the handrig frame
   * and `info` = { index, timeMs, mediapipeMs, handCount, cameraFrames (frames the camera
   * delivered since the start, processed or skipped), tag } (both objects reused: read them in the
   * call). `onError(error)` when processing fails (the webcam is stopped first).
   * `onProgress(text)` while starting.
   */
  constructor(video, { onFrame, onError, onProgress } = {}) {
    this.video = video;
    this.onProgress = onProgress ?? (() => {});
    this.onFrame = onFrame ?? (() => {});
    this.onError = onError ?? ((e) => console.warn("webcam:", e));
    /** Optional `(video) => any`, called just before each MediaPipe call; its value is `info.tag`. */
    this.probe = null;
    /** While true, camera frames are skipped (the avatar keeps the last one). */
    this.paused = false;
    this.mode = null;
    this.solution = null;
    this.hand = null;
    this.pose = null;
    this.stream = null;
    this.running = false;
    this.stopped = false;
    this.busy = false;
    this.lastVideoTime = -1;
    this.results = null;
    this.poseResult = null;
    this.frame = { timeMs: 0, hands: NO_HANDS, pose: null, imageAspect: undefined };
    this.holisticHands = HOLISTIC_HAND_LABELS.map(([, handedness]) => ({ handedness, landmarks: null }));
    this.holisticList = [];
    this.poseSlot = { worldLandmarks: null };
    this.info = { index: -1, timeMs: 0, mediapipeMs: 0, handCount: 0, cameraFrames: 0, tag: undefined };
    this.firstPresented = -1;
    this.pollTimer = 0;
  }

  /** "@mediapipe/holistic 0.5.1675471629", ...: what produced the landmarks. */
  get mediapipeLabel() {
    if (this.solution) return this.solution.label;
    return this.mode === "tasks" ? "@mediapipe/tasks-vision" : "";
  }

  /**
   * Loads MediaPipe and opens the camera. `mode`: a WEBCAM_MODES key. For "tasks": `hand`
   * (required) and `pose` (optional) model sources from `modelSource`, `wasmBase`. For the
   * built-in modes: `cpu` (true, false, or undefined = CPU when WebGL is software).
   */
  async start({ mode = "holistic", hand, pose, wasmBase, cpu } = {}) {
    if (!WEBCAM_MODES[mode]) throw new Error(`unknown webcam mode "${mode}" (expected ${Object.keys(WEBCAM_MODES).join(", ")})`);
    this.mode = mode;
    if (mode === "tasks") {
      // The user's model files first: a bad file is the likelier problem, and it is theirs to fix.
      if (!hand) throw new Error("give the hand landmarker model (.task) as a URL or a file");
      const vision = await import("@mediapipe/tasks-vision");
      const fileset = await vision.FilesetResolver.forVisionTasks(wasmBase || LOCAL_WASM_BASE);
      this.hand = await vision.HandLandmarker.createFromOptions(fileset, { baseOptions: hand, runningMode: "VIDEO", numHands: 2 });
      if (pose) {
        this.pose = await vision.PoseLandmarker.createFromOptions(fileset, { baseOptions: pose, runningMode: "VIDEO", numPoses: 1 });
      }
      this.checkStopped();
      await this.openCamera();
    } else {
      // The camera first: without one (or without permission) there is no point loading models.
      await this.openCamera();
      this.checkStopped();
      this.onProgress(`loading MediaPipe ${mode} (its models come with the page)…`);
      this.solution = await LegacySolution.create(mode, { cpu });
    }
    this.checkStopped();
    this.running = true;
    this.info.index = -1;
    this.firstPresented = -1;
    this.schedule();
  }

  // stop() during start(): give back what was opened meanwhile.
  checkStopped() {
    if (!this.stopped) return;
    this.stop();
    throw new WebcamStopped();
  }

  async openCamera() {
    if (!navigator.mediaDevices?.getUserMedia) throw new Error("this page has no camera access (it needs https or localhost)");
    try {
      this.stream = await navigator.mediaDevices.getUserMedia({
        video: { width: { ideal: 640 }, height: { ideal: 480 } },
        audio: false,
      });
    } catch (e) {
      throw new Error(cameraError(e), { cause: e });
    }
    this.checkStopped();
    this.video.srcObject = this.stream;
    this.video.hidden = false;
    try {
      await this.video.play();
    } catch (e) {
      this.checkStopped(); // play() is interrupted when stop() takes the stream away
      throw e;
    }
  }

  /** Size of the camera image MediaPipe sees. */
  get size() {
    return { width: this.video.videoWidth, height: this.video.videoHeight };
  }

  schedule() {
    if (!this.running) return;
    const v = this.video;
    if (typeof v.requestVideoFrameCallback === "function") v.requestVideoFrameCallback(this.onVideoFrame);
    else this.pollTimer = setTimeout(this.onVideoFrame, 15);
  }

  // One camera frame: run MediaPipe on it (the next frame is asked for when this one is done,
  // so frames that arrive meanwhile are skipped, never queued).
  onVideoFrame = async (_now, metadata) => {
    if (!this.running || this.busy) return;
    const v = this.video;
    if (this.paused || v.readyState < 2 || v.currentTime === this.lastVideoTime) return this.schedule();
    this.lastVideoTime = v.currentTime;
    // Camera frames shown since the start, processed or not.
    const presented = metadata ? metadata.presentedFrames : v.getVideoPlaybackQuality().totalVideoFrames;
    if (this.firstPresented < 0) this.firstPresented = presented;
    this.info.cameraFrames = presented - this.firstPresented + 1;
    this.busy = true;
    try {
      await this.process(performance.now());
    } catch (e) {
      this.stop();
      this.onError(e);
      return;
    } finally {
      this.busy = false;
      if (!this.running) this.release();
    }
    this.schedule();
  };

  async process(nowMs) {
    const v = this.video;
    const info = this.info;
    info.tag = this.probe ? this.probe(v) : undefined;
    const t0 = performance.now();
    const frame = this.frame;
    frame.timeMs = nowMs;
    if (this.mode === "tasks") {
      const hands = this.hand.detectForVideo(v, nowMs);
      const pose = this.pose ? this.pose.detectForVideo(v, nowMs) : null;
      this.results = hands;
      this.poseResult = pose;
      frame.hands = hands;
      frame.pose = pose && pose.worldLandmarks && pose.worldLandmarks.length ? pose : null;
      info.handCount = (hands.handedness ?? hands.handednesses ?? NO_HANDS).length;
    } else {
      const r = await this.solution.detect(v);
      if (!this.running) return;
      this.results = r;
      if (this.mode === "hands") {
        // No hands detected: the result has none of the multiHand* fields.
        frame.hands = r.multiHandedness ? r : NO_HANDS;
        info.handCount = r.multiHandedness ? r.multiHandedness.length : 0;
      } else {
        const list = this.holisticList;
        list.length = 0;
        for (let i = 0; i < HOLISTIC_HAND_LABELS.length; i++) {
          const lm = r[HOLISTIC_HAND_LABELS[i][0]];
          if (lm && lm.length === 21) {
            this.holisticHands[i].landmarks = lm;
            list.push(this.holisticHands[i]);
          }
        }
        frame.hands = list;
        info.handCount = list.length;
        const world = holisticPoseWorld(r);
        this.poseSlot.worldLandmarks = world;
        frame.pose = world && world.length === 33 ? this.poseSlot : null;
        frame.imageAspect = v.videoWidth > 0 && v.videoHeight > 0 ? v.videoWidth / v.videoHeight : undefined;
      }
    }
    info.mediapipeMs = performance.now() - t0;
    info.timeMs = nowMs;
    info.index++;
    this.onFrame(frame, info);
  }

  /** The last processed frame in the recording format: { hands, pose } (copies; allocates). */
  recordParts() {
    const r = this.results;
    if (!r) return { hands: null, pose: null };
    if (this.mode === "hands") return { hands: handsFromLegacyHands(r), pose: null };
    if (this.mode === "holistic") return { hands: handsFromHolistic(r), pose: poseFrom(r.poseLandmarks, holisticPoseWorld(r)) };
    const p = this.poseResult;
    return { hands: handsFromTasks(r), pose: p ? poseFrom(p.landmarks?.[0], p.worldLandmarks?.[0]) : null };
  }

  /** Stops the camera; MediaPipe is closed now, or when the frame in progress is done. */
  stop() {
    this.stopped = true;
    this.running = false;
    clearTimeout(this.pollTimer);
    for (const t of this.stream?.getTracks() ?? []) t.stop();
    this.stream = null;
    this.video.srcObject = null;
    this.video.hidden = true;
    this.lastVideoTime = -1;
    if (!this.busy) this.release();
  }

  release() {
    this.hand?.close();
    this.pose?.close();
    this.solution?.close();
    this.hand = this.pose = this.solution = null;
  }
}
