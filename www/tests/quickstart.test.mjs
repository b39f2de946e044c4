// The README's "Quick start: three-vrm in the browser" runs as written in Chromium: its two
// blocks (index.html with the import map, main.js) are served unchanged under /quickstart/,
// next to the node_modules/ they name (three and @pixiv/three-vrm from www/node_modules, handrig
// from the built package) and avatar.vrm (the shared robot). Two stand-ins, both at the URLs the
// README's import map names, so the README's code is untouched:
//   * @mediapipe/tasks-vision: FilesetResolver and HandLandmarker whose detectForVideo returns
//     the frames of the shared hand recording (right-hand-video-mediapipe.json), in order, as
//     tasks-vision HandLandmarkerResults (no model file, no MediaPipe wasm);
//   * handrig/three-vrm: the real adapter, re-exported, with applyToVRM counting its calls and
//     keeping the VRM it was given, so the test can look at the avatar.
// The webcam is Chromium's fake camera (--use-fake-device-for-media-stream).

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync, statSync } from "node:fs";
import { extname, join, normalize, resolve, sep } from "node:path";
import { findPackageDir } from "../serve.mjs";
import { launch, pixelStats, REPO, SHARED, shot, WWW } from "./helpers.mjs";
import { ARM_PROBE } from "./arm-probe.mjs";

const readme = readFileSync(join(REPO, "README.md"), "utf8");

/** The fenced blocks of language `lang` in the README section headed exactly `heading`. */
function codeBlocks(heading, lang) {
  const section = readme.split(`\n${heading}\n`)[1]?.split(/^##+ /m)[0];
  assert.ok(section, `README has a section "${heading}"`);
  return [...section.matchAll(new RegExp(`^\`\`\`${lang}\\n([\\s\\S]*?)^\`\`\`$`, "gm"))].map((m) => m[1]);
}

const HEADING = "## Quick start: three-vrm in the browser";

const TASKS_VISION_STAND_IN = `
// Stand-in for @mediapipe/tasks-vision: the shared hand recording, frame after frame (or, with
// ?clip=NAME in the page's URL, the hands of that sign-language clip, without its pose).
const clip = new URLSearchParams(location.search).get("clip");
const recording = clip
  ? (await (await fetch("clip.json?name=" + clip)).json()).frames
  : await (await fetch("/assets/right-hand-video-mediapipe.json")).json();
const qs = (globalThis.__quickstart ??= { detections: 0, applied: 0 });
const points = (list) => list.map(([x, y, z]) => ({ x, y, z }));
export const FilesetResolver = {
  async forVisionTasks(basePath) {
    qs.wasmBase = basePath;
    return { wasmLoaderPath: basePath + "/vision_wasm_internal.js", wasmBinaryPath: basePath + "/vision_wasm_internal.wasm" };
  },
};
export class HandLandmarker {
  static async createFromOptions(fileset, options) {
    qs.options = options;
    return new HandLandmarker();
  }
  detectForVideo(video, timestamp) {
    if (!(video instanceof HTMLVideoElement)) throw new Error("detectForVideo: not a video element");
    if (!(video.videoWidth > 0)) throw new Error("detectForVideo: the video has no frame yet");
    if (!(timestamp > (this.last ?? -Infinity))) throw new Error("detectForVideo: timestamps must increase");
    this.last = timestamp;
    const frame = recording[qs.detections++ % recording.length];
    qs.wristImage = frame.hands.map((h) => h.landmarks[0]); // for the probe: where each hand is
    const handedness = frame.hands.map((h) => [
      { index: h.handedness === "Left" ? 0 : 1, score: h.score, categoryName: h.handedness, displayName: h.handedness },
    ]);
    return {
      landmarks: frame.hands.map((h) => points(h.landmarks)),
      worldLandmarks: frame.hands.map((h) => points(h.worldLandmarks)),
      handedness,
      handednesses: handedness,
    };
  }
  close() {}
}
`;

const ADAPTER_PROBE = `
// The real handrig/three-vrm, with applyToVRM watched.
import { applyToVRM as apply } from "./three-vrm.real.js";
export * from "./three-vrm.real.js";
const qs = (globalThis.__quickstart ??= { detections: 0, applied: 0 });
export function applyToVRM(vrm, result) {
  const written = apply(vrm, result);
  qs.applied++;
  qs.written = written;
  qs.vrm = vrm;
  // Per frame and side, from the posed avatar (three-vrm's normalized bones, world space): an
  // arm without a tracked hand rests (arm.idle): its upper arm's largest angle from hanging
  // straight down; an arm with one follows it: the hand bone's world position against the
  // hand's image wrist, and how far the arm is from the T-pose (upper arm and forearm straight
  // out sideways). Neither may T-pose on any frame.
${ARM_PROBE}  return written;
}
`;

const TYPES = {
  ".html": "text/html",
  ".js": "text/javascript",
  ".mjs": "text/javascript",
  ".json": "application/json",
  ".wasm": "application/wasm",
  ".vrm": "model/gltf-binary",
};

/** A file under `root` for a URL path below it, or null outside it or missing. */
function fileIn(root, rel) {
  const full = resolve(root, normalize(decodeURIComponent(rel)).replace(/^[/\\]+/, ""));
  if (!full.startsWith(root + sep)) return null;
  try {
    return statSync(full).isFile() ? full : null;
  } catch {
    return null;
  }
}

let env;
let page;
const errors = [];
const served = [];

before(async () => {
  const [html, js] = [codeBlocks(HEADING, "html")[0], codeBlocks(HEADING, "js")[0]];
  assert.ok(html && js, "the browser quick start has an html and a js block");
  const pkg = findPackageDir();
  env = await launch({ args: ["--use-fake-device-for-media-stream", "--use-fake-ui-for-media-stream"] });
  const base = `${env.url}quickstart/`;
  await env.context.route(`${base}**`, async (route) => {
    const rel = new URL(route.request().url()).pathname.slice("/quickstart/".length);
    served.push(rel);
    const body = (type, content) => route.fulfill({ status: 200, contentType: type, body: content });
    const file = (path) => (path ? body(TYPES[extname(path)] ?? "application/octet-stream", readFileSync(path)) : null);
    let done = null;
    if (rel === "" || rel === "index.html") done = body("text/html", html);
    else if (rel === "main.js") done = body("text/javascript", js);
    else if (rel === "avatar.vrm") done = file(join(SHARED, "avatars", "debug-robot.vrm"));
    else if (rel === "clip.json") {
      const name = new URL(route.request().url()).searchParams.get("name");
      done = /^[a-z]+$/.test(name) ? file(fileIn(join(SHARED, "data", "asl"), `${name}.json`)) : null;
    }
    else if (rel === "node_modules/@mediapipe/tasks-vision/vision_bundle.mjs") done = body("text/javascript", TASKS_VISION_STAND_IN);
    else if (rel === "node_modules/handrig/three-vrm.js") done = body("text/javascript", ADAPTER_PROBE);
    else if (rel === "node_modules/handrig/three-vrm.real.js") done = file(join(pkg, "three-vrm.js"));
    else if (rel.startsWith("node_modules/handrig/")) done = file(fileIn(pkg, rel.slice("node_modules/handrig/".length)));
    else if (/^node_modules\/(three|@pixiv\/three-vrm)\//.test(rel)) done = file(fileIn(join(WWW, "node_modules"), rel.slice("node_modules/".length)));
    if (done) return done;
    errors.push(`not served: /quickstart/${rel}`);
    return route.fulfill({ status: 404, body: "not found" });
  });
  page = await env.context.newPage();
  page.on("console", (m) => m.type() === "error" && errors.push(`console.error: ${m.text()}`));
  page.on("pageerror", (e) => errors.push(`pageerror: ${e.message}`));
  page.on("requestfailed", (r) => errors.push(`request failed: ${r.url()} ${r.failure()?.errorText}`));
  page.on("response", (r) => r.status() >= 400 && !r.url().endsWith("/favicon.ico") && errors.push(`HTTP ${r.status()}: ${r.url()}`));
  await page.goto(`${base}index.html`);
});

after(async () => {
  await env?.close();
});

test("the browser quick start runs as written: the hands of the recording drive the avatar", async () => {
  await page
    .waitForFunction(() => (globalThis.__quickstart?.applied ?? 0) >= 60, null, { timeout: 90_000 })
    .catch((e) => assert.fail(`${e.message}\nerrors: ${errors.join("\n")}`));
  assert.deepEqual(errors, []);
  const state = await page.evaluate(() => {
    const qs = globalThis.__quickstart;
    const h = qs.vrm.humanoid;
    const q = (node) => node.quaternion.toArray();
    return {
      detections: qs.detections,
      applied: qs.applied,
      idleFromDown: qs.idleFromDown,
      armFromTPose: qs.armFromTPose,
      tracked: { left: qs.track.left.length, right: qs.track.right.length },
      written: qs.written,
      options: qs.options,
      wasmBase: qs.wasmBase,
      normalized: Object.fromEntries(["leftHand", "leftIndexProximal", "rightIndexProximal"].map((b) => [b, q(h.getNormalizedBoneNode(b))])),
      raw: q(h.getRawBoneNode("leftIndexProximal")),
      rawRest: h.normalizedRestPose && qs.vrm.humanoid.rawRestPose.leftIndexProximal.rotation,
      canvas: [...document.querySelectorAll("canvas")].map((c) => [c.width, c.height]),
    };
  });
  // Every animation frame tracked a hand and applied the result.
  assert.ok(state.detections >= state.applied && state.applied >= 60, JSON.stringify(state));
  assert.equal(state.options.runningMode, "VIDEO");
  assert.equal(state.options.baseOptions.modelAssetPath, "hand_landmarker.task");
  // Every driven bone is written each frame (arms, hands, fingers: `rig.drivenBones()`).
  assert.ok(state.written >= 30, `applyToVRM wrote ${state.written} bones`);
  // mirror: true: the recording's right hand (labelled "Left", un-mirrored) drives the avatar's
  // left hand; its right hand has no tracked hand and rests.
  const turned = (q) => Math.abs(q[3]) < 0.9999;
  assert.ok(turned(state.normalized.leftHand) && turned(state.normalized.leftIndexProximal), JSON.stringify(state.normalized));
  assert.deepEqual(state.normalized.rightIndexProximal, [0, 0, 0, 1]);
  // The tracked hand places its arm (arms from hands alone) on most frames, never in the T-pose;
  // the arm without a hand rests down by the side on every frame.
  assert.ok(state.tracked.left > state.applied / 2 && state.tracked.right === 0, JSON.stringify(state.tracked));
  assert.ok(state.armFromTPose > 30, `an arm ${state.armFromTPose.toFixed(1)} degrees from the T-pose`);
  assert.ok(state.idleFromDown < 30, `the idle upper arm ${state.idleFromDown.toFixed(1)} degrees from hanging down`);
  // vrm.update copied the normalized rotations onto the model's own bones.
  const dot = Math.abs(state.raw.reduce((s, v, k) => s + v * state.rawRest[k], 0));
  assert.ok(dot < 0.9999, `raw leftIndexProximal still at rest: ${state.raw} vs ${state.rawRest}`);
  assert.equal(state.canvas.length, 1);
  // The page fetched what the README says it needs, and the SIMD build (Chromium has WebAssembly SIMD).
  for (const want of ["index.html", "main.js", "avatar.vrm", "node_modules/handrig/index.js", "node_modules/handrig/wasm/handrig_simd_bg.wasm"]) {
    assert.ok(served.includes(want), `not requested: ${want} (requested: ${served.join(", ")})`);
  }
  const png = await page.screenshot({ path: shot("quickstart.png") });
  const viewport = page.viewportSize();
  const stats = await pixelStats(page, png, { x: 0, y: 0, w: viewport.width, h: viewport.height });
  assert.ok(stats.nonBg > 100, `the avatar is drawn: ${JSON.stringify(stats)}`);
});

test("HandRig.fromVrm from the fetched bytes, as the README writes it, builds the same rig", async () => {
  const line = readme.match(/`(HandRig\.fromVrm\(new Uint8Array\(await \(await fetch\("avatar\.vrm"\)\)\.arrayBuffer\(\)\)\))`/);
  assert.ok(line, "README has the fromVrm one-liner");
  const r = await page.evaluate(async (code) => {
    const { HandRig } = await import("./node_modules/handrig/index.js");
    const { restPoseFromVRM } = await import("./node_modules/handrig/three-vrm.js");
    const rig = await new Function("HandRig", `return (async () => ${code})();`)(HandRig);
    const fromThree = new HandRig(restPoseFromVRM(globalThis.__quickstart.vrm));
    const a = rig.restWorldPositions();
    const b = fromThree.restWorldPositions();
    let worst = 0;
    for (const [name, p] of Object.entries(a)) worst = Math.max(worst, Math.hypot(p[0] - b[name][0], p[1] - b[name][1], p[2] - b[name][2]));
    const out = { bones: Object.keys(a).length, worst, version: rig.vrmVersion };
    rig.free();
    fromThree.free();
    return out;
  }, line[1]);
  assert.equal(r.bones, 53);
  assert.equal(r.version, "1");
  assert.ok(r.worst < 1e-5, `rest positions differ by ${r.worst} m`);
  assert.deepEqual(errors, []);
});

test("the browser quick start on a sign-language clip's hands (no pose): both arms move with the hands, never in the T-pose", async () => {
  const clipPage = await env.context.newPage();
  const clipErrors = [];
  clipPage.on("console", (m) => m.type() === "error" && clipErrors.push(`console.error: ${m.text()}`));
  clipPage.on("pageerror", (e) => clipErrors.push(`pageerror: ${e.message}`));
  await clipPage.goto(`${env.url}quickstart/index.html?clip=again`);
  // again.json: 77 frames, both hands moving (one claps onto the other); played more than once.
  await clipPage
    .waitForFunction(() => (globalThis.__quickstart?.applied ?? 0) >= 130, null, { timeout: 120_000 })
    .catch((e) => assert.fail(`${e.message}\nerrors: ${[...errors, ...clipErrors].join("\n")}`));
  const png = await clipPage.screenshot({ path: shot("quickstart-hands-arms.png") });
  const state = await clipPage.evaluate(() => {
    const qs = globalThis.__quickstart;
    return { applied: qs.applied, idleFromDown: qs.idleFromDown, armFromTPose: qs.armFromTPose, track: qs.track };
  });
  const viewport = clipPage.viewportSize();
  await clipPage.close();
  assert.deepEqual(clipErrors, []);
  assert.ok(state.armFromTPose > 30, `an arm ${state.armFromTPose.toFixed(1)} degrees from the T-pose`);
  assert.ok(state.idleFromDown < 30, `an idle upper arm ${state.idleFromDown.toFixed(1)} degrees from hanging down`);
  // Pearson correlation of the avatar's hand bone (world, meters) with the hand's image wrist
  // over the frames its arm was placed: up in the image (y smaller) is up. (Across is reported:
  // with mirror: true, right in the un-mirrored image is the avatar's -X, as a mirror image
  // moves.)
  const r = (a, b) => {
    const mean = (v) => v.reduce((s, x) => s + x, 0) / v.length;
    const [ma, mb] = [mean(a), mean(b)];
    let [ab, aa, bb] = [0, 0, 0];
    for (let i = 0; i < a.length; i++) {
      ab += (a[i] - ma) * (b[i] - mb);
      aa += (a[i] - ma) ** 2;
      bb += (b[i] - mb) ** 2;
    }
    return ab / Math.sqrt(aa * bb);
  };
  const report = {};
  for (const side of ["left", "right"]) {
    const t = state.track[side];
    assert.ok(t.length > 40, `${side}: the arm placed from its hand on ${t.length} frames`);
    const up = r(t.map((s) => s.hand[1]), t.map((s) => -s.image[1]));
    const across = r(t.map((s) => s.hand[0]), t.map((s) => -s.image[0]));
    const rise = Math.max(...t.map((s) => s.hand[1])) - Math.min(...t.map((s) => s.hand[1]));
    report[side] = { frames: t.length, up: up.toFixed(2), across: across.toFixed(2), rise: rise.toFixed(2) };
    // (Not 1: the depth from the hand's size, the reach limit and self-contact near the face
    // move the hand bone too.)
    assert.ok(up > 0.5, `${side}: the hand bone rises and falls with the image wrist: ${JSON.stringify(report[side])}`);
    assert.ok(rise > 0.15, `${side}: the hand rose and fell ${rise.toFixed(2)} m`);
  }
  console.log(`# quick start on again.json's hands: ${JSON.stringify(report)}`);
  const stats = await pixelStats(page, png, { x: 0, y: 0, w: viewport.width, h: viewport.height });
  assert.ok(stats.nonBg > 100, `the avatar is drawn: ${JSON.stringify(stats)}`);
});
