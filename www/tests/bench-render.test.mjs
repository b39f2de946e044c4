// The ground-truth bench's renders are reproducible (issue 47): eval/bench/render.mjs re-renders
// frames of committed clips in headless Chromium (SwiftShader WebGL) and their RGBA pixels hash
// to the values in eval/bench/clips/frames.json, which the committed videos were encoded from.
// Also: rendering one frame twice in a session gives the same pixels, every clip's joint
// angles stay inside the ranges motions.mjs declares, and score.mjs measures the committed
// recordings of two clips (handrig from pkg/; Kalidokit left out, eval/'s npm deps are not
// part of `make setup`).

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { mkdtempSync, readFileSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
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

test("score.mjs on the committed pinch and wave recordings: the metric's self-check passes, handrig on ideal landmarks is near the truth, on MediaPipe's not (no truth leaks in)", () => {
  const dir = mkdtempSync(join(tmpdir(), "handrig-bench-score-"));
  try {
    const out = join(dir, "score.json");
    execFileSync(process.execPath, [join(BENCH, "score.mjs"), "--avatars", "woman", "--clips", "pinch,wave", "--no-kalidokit", "--json", out], {
      stdio: ["ignore", "ignore", "inherit"],
    });
    const r = JSON.parse(readFileSync(out, "utf8"));
    assert.ok(r.selfCheck < 0.05, `self-check ${r.selfCheck} deg`);
    const hand = r.summary.hand;
    // 75 frames with the hand found, 15 joints each, the same frames for every method.
    for (const m of ["handrig", "retarget", "mediapipe", "oracle"]) assert.equal(hand[m].joint.n, 75 * 15, m);
    assert.ok(hand.oracle.joint.median < 5 && hand.oracle.joint.p95 < 20, `ideal landmarks: ${JSON.stringify(hand.oracle.joint)}`);
    assert.ok(hand.oracle.palm.median < 1, `ideal landmarks, palm: ${JSON.stringify(hand.oracle.palm)}`);
    for (const m of ["handrig", "retarget", "mediapipe"]) {
      assert.ok(hand[m].joint.median > 2 && hand[m].joint.median < 60, `${m}: ${JSON.stringify(hand[m].joint)}`);
    }
    // The wave clip: both arms over 75 frames with a pose.
    const body = r.summary.body;
    for (const m of ["handrig", "mediapipe"]) {
      assert.equal(body[m].forearm.n, 150, m);
      assert.ok(body[m].forearm.median > 0.5 && body[m].forearm.median < 60, `${m} forearm: ${JSON.stringify(body[m].forearm)}`);
    }
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});
