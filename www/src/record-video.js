// record.html: MediaPipe on every frame of a video file, saved in the shared recording format
// (recording-format.js). Driven by hand in the page, or by tools/record-video.mjs through
// `window.__recordVideo(options)`.
//
// Frame i is shown by seeking the <video> to (i + 0.5) / fps (the middle of the frame's
// display interval, so rounding never lands on a neighbour) and handed to MediaPipe with the
// timestamp i * 1000 / fps: landmark smoothing (Holistic) and tracking see the video's own
// time, however long each frame takes to process.

import { LegacySolution, holisticPoseWorld } from "./mediapipe-solutions.js";
import { RecordingBuilder, handsFromHolistic, handsFromLegacyHands, poseFrom } from "./recording-format.js";

export const RECORD_MODES = ["hands", "holistic", "pose"];

function once(el, event) {
  return new Promise((resolve, reject) => {
    const ok = () => {
      el.removeEventListener("error", bad);
      resolve();
    };
    const bad = () => {
      el.removeEventListener(event, ok);
      reject(new Error(`the video cannot be decoded here: ${el.error?.message || "unsupported format"} (convert it with ffmpeg to H.264 MP4 or VP9 WebM)`));
    };
    el.addEventListener(event, ok, { once: true });
    el.addEventListener("error", bad, { once: true });
  });
}

/**
 * Records frames [from, to) of the video in `video` (an HTMLVideoElement with its `src` set).
 * Options: mode ("hands" | "holistic" | "pose"), fps (the video's frame rate), from (0),
 * to (default: duration * fps), cpu (undefined = auto), source (file name for the output),
 * onProgress(done, total). Returns a RecordingBuilder (`.build()`, `.toJSON()`).
 */
export async function recordVideo(video, { mode = "hands", fps = 30, from = 0, to, cpu, source = "", onProgress } = {}) {
  if (!RECORD_MODES.includes(mode)) throw new Error(`mode must be one of ${RECORD_MODES.join(", ")}, got "${mode}"`);
  if (!(fps > 0 && fps <= 1000)) throw new Error(`fps must be a positive frame rate, got ${fps}`);
  if (video.readyState < 1) await once(video, "loadedmetadata");
  const total = to ?? Math.round(video.duration * fps);
  if (!(Number.isInteger(from) && Number.isInteger(total) && from >= 0 && total > from)) {
    throw new Error(`frame range [${from}, ${total}) is empty or not whole frames`);
  }
  const solution = await LegacySolution.create(mode === "hands" ? "hands" : "holistic", { cpu });
  const rec = new RecordingBuilder({
    source,
    width: video.videoWidth,
    height: video.videoHeight,
    fps,
    mediapipe: solution.label,
    mode,
    inference: solution.cpu ? "cpu" : "gpu",
    settings: solution.options,
  });
  const times = [];
  try {
    for (let i = from; i < total; i++) {
      video.currentTime = (i + 0.5) / fps;
      await once(video, "seeked");
      const timeMs = (i * 1000) / fps;
      const t0 = performance.now();
      const r = await solution.detect(video, timeMs);
      times.push(performance.now() - t0);
      if (mode === "hands") rec.add(i, timeMs, handsFromLegacyHands(r), null);
      else if (mode === "holistic") rec.add(i, timeMs, handsFromHolistic(r), poseFrom(r.poseLandmarks, holisticPoseWorld(r)));
      else rec.add(i, timeMs, null, poseFrom(r.poseLandmarks, holisticPoseWorld(r)));
      onProgress?.(i + 1 - from, total - from);
    }
  } finally {
    solution.close();
  }
  times.sort((a, b) => a - b);
  rec.meta.mediapipeMsMedian = Math.round(times[times.length >> 1] * 10) / 10;
  return rec;
}

// ---------------------------------------------------------------- the page

const $ = (id) => document.getElementById(id);
const video = $("video");
let last = null;
let fileName = "";

function load(file) {
  fileName = file.name;
  video.src = URL.createObjectURL(file);
  $("run").disabled = false;
  $("status").textContent = `${file.name}: ready`;
}

async function run(options) {
  $("run").disabled = true;
  $("download").disabled = true;
  $("status").textContent = "loading MediaPipe…";
  const t0 = performance.now();
  try {
    last = await recordVideo(video, {
      ...options,
      source: options.source ?? fileName,
      onProgress: (done, total) => {
        $("progress").value = done / total;
        $("status").textContent = `frame ${done} / ${total}`;
      },
    });
    const n = last.frames.length;
    const hands = last.frames.filter((f) => f.hands?.length).length;
    const pose = last.frames.filter((f) => f.pose).length;
    $("status").textContent =
      `${n} frames in ${((performance.now() - t0) / 1000).toFixed(1)} s (MediaPipe ${last.meta.mediapipeMsMedian} ms a frame): ` +
      `hands in ${hands}, pose in ${pose}`;
    $("download").disabled = false;
    return last.toJSON();
  } catch (e) {
    $("status").textContent = `failed: ${e.message}`;
    throw e;
  } finally {
    $("run").disabled = false;
  }
}

$("file").addEventListener("change", (e) => {
  const f = e.target.files?.[0];
  if (f) load(f);
});
$("run").addEventListener("click", () => {
  const inference = $("inference").value;
  run({ mode: $("mode").value, fps: Number($("fps").value), cpu: inference === "auto" ? undefined : inference === "cpu" }).catch((e) =>
    console.warn("recording failed:", e),
  );
});
$("download").addEventListener("click", () => {
  if (!last) return;
  const a = document.createElement("a");
  a.href = URL.createObjectURL(new Blob([last.toJSON()], { type: "application/json" }));
  a.download = `${(fileName || "video").replace(/\.[^.]*$/, "")}-${last.meta.mode}.json`;
  a.click();
});

/** For tools/record-video.mjs: records the file already picked in #file; resolves to the JSON text. */
window.__recordVideo = (options) => run(options);
