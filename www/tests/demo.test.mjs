// Browser tests of the demo page on the bundled robot and recordings: loading, rendering,
// playback, the alignment error readout, the options panel and the webcam panel. The page opens
// on the robot (`?avatar=robot`): these tests judge the drawn skeleton (its finger colours) and
// its 53 bones; the default avatar, the generated woman, is tested in avatars.test.mjs.

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { around, diffPixels, launch, openDemo, pixelStats, shot } from "./helpers.mjs";

let env;
let page;
let errors;

before(async () => {
  env = await launch();
  ({ page, errors } = await openDemo(env, "?paused&avatar=robot"));
});

after(async () => {
  await env?.close();
});

const demoState = () =>
  page.evaluate(() => {
    const d = window.__handrigDemo;
    return {
      state: d.state,
      error: d.error,
      frame: d.frame,
      frameCount: d.frameCount,
      wasmBuild: d.wasmBuild,
      avatar: d.avatar,
      options: d.options,
      errorMm: d.errorMm,
      shownErrorMm: d.shownErrorMm,
      solveUs: d.solveUs,
      results: d.results,
    };
  });

const setFrame = (i) => page.evaluate((i) => window.__handrigDemo.setFrame(i), i);
const rects = () => page.evaluate(() => window.__handrigDemo.viewRects());
const screenPoint = (view, bone, part = "body") =>
  page.evaluate(([v, b, p]) => window.__handrigDemo.screenPoint(v, b, p), [view, bone, part]);

test("the page loads with no console errors and builds the panel from optionDescriptions()", async () => {
  const s = await demoState();
  assert.equal(s.state, "ready", `page state ${s.state}: ${s.error}`);
  // Let a few frames render before judging the console.
  await page.evaluate(() => window.__handrigDemo.nextRender());
  assert.deepEqual(errors, []);
  assert.equal(s.avatar.name, "debug-robot.vrm");
  assert.equal(s.avatar.vrmVersion, "1");
  assert.equal(s.avatar.boneCount, 53);
  assert.equal(s.frameCount, 281, "281 paired frames (the Kinect session is the shorter recording)");
  // Chromium has WebAssembly SIMD: the loader fetched the SIMD build.
  assert.equal(s.wasmBuild, "simd128");

  const descriptions = await page.evaluate(() => window.__handrigDemo.optionDescriptions);
  assert.ok(descriptions.length >= 6, "the package describes its options");
  const paths = await page.$$eval("#options .opt", (els) => els.map((e) => e.dataset.path));
  assert.deepEqual(paths, descriptions.map((d) => d.path ?? d.name));
  for (const d of descriptions) {
    const ctl = `#options .opt[data-path="${d.path ?? d.name}"]`;
    if (d.type === "boolean") assert.equal(await page.locator(`${ctl} input[type=checkbox]`).count(), 1, d.path);
    if (d.type === "enum") {
      const values = await page.$$eval(`${ctl} option`, (os) => os.map((o) => o.value));
      assert.deepEqual(values, d.values.map(String), d.path);
    }
    if (d.type === "number") assert.equal(await page.locator(`${ctl} input[name="${d.path ?? d.name}"]`).count(), 1, d.path);
  }
});

test("the avatar renders: skeleton pixels in both views, fingers visible", async () => {
  await setFrame(140);
  const png = await page.screenshot({ path: shot("demo-frame140.png") });
  const r = await rects();
  for (const view of ["without", "with"]) {
    const s = await pixelStats(page, png, r[view].body);
    assert.ok(s.nonBg > 0.01 * s.pixels, `${view}: screenshot is not blank (${s.nonBg} of ${s.pixels} pixels)`);
    assert.ok(s.saturated > 1500, `${view}: skeleton pixels present (${s.saturated})`);
  }
  // Fingers are drawn one colour each; the ring finger (cyan, hue bucket 180-210) and the
  // little finger (violet, 270-300) have no other use on the page, so finding them around the
  // right hand in the close-up means the fingers are drawn there.
  const p = await screenPoint("with", "rightMiddleProximal", "close");
  assert.ok(p, "the right hand is on screen");
  const hand = await pixelStats(page, png, around(p, 90, r.with.close));
  assert.ok(hand.hues[6] >= 10, `ring finger pixels near the hand: ${hand.hues}`);
  assert.ok(hand.hues[9] >= 10, `little finger pixels near the hand: ${hand.hues}`);
});

test("playback advances: two frames differ in the hand region, play and scrub move the frame", async () => {
  await setFrame(40);
  const a = await page.screenshot({ path: shot("demo-frame040.png") });
  const pa = await screenPoint("with", "rightHand");
  await setFrame(110);
  const b = await page.screenshot({ path: shot("demo-frame110.png") });
  const pb = await screenPoint("with", "rightHand");
  const r = await rects();
  const region = around({ x: (pa.x + pb.x) / 2, y: (pa.y + pb.y) / 2 }, 80 + Math.hypot(pa.x - pb.x, pa.y - pb.y) / 2, r.with.body);
  const changed = await diffPixels(page, a, b, region);
  assert.ok(changed > 150, `hand region changed between frames 40 and 110 (${changed} pixels)`);
  const close = await diffPixels(page, a, b, r.with.close);
  assert.ok(close > 150, `hand close-up changed (${close} pixels)`);

  // Play for a while: the frame moves on by itself.
  await setFrame(0);
  await page.click("#play");
  await page.waitForFunction(() => window.__handrigDemo.frame >= 5, null, { timeout: 20_000 });
  await page.click("#play");
  const stopped = (await demoState()).frame;
  await page.waitForTimeout(400);
  assert.equal((await demoState()).frame, stopped, "pause stops playback");

  // Scrub.
  await page.locator("#scrub").fill("200");
  await page.evaluate(() => window.__handrigDemo.nextRender());
  assert.equal((await demoState()).frame, 200);
  assert.match(await page.textContent("#frame-label"), /frame 200 \/ 280/);
});

test("alignment: the error readout is finite and below 2 mm, without alignment it is larger", async () => {
  const frames = [];
  for (let i = 0; i < 281; i += 14) frames.push(i);
  let reachable = 0;
  const withMm = [];
  const withoutMm = [];
  for (const i of frames) {
    await setFrame(i);
    const s = await demoState();
    const al = s.results.with.alignment.right;
    assert.ok(al, `frame ${i}: the right hand is aligned`);
    const mm = s.errorMm.with.right;
    assert.ok(Number.isFinite(mm), `frame ${i}: finite error`);
    // The readout shows the same number.
    const text = await page.textContent("#ro-right-with");
    assert.ok(Math.abs(Number(text) - mm) < 0.06, `frame ${i}: readout "${text}" vs ${mm}`);
    // What three-vrm shows (the avatar's normalized distal joint) agrees with handrig's own
    // forward kinematics: the result applies directly to three-vrm's bones.
    assert.ok(Math.abs(s.shownErrorMm.with.right - mm) < 0.05, `frame ${i}: shown ${s.shownErrorMm.with.right} vs ${mm}`);
    if (!al.reachable) continue;
    reachable++;
    withMm.push(mm);
    withoutMm.push(s.errorMm.without.right);
    assert.ok(mm < 2, `frame ${i}: alignment error ${mm.toFixed(3)} mm < 2 mm`);
    assert.ok(s.solveUs.with > 0, "solve time measured");
  }
  assert.ok(reachable >= frames.length * 0.8, `most frames reachable (${reachable}/${frames.length})`);
  const median = (xs) => [...xs].sort((a, b) => a - b)[xs.length >> 1];
  assert.ok(median(withoutMm) > 5 * Math.max(median(withMm), 0.1), `without alignment the error is larger: median ${median(withoutMm)} vs ${median(withMm)} mm`);
  await setFrame(140);
  await page.screenshot({ path: shot("demo-alignment-frame140.png") });
});

/** Changes one option through its control in the panel, as a user would. */
async function setControl(d, value) {
  const path = d.path ?? d.name;
  const ctl = `#options .opt[data-path="${path}"]`;
  if (d.type === "points" || d.type === "numbers") {
    const input = page.locator(`${ctl} input[name="${path}"]`);
    await input.fill(value == null ? "" : d.type === "numbers" ? value.join(", ") : JSON.stringify(value));
    await input.dispatchEvent("change");
  } else if (d.type === "boolean") await page.locator(`${ctl} input[type=checkbox]`).setChecked(value);
  else if (d.type === "enum") await page.locator(`${ctl} select`).selectOption(String(value));
  else if (value === null) await page.locator(`${ctl} input[name="${path}:auto"]`).setChecked(true);
  else {
    const auto = page.locator(`${ctl} input[name="${path}:auto"]`);
    if (await auto.count()) await auto.setChecked(false);
    await page.locator(`${ctl} input[name="${path}"]`).fill(String(value));
  }
  await page.evaluate(() => window.__handrigDemo.nextRender());
}

test("every control re-creates the rigs with its option, and the controls change the output", async () => {
  await setFrame(140);
  const base = await demoState();
  const descriptions = await page.evaluate(() => window.__handrigDemo.optionDescriptions);
  const get = (o, path) => path.split(".").reduce((x, k) => x?.[k], o);
  const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);

  // What each known option must do to this frame (the subject's right hand, aligned index DIP).
  const effects = {
    inputMirrored: (s) => assert.ok(s.results.with.hands.left && !s.results.with.hands.right, "hand moves to the avatar's left"),
    mirror: (s) => {
      assert.ok(s.results.with.hands.left && !s.results.with.hands.right, "hand moves to the avatar's left");
      // The page mirrors the Kinect wrists with it: the avatar's left wrist is the subject's
      // right wrist reflected (the robot is symmetric about x = 0).
      const p = base.results.without.ikTargets.right.position;
      const q = s.results.without.ikTargets.left.position;
      assert.ok(dist(q, [-p[0], p[1], p[2]]) < 1e-5, `mirrored wrist ${q} vs ${p}`);
    },
    // Alignment off: the finger misses its target as in the plain view (which has self-contact
    // off too, so the two need not agree to the micrometer), far more than when aligned.
    "alignment.enabled": (s) => {
      const off = s.errorMm.with.right;
      assert.ok(off > 1 && off > 20 * base.errorMm.with.right, `alignment off: ${off} mm, on: ${base.errorMm.with.right} mm`);
    },
    "alignment.finger": (s) => assert.ok(dist(s.results.with.alignment.right.targetDip, base.results.with.alignment.right.targetDip) > 0.005, "another finger's target"),
    "alignment.point": (s) => assert.ok(dist(s.results.with.alignment.right.targetDip, base.results.with.alignment.right.targetDip) > 0.005, "tip target differs from DIP"),
    "alignment.weight": (s) => {
      const p = s.results.with.ikTargets.right.position;
      assert.ok(dist(p, base.results.with.ikTargets.right.position) > 0.002, "IK target moves");
      assert.ok(dist(p, s.results.without.ikTargets.right.position) > 0.002, "and is not the plain pose wrist");
    },
    minHandScore: (s) => assert.ok(!s.results.with.hands.right && !s.results.with.alignment.right, "the hand (score < 1) is ignored"),
    // Playing a few frames with filtering off: the jitter readout is there (and differs).
    "filter.enabled": async (s) => {
      assert.equal(s.options.filter.enabled, false);
      const text = await page.textContent("#ro-jitter-with");
      assert.match(text, /^(–|\d+\.\d\d)$/, `jitter readout ${text}`);
    },
    // Every arm solver reaches the same aligned target (screenshots of each).
    armSolver: (s) => {
      assert.ok(s.results.with.alignment.right.reachable, "reached");
      assert.ok(s.errorMm.with.right < 0.05, `alignment error ${s.errorMm.with.right} mm`);
    },
    handStrategy: async (s) => {
      const r = s.results.with.retarget.right;
      assert.ok(r && r.scale > 0 && r.targets.index, "retargeting report with the fingertip targets");
      const shown = await page.evaluate(() => window.__handrigDemo.retargetMarkersShown?.());
      assert.equal(shown, 5, "the five fingertip targets are drawn");
    },
    torso: (s) => {
      const spine = s.results.with.bones.spine;
      if (s.options.torso === "pose") {
        // The Kinect body turns and bends the avatar's spine; the arms stay aligned on it.
        const turned = 2 * Math.acos(Math.min(1, Math.abs(spine[3])));
        assert.ok(turned > (0.5 * Math.PI) / 180, `spine turned ${turned} rad`);
        assert.ok(s.errorMm.with.right < 0.5, `aligned on the moving torso: ${s.errorMm.with.right} mm`);
      } else assert.equal(spine, undefined, "torso bones are the app's");
    },
  };
  const nonDefault = (d) => {
    if (d.type === "boolean") return [!d.default];
    // Points options (contact.faceAnchors) are covered by the Node tests: no value of theirs
    // has a single control value to compare.
    if (d.type === "points") return [];
    if (d.type === "enum") return d.values.filter((v) => v !== d.default);
    // A fixed-length array (retarget.tipWeights): its first number doubled.
    if (d.type === "numbers") return [d.default.map((x, i) => (i === 0 ? Math.min(d.max, x * 2) : x))];
    if (d.path === "minHandScore") return [1];
    // A value on the control's step grid (a range input snaps to it), away from the default.
    const step = d.step ? Number(d.step.toPrecision(6)) : 0.01;
    const min = Number.isFinite(d.min) ? Number(d.min.toPrecision(6)) : 0;
    const snap = (x) => Number((min + Math.round((x - min) / step) * step).toPrecision(6));
    if (d.default == null) return [snap(Math.max(min, 1.25))];
    return [Number.isFinite(d.min) && Number.isFinite(d.max) ? snap((d.min + d.max) / 2) : snap(d.default * 2)];
  };

  let checkedEffects = 0;
  for (const d of descriptions) {
    const path = d.path ?? d.name;
    for (const value of nonDefault(d)) {
      await setControl(d, value);
      const s = await demoState();
      assert.deepEqual(get(s.options, path), value, `${path}: the panel's options carry ${value}`);
      assert.doesNotMatch(await page.textContent("#status"), /rejected|failed/, `${path}=${value} accepted`);
      assert.ok(s.results.with, `${path}=${value}: the new rig solves`);
      if (effects[path]) {
        await effects[path](s);
        checkedEffects++;
        await page.screenshot({ path: shot(`option-${path.replace(/\./g, "-")}-${value}.png`) });
      }
    }
    // Back to the default: the output is the baseline again (rigs are re-created).
    await setControl(d, d.default);
    const s = await demoState();
    assert.deepEqual(s.options, base.options, `${path} restored`);
    assert.deepEqual(s.results.with.bones, base.results.with.bones, `${path}: same output after restoring`);
  }
  assert.ok(checkedEffects >= 6, `output effects checked for ${checkedEffects} options`);
  assert.deepEqual(errors, []);
});

test("every number control accepts the ends of its range (the package's bounds, e.g. 0.05, not 0.0500000007)", async () => {
  await setFrame(140);
  const base = await demoState();
  const descriptions = await page.evaluate(() => window.__handrigDemo.optionDescriptions);
  const get = (o, path) => path.split(".").reduce((x, k) => x?.[k], o);
  let checked = 0;
  for (const d of descriptions) {
    if (d.type !== "number" || !Number.isFinite(d.min) || !Number.isFinite(d.max)) continue;
    for (const end of [d.min, d.max]) {
      await setControl(d, end);
      const s = await demoState();
      const v = get(s.options, d.path);
      assert.doesNotMatch(await page.textContent("#status"), /rejected|failed/, `${d.path}=${end} accepted`);
      assert.ok(s.results.with, `${d.path}=${end}: the new rig solves`);
      // A range input snaps to min + k * step: the far end may land a step fraction short.
      assert.ok(v >= d.min && v <= d.max && Math.abs(v - end) <= (d.step ?? 0) * (1 + 1e-9), `${d.path}: ${v} for ${end}`);
      checked++;
    }
    await setControl(d, d.default);
  }
  assert.deepEqual((await demoState()).options, base.options, "restored");
  assert.ok(checked >= 30, `${checked} range ends`);
  assert.deepEqual(errors, []);
});

test("the jitter readout: playing the recording with the One Euro filter on shows less jitter than with it off", async () => {
  const play = async () => {
    for (let i = 60; i < 120; i++) await setFrame(i);
    return page.evaluate(() => window.__handrigDemo.jitter.with);
  };
  const on = await play();
  await page.evaluate(() => window.__handrigDemo.setOption("filter.enabled", false));
  const off = await play();
  await page.evaluate(() => window.__handrigDemo.setOption("filter.enabled", true));
  assert.ok(Number.isFinite(on) && Number.isFinite(off), `jitter ${on} / ${off}`);
  assert.ok(on < 0.8 * off, `jitter with the filter ${on.toFixed(2)} vs without ${off.toFixed(2)} deg/frame²`);
  console.log(`# demo jitter readout: ${on.toFixed(2)} deg/frame² filtered, ${off.toFixed(2)} unfiltered`);
  assert.deepEqual(errors, []);
});

test("webcam mode: built-in MediaPipe by default; the tasks-vision mode explains the model files and asks for them", async () => {
  await page.check('input[name="source"][value="webcam"]');
  assert.ok(await page.isVisible("#webcam-controls"));
  // The default needs nothing: Holistic from npm, no model fields shown.
  assert.equal(await page.inputValue("#webcam-mode"), "holistic");
  assert.equal(await page.isVisible("#tasks-fields"), false);
  assert.match(await page.textContent("#webcam-controls"), /@mediapipe\/holistic/);
  await page.selectOption("#webcam-mode", "tasks");
  assert.ok(await page.isVisible("#tasks-fields"));
  assert.equal(await page.isVisible("#webcam-inference-field"), false, "the inference choice is for the built-in modes");
  assert.match(await page.textContent("#tasks-fields"), /\.task/);
  assert.match(await page.inputValue("#wasm-base"), /tasks-vision\/wasm$/);
  await page.click("#webcam-start");
  assert.match(await page.textContent("#webcam-status"), /hand landmarker model/);
  await page.selectOption("#webcam-mode", "holistic");
  await page.check('input[name="source"][value="recording"]');
  assert.ok(await page.isVisible("#recording-controls"));
  await setFrame(140);
  assert.ok((await demoState()).results.with.alignment.right, "recordings work again");
  assert.deepEqual(errors, []);
});

test("webcam mode without a camera says so, and loads no model", async () => {
  // Camera access granted (as a user would), but headless Chromium here has no camera device.
  await env.context.grantPermissions(["camera"], { origin: new URL(env.url).origin });
  await page.check('input[name="source"][value="webcam"]');
  const requests = [];
  const onRequest = (r) => requests.push(r.url());
  page.on("request", onRequest);
  const before = errors.length;
  await page.click("#webcam-start");
  await page.waitForFunction(() => /failed|running/.test(document.getElementById("webcam-status").textContent), null, {
    timeout: 30_000,
  });
  page.off("request", onRequest);
  assert.match(await page.textContent("#webcam-status"), /^webcam failed: no camera found/);
  assert.deepEqual(requests.filter((u) => /@mediapipe\/holistic/.test(u)), [], "no model was fetched");
  assert.deepEqual(errors.slice(before), []);
  assert.equal(await page.isDisabled("#webcam-start"), false, "can try again");
  assert.equal(await page.isDisabled("#record"), true, "nothing to record");
  await page.check('input[name="source"][value="recording"]');
});

test("webcam mode loads the local MediaPipe runtime and reports a bad model file on the page", async () => {
  await page.check('input[name="source"][value="webcam"]');
  await page.selectOption("#webcam-mode", "tasks");
  await page.setInputFiles("#hand-model-file", {
    name: "not-a-model.task",
    mimeType: "application/octet-stream",
    buffer: Buffer.from("this is not a MediaPipe model bundle"),
  });
  const before = errors.length;
  await page.click("#webcam-start");
  await page.waitForFunction(() => /failed|running/.test(document.getElementById("webcam-status").textContent), null, {
    timeout: 60_000,
  });
  const text = await page.textContent("#webcam-status");
  // The wasm runtime (served from www/node_modules) loaded and started the graph; it is the
  // model bundle that is refused.
  assert.match(text, /^webcam failed: .*(zip|model|archive)/i);
  assert.doesNotMatch(text, /\n/);
  // MediaPipe itself logs the refused graph to the console; nothing else may.
  const extra = errors.slice(before).filter((e) => !/StartGraph failed|MediaPipeTasksStatus/.test(e));
  assert.deepEqual(extra, []);
  errors.length = before;
  assert.equal(await page.isDisabled("#webcam-start"), false, "can try again");
  await page.selectOption("#webcam-mode", "holistic");
  await page.check('input[name="source"][value="recording"]');
});
