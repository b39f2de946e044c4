// Screenshots of the face (issue 50): the demo's default avatar (tests/fixtures/avatars/woman-vrm1.vrm,
// its face from tools/avatars/face.mjs) driven through the package (restPoseFromVRM, rig.solve on
// every frame with default options, applyToVRM, vrm.update) by FaceLandmarker's blendshapes,
// matrices and landmarks of the ground-truth bench's renders of the same avatar (eval/bench/face-motions.mjs:
// tests/fixtures/face/bench-shots.json, made by `node eval/face-bench.mjs --write-shots`), after
// 2 s of its still face: saying "aa" and "ou", smiling, looking to its left, each from the front;
// and blinking (the bench's closed eyes). Saves artifacts/screenshots/face-<blink|aa|ou|smile|look-left>.png.
// Checks that the intended preset is on in the result and its morph target on the mesh, the
// other shots' near zero, and that the look-at turns the eyes.

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { join } from "node:path";
import { REPO, launch, openContactShots, shot } from "./helpers.mjs";

const data = JSON.parse(readFileSync(join(REPO, "tests", "fixtures", "face", "bench-shots.json"), "utf8"));

/**
 * A recorded frame as a FaceLandmarkerResult spread into rig.solve's frame. The fixture keeps of
 * the 478 landmarks the 20 the package reads (LAYOUT.faceMesh, `data.meshIndices`); the others
 * are filled with the face's middle (read by nothing).
 */
function landmarks(mesh) {
  const mid = { x: (mesh[18][0] + mesh[19][0]) / 2, y: (mesh[16][1] + mesh[17][1]) / 2, z: 0 };
  const out = Array.from({ length: 478 }, () => ({ ...mid }));
  data.meshIndices.forEach((k, i) => (out[k] = { x: mesh[i][0], y: mesh[i][1], z: mesh[i][2] }));
  return out;
}
const frame = (f, t0 = 0) => ({
  timeMs: t0 + f.timeMs,
  faceLandmarks: [landmarks(f.mesh)],
  faceBlendshapes: [{ headIndex: -1, headName: "", categories: f.blendshapes.map((score, index) => ({ index, score, categoryName: data.names[index], displayName: "" })) }],
  facialTransformationMatrixes: [{ rows: 4, columns: 4, data: f.matrix }],
});

let env;
let page;
const errors = [];

before(async () => {
  env = await launch();
  page = await openContactShots(env, errors);
  const info = await page.evaluate(() => window.__contactShots.load("/avatars/woman-vrm1.vrm"));
  assert.equal(String(info.metaVersion), "1");
});

after(async () => {
  await env?.close();
});

// Each shot's preset and the morph targets it moves on this perfect-sync avatar (applyToVRM
// sets the 52 ARKit expressions there, not the presets: they are mixes of the same targets).
const MAIN = { aa: ["aa", "jawOpen"], ou: ["ou", "mouthPucker"], smile: ["happy", "mouthSmileLeft"] };

for (const s of data.shots.filter((x) => x.name !== "blink")) {
  test(`the default avatar's face driven by FaceLandmarker through the package: ${s.name}, from the front`, async (t) => {
    const still = data.still.map((f) => frame(f));
    const t0 = still[still.length - 1].timeMs + 1000 / 30;
    const frames = [...still, ...s.frames.map((f) => frame(f, t0))];
    await page.evaluate((fr) => window.__contactShots.start(fr), frames);
    const r = await page.evaluate((i) => window.__contactShots.advanceFace(i), frames.length - 1);
    await page.locator("#view").screenshot({ path: shot(`face-${s.name}.png`) });
    assert.equal(r.face, "tracked");
    const e = r.expressions;
    const inf = r.influences;
    t.diagnostic(
      `${s.name}: ${Object.values(MAIN).map(([p, m]) => `${p} ${e[p].toFixed(2)} (${m} ${inf[m].toFixed(2)})`).join(", ")}, ` +
        `lookAt yaw ${r.lookAt.yaw.toFixed(1)}, left eye ${r.eyeYaw.toFixed(1)} deg`,
    );
    const mine = MAIN[s.name];
    for (const [name, [preset, morph]] of Object.entries(MAIN)) {
      if (name === s.name) continue;
      // The other shots' shapes stay off (aa's render also reads as some pucker: see below).
      if (!(s.name === "aa" && name === "ou")) {
        assert.ok(e[preset] <= 0.1 && inf[morph] <= 0.15, `${s.name}: ${preset} ${e[preset]}, ${morph} ${inf[morph]}`);
      }
    }
    if (mine) {
      const [preset, morph] = mine;
      assert.ok(e[preset] >= 0.3, `${s.name}: ${preset} ${e[preset]}`);
      assert.ok(inf[morph] >= 0.2, `${s.name}: morph ${morph} influence ${inf[morph]}`);
    } else {
      // Looking to the avatar's left: yaw > 0 and the left eye bone turned that way.
      assert.ok(r.lookAt.yaw > 10 && r.eyeYaw > 10, `look-left: lookAt yaw ${r.lookAt.yaw}, eye ${r.eyeYaw} deg`);
    }
    assert.deepEqual(errors, []);
  });
}

test("the default avatar blinking, driven by FaceLandmarker through the package", async () => {
  // MediaPipe reads the rendered closed lids with eyeBlink 0.6-0.67 and eyeLookDown 0.75 (as a
  // real blink); handrig takes a quarter of the calibrated look-down off (LOOK_DOWN_BLINK) and
  // closes both eyes.
  const blink = data.shots.find((x) => x.name === "blink");
  const still = data.still.map((f) => frame(f));
  const t0 = still[still.length - 1].timeMs + 1000 / 30;
  const frames = [...still, ...blink.frames.map((f) => frame(f, t0))];
  await page.evaluate((fr) => window.__contactShots.start(fr), frames);
  const s = await page.evaluate((i) => window.__contactShots.advanceFace(i), frames.length - 1);
  await page.locator("#view").screenshot({ path: shot("face-blink.png") });
  assert.equal(s.face, "tracked");
  const closed = Math.min(s.expressions.blink + s.expressions.blinkLeft, s.expressions.blink + s.expressions.blinkRight);
  assert.ok(closed >= 0.5, `handrig's blink on the bench's closed eyes: ${JSON.stringify(s.expressions)}`);
  // It reaches both eyes' morph targets on this perfect-sync avatar, and the mouth stays shut.
  assert.ok(s.influences.eyeBlinkLeft >= 0.5 && s.influences.eyeBlinkRight >= 0.5, JSON.stringify(s.influences));
  assert.ok(s.influences.jawOpen <= 0.15 && s.influences.mouthSmileLeft <= 0.15, JSON.stringify(s.influences));
  assert.deepEqual(errors, []);
});
