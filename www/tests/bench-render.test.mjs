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
const { CLIPS, CONTACT_CLIPS, LEG_CLIPS, LEG_RANGES, clipAngles, clipPose, legClipPose, RANGES } = await import(join(BENCH, "motions.mjs"));
const committed = JSON.parse(readFileSync(join(BENCH, "clips", "frames.json"), "utf8"));

let r;
before(async () => {
  r = await openRenderer();
});
after(async () => {
  await r?.close();
});

// One body clip, one hand clip and one leg clip (whole body, the hips moving), three frames each.
const CASES = [
  { name: "woman-wave", frames: [0, 30, 74] },
  { name: "child-pinch", frames: [0, 20, 55] },
  { name: "man-squat", frames: [0, 40, 96] },
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
  // The arm clips and the contact clips (issue 52) alike.
  for (const clip of [...CLIPS, ...CONTACT_CLIPS]) {
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

test("the leg clips' truth (legClipPose) on each leg avatar: knees bent forwards within range, planted feet still, no sole under the floor, the hips moving", async () => {
  const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const len = (a) => Math.hypot(...a);
  const deg = (a, b) => (Math.acos(Math.min(1, Math.max(-1, dot(a, b) / (len(a) * len(b))))) * 180) / Math.PI;
  const { LEG_AVATARS } = await import(join(BENCH, "common.mjs"));
  for (const avatar of LEG_AVATARS) {
    await r.load(avatar);
    const rest = await r.legRest();
    for (const clip of LEG_CLIPS) {
      let prev = null;
      let planted = 0;
      let lifted = 0;
      let hipsMoved = 0;
      for (let i = 0; i < clip.frames; i++) {
        const t = legClipPose(clip, i, rest);
        for (const q of Object.values(t.bones)) assert.ok(Math.abs(Math.hypot(...q) - 1) < 1e-9, `${avatar} ${clip.id} ${i}: not unit`);
        hipsMoved = Math.max(hipsMoved, len(t.hipsOffset));
        for (const side of ["left", "right"]) {
          const H = t.points[`${side}Hip`];
          const K = t.points[`${side}Knee`];
          const A = t.points[`${side}Ankle`];
          const knee = deg(sub(K, H), sub(A, K));
          const hipFlex = deg([0, -1, 0], sub(K, H)) * Math.sign(K[2] - H[2] || 1);
          assert.ok(knee >= LEG_RANGES.kneeFlex[0] && knee <= LEG_RANGES.kneeFlex[1], `${avatar} ${clip.id} ${i} ${side}: knee ${knee}`);
          assert.ok(hipFlex >= LEG_RANGES.hipFlex[0] && hipFlex <= LEG_RANGES.hipFlex[1], `${avatar} ${clip.id} ${i} ${side}: hip flexion ${hipFlex}`);
          // The knee in front of the hip-ankle line (it bends forwards), when bent.
          const u = sub(A, H);
          const k = sub(K, H);
          const off = sub(k, u.map((x) => (x * dot(k, u)) / dot(u, u)));
          if (knee > 1) assert.ok(off[2] > 0, `${avatar} ${clip.id} ${i} ${side}: knee behind the hip-ankle line`);
          // No sole under the floor: the ankle at or above its rest height (the foot level or toes down when lifted).
          const restAnkle = rest[`${side}Foot`];
          assert.ok(A[1] >= restAnkle[1] - 1e-9, `${avatar} ${clip.id} ${i} ${side}: ankle under its rest height`);
          if (prev) {
            const moved = len(sub(A, prev.points[`${side}Ankle`]));
            if (A[1] < restAnkle[1] + 1e-9 && prev.points[`${side}Ankle`][1] < restAnkle[1] + 1e-9) {
              // On the floor on both frames: planted, or sliding into place (never here: feet are lifted to move).
              assert.ok(moved < 1e-9, `${avatar} ${clip.id} ${i} ${side}: a foot on the floor moved ${moved} m`);
              planted++;
            } else lifted++;
          }
        }
        prev = t;
      }
      assert.ok(planted > clip.frames / 2, `${avatar} ${clip.id}: ${planted} planted foot-frames`);
      if (clip.id !== "squat") assert.ok(lifted > 10, `${avatar} ${clip.id}: ${lifted} lifted foot-frames`);
      assert.ok(hipsMoved > 0.02, `${avatar} ${clip.id}: the hips moved ${hipsMoved} m at most`);
    }
  }
  assert.deepEqual(r.errors, []);
});
