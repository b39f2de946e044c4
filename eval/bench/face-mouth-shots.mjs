#!/usr/bin/env node
// The generated avatars' mouth shapes as rendered (issue 50): the lower face with each named
// expression at weight 1 (VRM presets, ARKit names, "a+b" for both, "a=0.4" for a weight,
// "neutral" for none), at rest
// otherwise, in the face bench's light and own colours (render-page.js), from the front and from
// the avatar's right, one row a shape (labelled), into artifacts/screenshots/face-mouth-AVATAR.png
// (or PREFIX-AVATAR.png). --distance: the camera's distance from the mouth, metres.
//
//   node eval/bench/face-mouth-shots.mjs [--avatars woman,man,child] [--shapes aa,jawOpen,...] [--distance 0.3] [--out PREFIX]

import { spawnSync } from "node:child_process";
import { mkdirSync, mkdtempSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { parseArgs } from "node:util";
import { REPO } from "./common.mjs";
import { HEIGHT, WIDTH, openRenderer } from "./render.mjs";

const { values: o } = parseArgs({ options: { avatars: { type: "string" }, shapes: { type: "string" }, distance: { type: "string" }, out: { type: "string" } } });
const OUT = join(REPO, "artifacts", "screenshots");
const AVATARS = (o.avatars ?? "woman").split(",");
// Default: the five visemes beside the face at rest. The ARKit shapes they mix (jawOpen,
// mouthLowerDownLeft+mouthLowerDownRight, mouthStretchLeft+mouthStretchRight, mouthFunnel,
// mouthPucker, jawOpen+mouthClose: perfect sync drives them directly) with --shapes.
const SHAPES = (o.shapes ?? "neutral,aa,ih,ou,ee,oh").split(",");

const ffmpeg = (args) => {
  const p = spawnSync("ffmpeg", ["-v", "error", "-y", ...args], { stdio: "inherit" });
  if (p.status !== 0) throw new Error(`ffmpeg exited with ${p.status}`);
};

mkdirSync(OUT, { recursive: true });
const tmp = mkdtempSync(join(tmpdir(), "handrig-mouth-"));
const r = await openRenderer();
try {
  for (const avatar of AVATARS) {
    await r.load(avatar);
    await r.clip("face-still");
    const eyes = await r.page.evaluate(() => window.__bench.eyesMiddle());
    // The mouth is about 5 cm under the eyes (the woman: 5.3 cm).
    const target = [eyes[0], eyes[1] - 0.053, eyes[2]];
    const pngs = [];
    for (const shape of SHAPES) {
      // "name" at 1, "name=w" at w.
      const ex = Object.fromEntries(shape === "neutral" ? [] : shape.split("+").map((n) => [n.split("=")[0], Number(n.split("=")[1] ?? 1)]));
      for (const view of ["front", "side"]) {
        // From the side, the view's middle 3 cm ahead of the eyes (the lips' profile).
        const at = view === "side" ? [target[0], target[1], target[2] + 0.03] : target;
        const b64 = await r.page.evaluate(([e, t, v, d]) => window.__bench.faceShot(e, t, v, d), [ex, at, view, Number(o.distance ?? 0.3)]);
        const raw = join(tmp, `${avatar}-${shape}-${view}.rgba`);
        writeFileSync(raw, Buffer.from(b64, "base64"));
        const png = join(tmp, `${avatar}-${shape}-${view}.png`);
        // The middle 320 x 200 of the frame (the mouth, the nose and the chin).
        ffmpeg(["-f", "rawvideo", "-pix_fmt", "rgba", "-s", `${WIDTH}x${HEIGHT}`, "-i", raw, "-vf", `crop=320:200:160:140,drawtext=text='${shape.replace(/\+/g, " ").replace(/=/g, " ")} ${view}':x=4:y=4:fontsize=14:fontcolor=white`, "-frames:v", "1", png]);
        pngs.push(png);
      }
    }
    const inputs = pngs.flatMap((p) => ["-i", p]);
    const rows = SHAPES.map((_, k) => `[${2 * k}][${2 * k + 1}]hstack=2[r${k}]`).join(";");
    const sheet = o.out ? `${o.out}-${avatar}.png` : join(OUT, `face-mouth-${avatar}.png`);
    ffmpeg([...inputs, "-filter_complex", `${rows};${SHAPES.map((_, k) => `[r${k}]`).join("")}vstack=${SHAPES.length}`, sheet]);
    console.error(`${sheet}: rows ${SHAPES.join(", ")}; columns front, side`);
  }
} finally {
  await r.close();
  rmSync(tmp, { recursive: true, force: true });
}
if (r.errors.length) throw new Error(`page errors: ${r.errors.join("; ")}`);
