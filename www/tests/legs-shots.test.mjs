// Screenshots of the legs (issue 51): the generated adult (tests/fixtures/avatars/woman-vrm1.vrm)
// in the contact-shots page (three + three-vrm, the package's adapter: restPoseFromVRM, rig.solve
// on every frame from the start, applyToVRM), driven by the synthetic walk in place and squat of
// eval/frames/legs-synthetic.json (eval_legs --write-frames: pose only, legs in view), rendered
// whole from the front and from the avatar's right. Saves
// artifacts/screenshots/legs-<walk|squat>-<frame>-<front|side>.png. Checks that three-vrm's
// posed leg bones are where the rig put them in the room (its worldPositions plus hipsOffset:
// applyToVRM moved the normalized hips), and that the legs are drawn.

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { join } from "node:path";
import { REPO, launch, openContactShots, shot } from "./helpers.mjs";

const frames = JSON.parse(readFileSync(join(REPO, "eval", "frames", "legs-synthetic.json"), "utf8")).frames;
// The walk is frames 0-134 (a 1.2 s cycle at 30 fps: the left foot highest at 9, the right at
// 27), the squat 135-269 (deepest at 157 and 247).
const SHOTS = [
  ["walk", 9],
  ["walk", 27],
  ["squat", 150],
  ["squat", 157],
];

let env;
let page;
const errors = [];

before(async () => {
  env = await launch();
  page = await openContactShots(env, errors);
  await page.evaluate(() => window.__contactShots.load("/avatars/woman-vrm1.vrm"));
  await page.evaluate((frames) => window.__contactShots.start(frames), frames);
});

after(async () => {
  await env?.close();
});

test("a walk and a squat, whole body, front and side", async () => {
  let lowest = 0;
  for (const [motion, frame] of SHOTS) {
    await page.evaluate((i) => window.__contactShots.advanceTo(i), frame);
    const legs = await page.evaluate(() => window.__contactShots.legs());
    assert.ok(legs.maxBoneError < 0.005, `${motion} ${frame}: posed leg bones ${legs.maxBoneError} m from the rig's (hips offset included)`);
    lowest = Math.min(lowest, legs.hipsOffset[1]);
    for (const view of ["front", "side"]) {
      await page.evaluate((v) => window.__contactShots.setView(v, true), view);
      await page.locator("#view").screenshot({ path: shot(`legs-${motion}-${frame}-${view}.png`) });
      const px = await page.evaluate(() => window.__contactShots.legPixels());
      assert.ok(px.covered >= 0.8 * px.points.length, `${motion} ${frame} ${view}: ${px.covered} of ${px.points.length} leg bone points drawn over`);
    }
  }
  assert.ok(lowest < -0.15, `the squat lowers the hips (${lowest} m)`);
  assert.deepEqual(errors, []);
});
