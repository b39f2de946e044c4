// The real walking video's tracker page (issue 51), driven by eval/walk-video.mjs: the Tasks API
// PoseLandmarker (pose_landmarker_full.task, CPU, VIDEO mode, several poses) on a frame handed in
// as RGBA pixels, either whole or as overlapping tiles, each tile scaled before tracking and its
// own landmarker (its own tracking state); every pose found comes back with its image landmarks
// in the whole frame's normalized coordinates.

import { FilesetResolver, PoseLandmarker } from "@mediapipe/tasks-vision";

const fileset = await FilesetResolver.forVisionTasks("/node_modules/@mediapipe/tasks-vision/wasm");

let tiles = [];
let width = 0;
let height = 0;
let full = null;

const round = (x) => Math.round(x * 1e5) / 1e5;

window.__walk = {
  /** `tiles`: [{ x, y, w, h }] in pixels of the whole frame; each is scaled by `scale` and tracked by its own landmarker. */
  async start({ w, h, scale, numPoses, tiles: rects }) {
    for (const t of tiles) t.pose.close();
    width = w;
    height = h;
    full = new OffscreenCanvas(w, h);
    tiles = [];
    for (const r of rects) {
      const pose = await PoseLandmarker.createFromOptions(fileset, {
        baseOptions: { modelAssetPath: "/models/pose_landmarker_full.task", delegate: "CPU" },
        runningMode: "VIDEO", numPoses,
        minPoseDetectionConfidence: 0.5, minPosePresenceConfidence: 0.5, minTrackingConfidence: 0.5,
      });
      const cw = Math.round(r.w * scale);
      const ch = Math.round(r.h * scale);
      const canvas = new OffscreenCanvas(cw, ch);
      tiles.push({ ...r, pose, canvas, ctx: canvas.getContext("2d", { willReadFrequently: true }) });
    }
  },
  /** One frame (base64 RGBA, top row first) at `timeMs`: every tile's poses. */
  frame(timeMs, b64) {
    const bin = atob(b64);
    const px = new Uint8ClampedArray(bin.length);
    for (let k = 0; k < bin.length; k++) px[k] = bin.charCodeAt(k);
    full.getContext("2d").putImageData(new ImageData(px, width, height), 0, 0);
    const out = [];
    const t0 = performance.now();
    tiles.forEach((t, ti) => {
      t.ctx.imageSmoothingEnabled = true;
      t.ctx.imageSmoothingQuality = "high";
      t.ctx.drawImage(full, t.x, t.y, t.w, t.h, 0, 0, t.canvas.width, t.canvas.height);
      const image = t.ctx.getImageData(0, 0, t.canvas.width, t.canvas.height);
      const r = t.pose.detectForVideo(image, timeMs);
      (r.landmarks ?? []).forEach((lm, k) => {
        out.push({
          tile: ti,
          landmarks: lm.map((p) => [round((t.x + p.x * t.w) / width), round((t.y + p.y * t.h) / height), round((p.z * t.w) / width), round(p.visibility ?? 0)]),
          worldLandmarks: r.worldLandmarks[k].map((p) => [round(p.x), round(p.y), round(p.z), round(p.visibility ?? 0)]),
        });
      });
    });
    return { poses: out, ms: performance.now() - t0 };
  },
};
window.__benchReady = true;
