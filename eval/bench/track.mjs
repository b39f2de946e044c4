#!/usr/bin/env node
// Tracks the rendered bench clips with MediaPipe (issue 47): tools/record-video.mjs (the legacy
// @mediapipe/holistic and @mediapipe/hands npm packages in headless Chromium) over each
// eval/bench/clips/AVATAR-CLIP.mp4, writing AVATAR-CLIP-MODE.json beside it in the shared
// recording format (tools/README.md). Body clips: holistic (pose + both hands' image landmarks);
// hand clips: hands (hand world landmarks).
//
//   node eval/bench/track.mjs [--avatars woman,child] [--clips reach,fist,...]

import { execFileSync } from "node:child_process";
import { existsSync } from "node:fs";
import { join } from "node:path";
import { parseArgs } from "node:util";
import { CLIPS } from "./motions.mjs";
import { AVATARS, REPO, modeOf, recordingFile, videoFile } from "./common.mjs";

const { values: o } = parseArgs({ options: { avatars: { type: "string" }, clips: { type: "string" } } });
const avatars = (o.avatars ?? AVATARS.join(",")).split(",");
const clips = o.clips ? CLIPS.filter((c) => o.clips.split(",").includes(c.id)) : CLIPS;
const t0 = Date.now();
for (const avatar of avatars) {
  for (const clip of clips) {
    const video = videoFile(avatar, clip);
    if (!existsSync(video)) throw new Error(`${video} missing: run node eval/bench/render.mjs first`);
    execFileSync(process.execPath, [join(REPO, "tools", "record-video.mjs"), video, "--mode", modeOf(clip), "--out", recordingFile(avatar, clip), "--quiet"], {
      stdio: "inherit",
    });
  }
}
console.log(`tracked in ${((Date.now() - t0) / 1000).toFixed(0)} s`);
