#!/usr/bin/env node
// Screenshots of the bench's leg clips as handrig solves them (issue 51): the Tasks API
// tracking of a rendered clip (eval/bench/clips/AVATAR-CLIP-tasks.json, `node
// eval/bench/tasks.mjs --legs`) solved frame by frame by handrig (pkg/, default options,
// applyToVRM on a three-vrm avatar in Node), the solved pose rendered by the bench's renderer
// (render-page.js) from the front (the clip's camera) and from the avatar's right, beside the
// rendered truth of the same frame, into artifacts/screenshots/legs-bench-AVATAR-CLIP-FRAME-{truth,front,side}.png.
//
//   node eval/bench/legs-shots.mjs [--avatar woman] [--shots walk:15,walk:30,walk:45,walk:60,squat:40,squat:96] [--out DIR] [--pkg DIR]

import { spawn } from "node:child_process";
import { existsSync, mkdirSync, readFileSync } from "node:fs";
import { join } from "node:path";
import { pathToFileURL } from "node:url";
import { parseArgs } from "node:util";
import { REPO, recordingFile, avatarFile } from "./common.mjs";
import { FPS, LEG_CLIPS } from "./motions.mjs";
import { HEIGHT, WIDTH, openRenderer } from "./render.mjs";

const { values: o } = parseArgs({
  options: {
    avatar: { type: "string", default: "woman" },
    shots: { type: "string", default: "walk:15,walk:30,walk:45,walk:60,squat:40,squat:96" },
    out: { type: "string", default: join(REPO, "artifacts", "screenshots") },
    pkg: { type: "string", default: join(REPO, "pkg") },
  },
});
const { HandRig } = await import(pathToFileURL(join(o.pkg, "index.mjs")).href);
const { restPoseFromVRM, applyToVRM } = await import(pathToFileURL(join(o.pkg, "three-vrm.js")).href);
const { loadVrm } = await import(pathToFileURL(join(REPO, "tests", "node", "consumer", "skin-measure.mjs")).href);

const png = (file, rgba) =>
  new Promise((res, rej) => {
    const p = spawn("ffmpeg", ["-v", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgba", "-s", `${WIDTH}x${HEIGHT}`, "-i", "-", "-frames:v", "1", file], { stdio: ["pipe", "inherit", "inherit"] });
    p.on("close", (c) => (c === 0 ? res() : rej(new Error(`ffmpeg exited with ${c}`))));
    p.stdin.end(rgba);
  });

const wanted = new Map();
for (const s of o.shots.split(",")) {
  const [clip, frame] = s.split(":");
  if (!LEG_CLIPS.some((c) => c.id === clip)) throw new Error(`no leg clip ${clip}`);
  wanted.set(clip, [...(wanted.get(clip) ?? []), Number(frame)]);
}
mkdirSync(o.out, { recursive: true });
const vrm = await loadVrm(avatarFile(o.avatar));
const h = vrm.humanoid;
const names = Object.keys(h.humanBones).filter((n) => h.getNormalizedBoneNode(n));
const hips = h.getNormalizedBoneNode("hips");
const hipsRest = hips.position.toArray();
const r = await openRenderer();
try {
  await r.load(o.avatar);
  for (const [clipId, frames] of wanted) {
    const clip = LEG_CLIPS.find((c) => c.id === clipId);
    const file = recordingFile(o.avatar, clip, "tasks");
    if (!existsSync(file)) throw new Error(`${file} missing: node eval/bench/tasks.mjs --legs first`);
    const rec = JSON.parse(readFileSync(file, "utf8"));
    await r.clip(clipId);
    for (const n of names) h.getNormalizedBoneNode(n).quaternion.identity();
    hips.position.fromArray(hipsRest);
    const rig = new HandRig(restPoseFromVRM(vrm));
    const last = Math.max(...frames);
    for (let i = 0; i <= last; i++) {
      applyToVRM(vrm, rig.solve({ ...rec.frames[i], imageAspect: rec.width / rec.height }));
      if (!frames.includes(i)) continue;
      const bones = Object.fromEntries(names.map((n) => [n, h.getNormalizedBoneNode(n).quaternion.toArray()]));
      const base = join(o.out, `legs-bench-${o.avatar}-${clipId}-${i}`);
      for (const view of ["front", "side"]) {
        const px = Buffer.from(await r.page.evaluate(([b, p, v]) => window.__bench.show(b, p, v), [bones, hips.position.toArray(), view]), "base64");
        await png(`${base}-${view}.png`, px);
      }
      await png(`${base}-truth.png`, await r.frame(i));
      console.log(`${base}-{truth,front,side}.png (${(i / FPS).toFixed(2)} s)`);
    }
    rig.free();
  }
} finally {
  await r.close();
}
if (r.errors.length) throw new Error(`page errors: ${r.errors.join("; ")}`);
