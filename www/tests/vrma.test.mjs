// Browser test: a .vrma written by handrig's MotionRecorder (the built package, in Node) from a
// shared ASL clip, dropped on the demo, plays on the loaded avatar through
// @pixiv/three-vrm-animation: at the recorded times the avatar's normalized bones have the
// recorded rotations, on the VRM 1.0 avatar it was recorded on and on a VRM 0.x one.

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { join } from "node:path";
import { REPO, SHARED, dropFile, launch, openDemo, shot } from "./helpers.mjs";
import { findPackageDir } from "../serve.mjs";

let env;
let page;
let errors;

before(async () => {
  env = await launch();
  ({ page, errors } = await openDemo(env));
});

after(async () => {
  await env?.close();
});

const angle = (a, b) => 2 * Math.acos(Math.min(1, Math.abs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3])));

/** The shared "thanks" clip solved on the woman (VRM 1.0), recorded; with a copy of every frame's bones. */
function makeVrma() {
  const { HandRig, MotionRecorder } = createRequire(import.meta.url)(findPackageDir());
  const rig = HandRig.fromVrm(readFileSync(join(REPO, "tests", "fixtures", "avatars", "woman-vrm1.vrm")), { torso: "pose" });
  const recorder = new MotionRecorder(rig);
  const { frames } = JSON.parse(readFileSync(join(SHARED, "data", "asl", "thanks.json"), "utf8"));
  const expected = [];
  for (const f of frames) {
    const r = rig.solve({ timeMs: f.timeMs, hands: f.hands, pose: f.pose });
    recorder.add(f.timeMs, r);
    expected.push({ t: (f.timeMs - frames[0].timeMs) / 1000, bones: structuredClone(r.bones) });
  }
  const driven = rig.drivenBones();
  rig.free();
  return { bytes: recorder.toVRMA(), expected, driven };
}

test("a dropped .vrma plays on the avatar: the recorded rotations at the recorded times (VRM 1.0, then 0.x)", async () => {
  const { bytes, expected, driven } = makeVrma();
  await page.evaluate(() => window.__handrigDemo.selectAvatar("woman"));
  await dropFile(page, bytes, "thanks.vrma");
  await page.waitForFunction(() => window.__handrigDemo.vrma() !== null, null, { timeout: 30_000 });
  const info = await page.evaluate(() => window.__handrigDemo.vrma());
  assert.equal(info.name, "thanks.vrma");
  assert.ok(Math.abs(info.duration - expected.at(-1).t) < 1e-3, `duration ${info.duration} s`);
  assert.match(await page.textContent("#status"), /playing thanks\.vrma/);
  const check = async (flip) => {
    let worst = 0;
    let worstAt = "";
    let turned = 0;
    for (let i = 0; i < expected.length; i += 5) {
      await page.evaluate((t) => window.__handrigDemo.seekVrma(t), expected[i].t);
      for (const key of ["with", "without"]) {
        const got = await page.evaluate((k) => window.__handrigDemo.normalizedRotations(k), key);
        for (const bone of driven) {
          const q = expected[i].bones[bone];
          const want = flip ? [-q[0], q[1], -q[2], q[3]] : q;
          const a = angle(got[bone], want);
          if (a > worst) worstAt = `${key} ${bone} frame ${i}: got ${got[bone]} want ${want}`;
          worst = Math.max(worst, a);
          if (angle(want, [0, 0, 0, 1]) > 0.35) turned++;
        }
      }
    }
    assert.ok(turned > 100, `${turned} bone-frames turned more than 20 degrees`);
    assert.ok(worst < (0.5 * Math.PI) / 180, `largest angle ${((worst * 180) / Math.PI).toFixed(4)} degrees at ${worstAt}`);
  };
  await check(false);
  await page.screenshot({ path: shot("vrma-woman.png") });
  // Another avatar, a VRM 0.x: the animation goes on playing on it (three-vrm-animation turns
  // VRM 1.0's rotations into the 0.x model's frame, where handrig's 0.x rotations live).
  await page.evaluate(() => window.__handrigDemo.selectAvatar("man-vrm0"));
  assert.notEqual(await page.evaluate(() => window.__handrigDemo.vrma()), null);
  await check(true);
  await page.screenshot({ path: shot("vrma-man-vrm0.png") });
  // A file that is not a VRM Animation: one status line, the page keeps working.
  await dropFile(page, new Uint8Array([1, 2, 3, 4]), "broken.vrma");
  await page.waitForFunction(() => document.getElementById("status").textContent.includes("could not play broken.vrma"), null, {
    timeout: 30_000,
  });
  // Back to the recordings: the player stops, handrig drives the avatar again.
  await page.click('input[name="source"][value="recording"]');
  assert.equal(await page.evaluate(() => window.__handrigDemo.vrma()), null);
  await page.evaluate(() => window.__handrigDemo.setFrame(140));
  assert.ok(await page.evaluate(() => window.__handrigDemo.results.with !== null));
  assert.deepEqual(errors, []);
});
