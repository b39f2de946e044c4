#!/usr/bin/env node
// The face bench's eyes as rendered (issue 50): for each avatar, crops of both eyes (4x) open
// (face-blink frame 10), closed (face-blink frame 19) and winking the avatar's left eye
// (face-wink frame 24), one row an avatar (woman, man, child), into
// artifacts/screenshots/face-bench-eyes.png; each crop also as AVATAR-CLIP-FRAME.png there.
// The crops are placed by FaceLandmarker's eye landmarks in eval/face-bench/AVATAR-CLIP.json
// (made by eval/face-bench.mjs), so those recordings must exist.
//
//   node eval/bench/face-eye-shots.mjs

import { spawnSync } from "node:child_process";
import { mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { REPO } from "./common.mjs";
import { HEIGHT, WIDTH, openRenderer } from "./render.mjs";

const OUT = join(REPO, "artifacts", "screenshots");
const AVATARS = ["woman", "man", "child"];
const SHOTS = [["face-blink", 10], ["face-blink", 19], ["face-wink", 24]];
// Eye corners, lid middles and brows (MediaPipe face mesh indices).
const EYES = [33, 133, 263, 362, 159, 386, 145, 374];
const BROWS = [105, 334];

const ffmpeg = (args) => {
  const p = spawnSync("ffmpeg", ["-v", "error", "-y", ...args], { stdio: "inherit" });
  if (p.status !== 0) throw new Error(`ffmpeg exited with ${p.status}`);
};

mkdirSync(OUT, { recursive: true });
const tmp = mkdtempSync(join(tmpdir(), "handrig-eyes-"));
const rows = [];
const r = await openRenderer();
try {
  for (const avatar of AVATARS) {
    await r.load(avatar);
    const row = [];
    for (const [clip, i] of SHOTS) {
      await r.clip(clip);
      const raw = join(tmp, `${avatar}-${clip}-${i}.rgba`);
      writeFileSync(raw, await r.frame(i));
      const lm = JSON.parse(readFileSync(join(REPO, "eval", "face-bench", `${avatar}-${clip}.json`), "utf8")).frames[i].landmarks;
      const xs = EYES.map((k) => lm[k][0] * WIDTH);
      const ys = [...EYES, ...BROWS].map((k) => lm[k][1] * HEIGHT);
      const x0 = Math.floor(Math.min(...xs) - 15);
      const y0 = Math.floor(Math.min(...ys) - 10);
      const w = Math.ceil(Math.max(...xs) + 15) - x0;
      const h = Math.ceil(Math.max(...ys) + 10) - y0;
      const png = join(OUT, `face-bench-eyes-${avatar}-${clip}-${i}.png`);
      ffmpeg(["-f", "rawvideo", "-pix_fmt", "rgba", "-s", `${WIDTH}x${HEIGHT}`, "-i", raw, "-vf", `crop=${w}:${h}:${x0}:${y0},scale=iw*4:ih*4:flags=neighbor`, "-frames:v", "1", png]);
      row.push(png);
    }
    rows.push(row);
  }
} finally {
  await r.close();
}
// One sheet: each crop scaled to 400x130, a row an avatar.
const inputs = rows.flat().flatMap((p) => ["-i", p]);
const scaled = rows.flat().map((_, k) => `[${k}]scale=400:130[s${k}]`).join(";");
const stacked = rows.map((row, a) => `${row.map((_, c) => `[s${a * row.length + c}]`).join("")}hstack=${row.length}[r${a}]`).join(";");
const sheet = join(OUT, "face-bench-eyes.png");
ffmpeg([...inputs, "-filter_complex", `${scaled};${stacked};${rows.map((_, a) => `[r${a}]`).join("")}vstack=${rows.length}`, sheet]);
rmSync(tmp, { recursive: true, force: true });
console.error(`${sheet}: rows ${AVATARS.join(", ")}; columns open (face-blink 10), closed (face-blink 19), left wink (face-wink 24)`);
