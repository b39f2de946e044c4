// Live webcam mode: MediaPipe tasks-vision HandLandmarker (+ optional PoseLandmarker) on the
// camera video, results handed to handrig as-is (it accepts MediaPipe's own result shapes).
//
// The model files (.task) are not bundled: the user gives a URL or a local file. The wasm
// runtime ships in the @mediapipe/tasks-vision npm package, served from www/node_modules, and
// can be pointed elsewhere. The video is given to MediaPipe un-mirrored (inputMirrored: false);
// only its preview is shown mirrored.

/** Where the local copy of the tasks-vision wasm runtime is served. */
export const LOCAL_WASM_BASE = new URL("../node_modules/@mediapipe/tasks-vision/wasm", import.meta.url).href;

/** A model source from a URL field and a file input: { modelAssetPath } | { modelAssetBuffer } | null. */
export async function modelSource(url, file) {
  if (file) return { modelAssetBuffer: new Uint8Array(await file.arrayBuffer()) };
  const u = (url || "").trim();
  return u ? { modelAssetPath: u } : null;
}

export class Webcam {
  constructor(video) {
    this.video = video;
    this.hand = null;
    this.pose = null;
    this.stream = null;
    this.lastVideoTime = -1;
  }

  /**
   * Loads the landmarkers and opens the camera. `hand` is required, `pose` optional
   * (each a model source from `modelSource`).
   */
  async start({ hand, pose, wasmBase }) {
    if (!hand) throw new Error("give the hand landmarker model (.task) as a URL or a file");
    const vision = await import("@mediapipe/tasks-vision");
    const fileset = await vision.FilesetResolver.forVisionTasks(wasmBase || LOCAL_WASM_BASE);
    this.hand = await vision.HandLandmarker.createFromOptions(fileset, {
      baseOptions: hand,
      runningMode: "VIDEO",
      numHands: 2,
    });
    if (pose) {
      this.pose = await vision.PoseLandmarker.createFromOptions(fileset, {
        baseOptions: pose,
        runningMode: "VIDEO",
        numPoses: 1,
      });
    }
    this.stream = await navigator.mediaDevices.getUserMedia({ video: { width: 640, height: 480 }, audio: false });
    this.video.srcObject = this.stream;
    this.video.hidden = false;
    await this.video.play();
  }

  /** Runs the landmarkers on a new video frame; null when there is no new frame. */
  detect(nowMs) {
    const v = this.video;
    if (!this.hand || v.readyState < 2 || v.currentTime === this.lastVideoTime) return null;
    this.lastVideoTime = v.currentTime;
    const hands = this.hand.detectForVideo(v, nowMs);
    const pose = this.pose ? this.pose.detectForVideo(v, nowMs) : null;
    const frame = { timeMs: nowMs, hands };
    if (pose && pose.worldLandmarks && pose.worldLandmarks.length) frame.pose = pose;
    return frame;
  }

  stop() {
    for (const t of this.stream?.getTracks() ?? []) t.stop();
    this.stream = null;
    this.video.srcObject = null;
    this.video.hidden = true;
    this.hand?.close();
    this.pose?.close();
    this.hand = this.pose = null;
    this.lastVideoTime = -1;
  }
}
