// The ground-truth bench's renders are reproducible (issue 47): eval/bench/render.mjs re-renders
// frames of committed clips in headless Chromium (SwiftShader WebGL) and their RGBA pixels hash
// to the values in eval/bench/clips/frames.json, which the committed videos were encoded from.
// Also: rendering one frame twice in a session gives the same pixels, and every clip's joint
// angles stay inside the ranges motions.mjs declares.

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { join } from "node:path";
import { REPO } from "./helpers.mjs";

const BENCH = join(REPO, "eval", "bench");
const { openRenderer, sha256 } = await import(join(BENCH, "render.mjs"));
const { CLIPS, clipAngles, clipPose, RANGES } = await import(join(BENCH, "motions.mjs"));
const committed = JSON.parse(readFileSync(join(BENCH, "clips", "frames.json"), "utf8"));

let r;
before(async () => {
  r = await openRenderer();
});
after(async () => {
  await r?.close();
});

// One body clip and one hand clip, three frames each, on both avatars' first.
const CASES = [
  { name: "woman-wave", frames: [0, 30, 74] },
  { name: "child-pinch", frames: [0, 20, 55] },
];

test("re-rendered frames hash to the committed frames.json (same Chromium build), and twice the same in one session", async () => {
  for (const c of CASES) {
    const entry = committed.clips[c.name];
    assert.ok(entry, `${c.name} missing from frames.json`);
    await r.load(entry.avatar);
    const cam = await r.clip(entry.clip);
    assert.deepEqual(cam.position.map((x) => x.toFixed(6)), entry.camera.position.map((x) => x.toFixed(6)), `${c.name}: camera moved`);
    for (const i of c.frames) {
      const a = sha256(await r.frame(i)).slice(0, 16);
      const b = sha256(await r.frame(i)).slice(0, 16);
      assert.equal(a, b, `${c.name} frame ${i}: two renders differ`);
      if (r.browser === committed.browser) {
        assert.equal(a, entry.rgbaSha256[i], `${c.name} frame ${i}: pixels differ from the committed render`);
      }
    }
  }
  assert.deepEqual(r.errors, []);
  if (r.browser !== committed.browser) {
    console.log(`# frames.json was rendered by ${committed.browser}, this is ${r.browser}: only the in-session repeat was compared`);
  }
});

test("the truth: every clip's joint angles are inside the declared ranges, rotations unit and the frames distinct", () => {
  for (const clip of CLIPS) {
    let moving = 0;
    let prev = null;
    for (let i = 0; i < clip.frames; i++) {
      for (const [key, v] of Object.entries(clipAngles(clip, i))) {
        // "right.shape.index.2" -> "shape.finger.2", "left.upperArm.flex" -> "upperArm.flex".
        const joint = key.slice(key.indexOf(".") + 1).replace(/^shape\.(index|middle|ring|little)\./, "shape.finger.");
        const range = RANGES[joint];
        assert.ok(range, `${clip.id}: no range for ${key}`);
        assert.ok(v >= range[0] - 1e-9 && v <= range[1] + 1e-9, `${clip.id} frame ${i}: ${key} = ${v} outside [${range}]`);
      }
      const pose = clipPose(clip, i);
      for (const [bone, q] of Object.entries(pose)) assert.ok(Math.abs(Math.hypot(...q) - 1) < 1e-9, `${clip.id} ${bone}: not unit`);
      const key = JSON.stringify(pose);
      if (prev !== null && key !== prev) moving++;
      prev = key;
    }
    assert.ok(moving > clip.frames / 2, `${clip.id}: only ${moving} frames move`);
  }
});
