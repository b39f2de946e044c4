// The face eval's tracker page (issue 50), driven by eval/face.mjs: FaceLandmarker
// (@mediapipe/tasks-vision from www's node_modules, ../shared/data/models/face_landmarker.task,
// CPU, VIDEO mode, blendshapes and transformation matrices on) on frames handed in as RGBA
// pixels. Returns each frame's first face as MediaPipe gives it (landmarks rounded to 1e-5).

import { FaceLandmarker, FilesetResolver } from "@mediapipe/tasks-vision";

const fileset = await FilesetResolver.forVisionTasks("/node_modules/@mediapipe/tasks-vision/wasm");
let face = null;
let width = 0;
let height = 0;
const r5 = (v) => Math.round(v * 1e5) / 1e5;

window.__face = {
  async start({ w, h }) {
    face?.close();
    face = await FaceLandmarker.createFromOptions(fileset, {
      baseOptions: { modelAssetPath: "/models/face_landmarker.task", delegate: "CPU" },
      runningMode: "VIDEO", numFaces: 1, outputFaceBlendshapes: true, outputFacialTransformationMatrixes: true,
    });
    width = w;
    height = h;
  },
  frame(timeMs, b64) {
    const bin = atob(b64);
    const px = new Uint8ClampedArray(bin.length);
    for (let k = 0; k < bin.length; k++) px[k] = bin.charCodeAt(k);
    const r = face.detectForVideo(new ImageData(px, width, height), timeMs);
    if (!r.faceLandmarks?.length) return null;
    return {
      landmarks: r.faceLandmarks[0].map((p) => [r5(p.x), r5(p.y), r5(p.z)]),
      blendshapes: r.faceBlendshapes[0].categories.map((c) => [c.categoryName, r5(c.score)]),
      matrix: Array.from(r.facialTransformationMatrixes[0].data, r5),
    };
  },
};
window.__benchReady = true;
