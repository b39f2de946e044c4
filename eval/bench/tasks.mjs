#!/usr/bin/env node
// Tracks the bench clips with the MediaPipe Tasks API (issue 47): HandLandmarker and
// PoseLandmarker (@mediapipe/tasks-vision 1.1, in www's dependencies) with the .task models of
// ../shared/data/models (Apache-2.0), in headless Chromium (tasks-page.js), on every frame of
// each eval/bench/clips/AVATAR-CLIP.mp4 decoded by ffmpeg; writes AVATAR-CLIP-tasks.json in the
// shared recording format (hands with world landmarks and handedness, pose with world landmarks).
//
//   node eval/bench/tasks.mjs [--avatars woman,child] [--clips reach,fist,...]
//   node eval/bench/tasks.mjs --legs [--avatars woman,man,child,primitive] [--clips walk,...]
//   node eval/bench/tasks.mjs --contact [--avatars woman,man,child]
//
// --legs tracks the leg clips (whole body) with the PoseLandmarker alone (no hands: they are a
// few pixels wide at that framing, and the leg scores do not use them).

import { execFileSync } from "node:child_process";
import { basename, join } from "node:path";
import { readFileSync, writeFileSync } from "node:fs";
import { parseArgs } from "node:util";
import { AVATARS, CONTACT_AVATARS, LEG_AVATARS, REPO, recordingFile, videoFile } from "./common.mjs";
import { CLIPS, CONTACT_CLIPS, FPS, LEG_CLIPS, PITCHED_LEG_CLIPS } from "./motions.mjs";
import { HEIGHT, WIDTH, openBenchPage } from "./render.mjs";

const tasksFile = (avatar, clip) => recordingFile(avatar, clip, "tasks");

const { values: o } = parseArgs({ options: { avatars: { type: "string" }, clips: { type: "string" }, legs: { type: "boolean" }, pitched: { type: "boolean" }, contact: { type: "boolean" } } });
const avatars = (o.avatars ?? (o.legs ? LEG_AVATARS : o.contact ? CONTACT_AVATARS : AVATARS).join(",")).split(",");
const all = o.legs ? (o.pitched ? PITCHED_LEG_CLIPS : LEG_CLIPS) : o.contact ? CONTACT_CLIPS : CLIPS;
const clips = o.clips ? all.filter((c) => o.clips.split(",").includes(c.id)) : all;
const version = JSON.parse(readFileSync(join(REPO, "www", "node_modules", "@mediapipe", "tasks-vision", "package.json"), "utf8")).version;
const t0 = Date.now();
const { page, errors, close } = await openBenchPage("tasks-page.html");
try {
  for (const avatar of avatars) {
    for (const clip of clips) {
      if (clip.avatar && clip.avatar !== avatar) continue; // a contact clip is its avatar's own
      const video = videoFile(avatar, clip);
      const raw = execFileSync("ffmpeg", ["-v", "error", "-i", video, "-f", "rawvideo", "-pix_fmt", "rgba", "-"], { maxBuffer: 1 << 30 });
      const size = WIDTH * HEIGHT * 4;
      const n = raw.length / size;
      if (n !== clip.frames) throw new Error(`${video}: ${n} frames decoded, the clip has ${clip.frames}`);
      await page.evaluate((a) => window.__tasks.start(a), { source: basename(video), w: WIDTH, h: HEIGHT, fps: FPS, version, hands: clip.kind !== "legs" });
      let hands = 0;
      let poses = 0;
      for (let i = 0; i < n; i++) {
        const r = await page.evaluate(([k, t, b]) => window.__tasks.frame(k, t, b), [i, (i * 1000) / FPS, raw.subarray(i * size, (i + 1) * size).toString("base64")]);
        if (r.hands) hands++;
        if (r.pose) poses++;
      }
      writeFileSync(tasksFile(avatar, clip), await page.evaluate(() => window.__tasks.finish()));
      console.log(`${basename(tasksFile(avatar, clip))}: ${n} frames, hands in ${hands}, pose in ${poses}`);
    }
  }
} finally {
  await close();
}
if (errors.length) throw new Error(`page errors: ${errors.join("; ")}`);
console.log(`tracked (Tasks API) in ${((Date.now() - t0) / 1000).toFixed(0)} s`);
