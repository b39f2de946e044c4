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

const readme = readFileSync(join(REPO, "README.md"), "utf8");

/** The fenced blocks of language `lang` in the README section headed exactly `heading`. */
function codeBlocks(heading, lang) {
  const section = readme.split(`\n${heading}\n`)[1]?.split(/^##+ /m)[0];
  assert.ok(section, `README has a section "${heading}"`);
  return [...section.matchAll(new RegExp(`^\`\`\`${lang}\\n([\\s\\S]*?)^\`\`\`$`, "gm"))].map((m) => m[1]);
}

const HEADING = "## Quick start: three-vrm in the browser";

const TASKS_VISION_STAND_IN = `
// Stand-in for @mediapipe/tasks-vision: the shared hand recording, frame after frame.
const recording = await (await fetch("/assets/right-hand-video-mediapipe.json")).json();
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
  // The upper arms' largest angle from hanging straight down over every frame (degrees): a hand
  // tracker gives no wrist, so the arms rest (arm.idle), never in the T-pose.
  for (const side of ["left", "right"]) {
    const upper = vrm.humanoid.getNormalizedBoneNode(side + "UpperArm");
    const lower = vrm.humanoid.getNormalizedBoneNode(side + "LowerArm");
    lower.updateWorldMatrix(true, false);
    const a = upper.matrixWorld.elements;
    const b = lower.matrixWorld.elements;
    const d = [b[12] - a[12], b[13] - a[13], b[14] - a[14]];
    const deg = (Math.acos(-d[1] / Math.hypot(d[0], d[1], d[2])) * 180) / Math.PI;
    qs.armFromDown = Math.max(qs.armFromDown ?? 0, deg);
  }
  return written;
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
      armFromDown: qs.armFromDown,
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
  // No wrist to follow: both arms rest down by the sides on every frame, never the T-pose.
  assert.ok(state.armFromDown < 30, `an upper arm ${state.armFromDown.toFixed(1)} degrees from hanging down`);
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
