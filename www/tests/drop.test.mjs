// Browser tests: dropping .vrm files (VRM 0.x and 1.0) and a plain glTF humanoid (.glb) onto the page with a DataTransfer drop
// event, and a broken file that must not break the page.

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { existsSync, readFileSync } from "node:fs";
import { join } from "node:path";
import { REPO, SHARED, around, dropFile, launch, openDemo, pixelStats, shot } from "./helpers.mjs";

let env;
let page;
let errors;

before(async () => {
  assert.ok(existsSync(join(SHARED, "avatars", "debug-robot.vrm")), `shared avatars not found in ${SHARED}: set HANDRIG_SHARED`);
  env = await launch();
  ({ page, errors } = await openDemo(env));
});

after(async () => {
  await env?.close();
});

/** Drops a file and waits until the page has loaded it (or reported a failure). */
async function drop(bytes, name) {
  const before = await page.evaluate(() => window.__handrigDemo.avatarLoads);
  await dropFile(page, bytes, name);
  await page.waitForFunction(
    ([n, name]) =>
      window.__handrigDemo.avatarLoads > n || document.getElementById("status").textContent.includes(`could not load ${name}`),
    [before, name],
    { timeout: 30_000 },
  );
  await page.evaluate(() => window.__handrigDemo.setFrame(140));
  return page.evaluate(() => {
    const d = window.__handrigDemo;
    return {
      avatar: d.avatar,
      status: document.getElementById("status").textContent,
      results: d.results,
      errorMm: d.errorMm,
      shownErrorMm: d.shownErrorMm,
      rects: d.viewRects(),
      wrists: d.lastFrame?.wrists ?? null,
      left: d.screenPoint("with", "leftHand"),
      right: d.screenPoint("with", "rightHand"),
    };
  });
}

/** handrig's own parser (fromVrm) and three-vrm agree on the rest pose. */
function assertParserAgrees(avatar) {
  const p = avatar.parser;
  assert.equal(p.error, undefined, `HandRig.fromVrm: ${p.error}`);
  assert.equal(p.version, avatar.vrmVersion);
  assert.equal(p.bones, avatar.boneCount);
  assert.deepEqual(p.missing, []);
  assert.deepEqual(p.extra, []);
  assert.ok(p.maxDiff < 1e-5, `rest positions agree to ${p.maxDiff} m`);
}

function assertFiniteResult(result, label) {
  assert.ok(result, `${label}: a result`);
  for (const [bone, q] of Object.entries(result.bones)) {
    assert.equal(q.length, 4);
    assert.ok(q.every(Number.isFinite), `${label}: ${bone} finite`);
    assert.ok(Math.abs(Math.hypot(...q) - 1) < 1e-4, `${label}: ${bone} unit`);
  }
}

/**
 * Each side with a wrist in the frame: the plain view's hand bone (no fingertip alignment, which
 * moves the target on purpose) on it, or pointed at it from the shoulder.
 */
function assertArmsReach(s) {
  const sub = (a, b) => a.map((v, i) => v - b[i]);
  const len = (a) => Math.hypot(...a);
  const deg = (a, b) => (Math.acos(Math.min(1, a.reduce((t, v, i) => t + v * b[i], 0) / (len(a) * len(b)))) * 180) / Math.PI;
  const sides = ["left", "right"].filter((side) => s.wrists?.[side]);
  assert.equal(sides.length, 2, `the frame has both Kinect wrists: ${JSON.stringify(s.wrists)}`);
  for (const side of sides) {
    const p = s.results.without.worldPositions;
    const target = s.wrists[side].position;
    const miss = len(sub(p[`${side}Hand`], target));
    const off = deg(sub(p[`${side}Hand`], p[`${side}UpperArm`]), sub(target, p[`${side}UpperArm`]));
    assert.ok(miss < 0.02 || off < 5, `${side}: the hand bone ${(miss * 100).toFixed(1)} cm from its wrist, ${off.toFixed(1)} degrees off its direction`);
  }
}

async function assertSkeletonDrawn(s, file) {
  const png = await page.screenshot({ path: shot(file) });
  const stats = await pixelStats(page, png, s.rects.with.body);
  assert.ok(stats.saturated > 800, `skeleton pixels present (${stats.saturated})`);
  // The avatar faces the viewer (VRM 0.x models are turned around for display): its left
  // hand is on the right of the screen.
  assert.ok(s.left.x > s.right.x, `avatar faces the viewer (left hand at x=${s.left.x}, right at x=${s.right.x})`);
  return png;
}

test("dropping a VRM 0.x file without fingers and off the T-pose (odd-armature-vrm0.vrm)", async () => {
  const s = await drop(readFileSync(join(SHARED, "avatars", "odd-armature-vrm0.vrm")), "odd-armature-vrm0.vrm");
  assert.equal(s.avatar?.name, "odd-armature-vrm0.vrm", s.status);
  assert.equal(s.avatar.vrmVersion, "0");
  assert.equal(s.avatar.boneCount, 17);
  assertParserAgrees(s.avatar);
  assert.doesNotMatch(s.status, /could not|failed/);
  for (const v of ["without", "with"]) assertFiniteResult(s.results[v], v);
  // No fingers: the palm stands in for the aligned finger (docs/how-it-works/alignment-ik.md, "Avatars
  // without the aligned finger"), so the alignment reports it and the error readout shows a
  // number whenever the hand is tracked.
  const al = s.results.with.alignment.right;
  if (al) {
    assert.equal(al.aligned, true);
    assert.equal(al.finger, "palm");
    assert.equal(al.bone, "rightHand");
    assert.ok(s.errorMm.with.right === null || Number.isFinite(s.errorMm.with.right), "error readout");
  } else {
    assert.equal(s.errorMm.with.right, null, "no error readout without an alignment");
  }
  // Both arms reach their Kinect wrists: each hand bone of the plain view where the frame's
  // wrist is, or (a wrist out of reach) in its direction from the shoulder. (arm.idle turns an
  // arm that ignores its wrist too, so "moved from rest" would not tell.)
  assertArmsReach(s);
  await assertSkeletonDrawn(s, "drop-vrm0-odd-armature.png");
  assert.deepEqual(errors, []);
});

test("dropping a VRM 0.x file with fingers (tests/fixtures/vrm0-fingers.vrm)", async (t) => {
  const file = join(REPO, "tests", "fixtures", "vrm0-fingers.vrm");
  if (!existsSync(file)) {
    t.skip("tests/fixtures/vrm0-fingers.vrm is not in this checkout yet (the vrm branch generates it)");
    return;
  }
  const s = await drop(readFileSync(file), "vrm0-fingers.vrm");
  assert.equal(s.avatar?.name, "vrm0-fingers.vrm", s.status);
  assert.equal(s.avatar.vrmVersion, "0");
  assert.ok(s.avatar.boneCount > 17 + 20, `finger bones present (${s.avatar.boneCount})`);
  assertParserAgrees(s.avatar);
  for (const v of ["without", "with"]) assertFiniteResult(s.results[v], v);
  const moved = (q) => Math.abs(Math.abs(q[3]) - 1) > 1e-4;
  assert.equal(s.results.with.hands.right?.status, "solved");
  assert.ok(moved(s.results.with.bones.rightIndexProximal), "the right index finger is solved");
  assert.ok(moved(s.results.with.bones.rightThumbMetacarpal), "the thumb (0.x thumbProximal) is solved");
  // handrig's FK and three-vrm's normalized bones agree in the 0.x model frame.
  const mm = s.errorMm.with.right;
  assert.ok(Number.isFinite(mm));
  assert.ok(Math.abs(s.shownErrorMm.with.right - mm) < 0.05, `three-vrm ${s.shownErrorMm.with.right} vs handrig ${mm} mm`);
  if (s.results.with.alignment.right.reachable) assert.ok(mm < 2, `alignment error ${mm} mm`);
  const png = await assertSkeletonDrawn(s, "drop-vrm0-fingers.png");
  const p = await page.evaluate(() => window.__handrigDemo.screenPoint("with", "rightMiddleProximal", "close"));
  const hand = await pixelStats(page, png, around(p, 90, s.rects.with.close));
  assert.ok(hand.hues[6] >= 10 && hand.hues[9] >= 10, `ring and little finger pixels: ${hand.hues}`);
  assert.deepEqual(errors, []);
});

test("dropping a VRM 1.0 file (debug-robot.vrm from shared/)", async () => {
  const s = await drop(readFileSync(join(SHARED, "avatars", "debug-robot.vrm")), "debug-robot-dropped.vrm");
  assert.equal(s.avatar?.name, "debug-robot-dropped.vrm", s.status);
  assert.equal(s.avatar.vrmVersion, "1");
  assert.equal(s.avatar.boneCount, 53);
  assertParserAgrees(s.avatar);
  assertFiniteResult(s.results.with, "with");
  assert.ok(s.results.with.alignment.right, "the right hand is aligned");
  await assertSkeletonDrawn(s, "drop-vrm1-robot.png");
  assert.deepEqual(errors, []);
});

test("dropping a VRM 1.0 file with human proportions (tests/fixtures/human-proportions-vrm1.vrm)", async (t) => {
  const file = join(REPO, "tests", "fixtures", "human-proportions-vrm1.vrm");
  if (!existsSync(file)) {
    t.skip("tests/fixtures/human-proportions-vrm1.vrm is not in this checkout yet");
    return;
  }
  const s = await drop(readFileSync(file), "human-proportions-vrm1.vrm");
  assert.equal(s.avatar?.name, "human-proportions-vrm1.vrm", s.status);
  assert.equal(s.avatar.vrmVersion, "1");
  assertParserAgrees(s.avatar);
  assertFiniteResult(s.results.with, "with");
  const mm = s.errorMm.with.right;
  assert.ok(Number.isFinite(mm));
  assert.ok(Math.abs(s.shownErrorMm.with.right - mm) < 0.05, `three-vrm ${s.shownErrorMm.with.right} vs handrig ${mm} mm`);
  if (s.results.with.alignment.right.reachable) assert.ok(mm < 2, `alignment error ${mm} mm`);
  await assertSkeletonDrawn(s, "drop-vrm1-human-proportions.png");
  assert.deepEqual(errors, []);
});

test("dropping a generated human (tests/fixtures/avatars/child-vrm0.vrm): its body is shown, lit, facing the viewer", async (t) => {
  const bytes = readFileSync(join(REPO, "tests", "fixtures", "avatars", "child-vrm0.vrm"));
  const s = await drop(bytes, "child-vrm0.vrm");
  assert.equal(s.avatar?.name, "child-vrm0.vrm", s.status);
  assert.equal(s.avatar.vrmVersion, "0");
  assert.equal(s.avatar.boneCount, 54);
  assert.equal(s.avatar.hasBody, true);
  assertParserAgrees(s.avatar);
  assertFiniteResult(s.results.with, "with");
  assert.equal(await page.isChecked("#show-meshes"), true);
  const png = await page.screenshot({ path: shot("drop-vrm0-child.png") });
  const stats = await pixelStats(page, png, s.rects.with.body);
  assert.ok(stats.nonBg > 0.03 * stats.pixels, `the body is drawn (${stats.nonBg} of ${stats.pixels} pixels)`);
  assert.ok(s.left.x > s.right.x, `faces the viewer (left hand at x=${s.left.x}, right at x=${s.right.x})`);
  t.diagnostic(`right error with alignment ${s.errorMm.with.right?.toFixed(2)} mm`);
  assert.deepEqual(errors, []);
});

test("dropping a plain glTF humanoid (tests/fixtures/avatars/man-mixamo.glb, Mixamo names, bone rolls): bound by HandRig.fromGltf, driven like a VRM", async (t) => {
  const bytes = readFileSync(join(REPO, "tests", "fixtures", "avatars", "man-mixamo.glb"));
  const s = await drop(bytes, "man-mixamo.glb");
  assert.equal(s.avatar?.name, "man-mixamo.glb", s.status);
  assert.equal(s.avatar.vrmVersion, "1");
  assert.equal(s.avatar.boneCount, 54);
  assert.equal(s.avatar.hasBody, true);
  assert.equal(s.avatar.parser.reader, "fromGltf");
  assertParserAgrees(s.avatar);
  assertFiniteResult(s.results.with, "with");
  // three-vrm's normalized rig over the Mixamo bones and handrig's FK agree.
  const mm = s.errorMm.with.right;
  if (Number.isFinite(mm)) {
    assert.ok(Math.abs(s.shownErrorMm.with.right - mm) < 0.05, `three ${s.shownErrorMm.with.right} vs handrig ${mm} mm`);
  }
  const png = await page.screenshot({ path: shot("drop-glb-mixamo-man.png") });
  const stats = await pixelStats(page, png, s.rects.with.body);
  assert.ok(stats.nonBg > 0.03 * stats.pixels, `the body is drawn (${stats.nonBg} of ${stats.pixels} pixels)`);
  assert.ok(s.left.x > s.right.x, `faces the viewer (left hand at x=${s.left.x}, right at x=${s.right.x})`);
  t.diagnostic(`right error with alignment ${mm?.toFixed(2)} mm`);
  assert.deepEqual(errors, []);
});

test("a broken file is reported on the page and the current avatar keeps working", async () => {
  const good = readFileSync(join(SHARED, "avatars", "debug-robot.vrm"));
  const current = await page.evaluate(() => window.__handrigDemo.avatar.name);
  const s = await drop(good.subarray(0, 1000), "truncated.vrm");
  assert.match(s.status, /could not load truncated\.vrm/);
  assert.equal(s.avatar.name, current, "previous avatar kept");
  assertFiniteResult(s.results.with, "with");
  assert.ok(s.results.with.alignment.right);
  const nonVrm = await drop(Buffer.from("not a vrm at all"), "notes.vrm");
  assert.match(nonVrm.status, /could not load notes\.vrm/);
  assert.deepEqual(errors, []);
});
