// Issue 48's acceptance: a new user's run of the README. A clean Vite + TypeScript app, with the
// compiler settings of Vite's vanilla-ts template plus `exactOptionalPropertyTypes`, whose
// src/main.ts is the README's browser quick start (`main.js`) as written, built against the
// packed package (`npm pack` of pkg/, installed as node_modules/handrig), type-checked against
// the real three, @types/three, @pixiv/three-vrm and @mediapipe/tasks-vision, built for
// production and run in headless Chromium with a fake webcam. Two modules are swapped at build
// time only (Vite aliases; the type check sees the real ones): @mediapipe/tasks-vision plays the
// hands of the sign-language clip again.json (no model file, no MediaPipe wasm), and
// handrig/three-vrm is the real adapter watched (window.__quickstart). The avatar must move:
// both arms follow the hands, never in the T-pose. Options with `undefined` fields type-check
// under exactOptionalPropertyTypes and are taken at run time.

import { execFileSync } from "node:child_process";
import { cpSync, existsSync, mkdirSync, mkdtempSync, readFileSync, rmSync, symlinkSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { build, preview } from "vite";
import { findPackageDir } from "../serve.mjs";
import { REPO, SHARED, WWW, launch, pixelStats, shot } from "./helpers.mjs";
import { ARM_PROBE } from "./arm-probe.mjs";

const readme = readFileSync(join(REPO, "README.md"), "utf8");
const section = readme.split("\n## Quick start: three-vrm in the browser\n")[1]?.split(/^## /m)[0] ?? "";
const mainJs = [...section.matchAll(/^```js\n([\s\S]*?)^```$/gm)].map((m) => m[1])[0];

// Vite's vanilla-ts template (create-vite 6) tsconfig, with exactOptionalPropertyTypes added.
const TSCONFIG = {
  compilerOptions: {
    target: "ES2022",
    useDefineForClassFields: true,
    module: "ESNext",
    lib: ["ES2022", "DOM", "DOM.Iterable"],
    skipLibCheck: true,
    moduleResolution: "bundler",
    allowImportingTsExtensions: true,
    verbatimModuleSyntax: true,
    moduleDetection: "force",
    noEmit: true,
    strict: true,
    exactOptionalPropertyTypes: true,
    noUnusedLocals: true,
    noUnusedParameters: true,
    noFallthroughCasesInSwitch: true,
    noUncheckedSideEffectImports: true,
  },
  include: ["src"],
};

const INDEX_HTML = `<!doctype html>
<html lang="en">
  <head><meta charset="UTF-8" /><link rel="icon" href="data:," /><title>handrig quick start</title></head>
  <body style="margin: 0">
    <script type="module" src="/src/main.ts"></script>
  </body>
</html>
`;

// Options whose fields are given as undefined (a settings panel's unset values).
const OPTIONS_TS = `import { HandRig, type HandRigOptions } from "handrig";
export const unset: HandRigOptions = {
  mirror: undefined,
  arm: undefined,
  filter: { beta: undefined, enabled: undefined },
  handsOnly: { fov: undefined },
  calibration: { bodyScale: undefined },
};
export const takesUnset = (rest: ConstructorParameters<typeof HandRig>[0]) => new HandRig(rest, unset);
`;

const TASKS_VISION_STAND_IN = `// Stand-in for @mediapipe/tasks-vision (build-time alias): again.json's hands, frame after frame.
const recording = (await (await fetch("/again.json")).json()).frames;
const qs = (globalThis.__quickstart ??= { detections: 0, applied: 0 });
const points = (list) => list.map(([x, y, z]) => ({ x, y, z }));
export const FilesetResolver = { async forVisionTasks(basePath) { return { wasmLoaderPath: basePath, wasmBinaryPath: basePath }; } };
export class HandLandmarker {
  static async createFromOptions() { return new HandLandmarker(); }
  detectForVideo(video, timestamp) {
    if (!(video.videoWidth > 0)) throw new Error("detectForVideo: the video has no frame yet");
    if (!(timestamp > (this.last ?? -Infinity))) throw new Error("detectForVideo: timestamps must increase");
    this.last = timestamp;
    const frame = recording[qs.detections++ % recording.length];
    qs.wristImage = frame.hands.map((h) => h.landmarks[0]);
    const handedness = frame.hands.map((h) => [{ index: h.handedness === "Left" ? 0 : 1, score: h.score, categoryName: h.handedness, displayName: h.handedness }]);
    return { landmarks: frame.hands.map((h) => points(h.landmarks)), worldLandmarks: frame.hands.map((h) => points(h.worldLandmarks)), handedness, handednesses: handedness };
  }
}
`;

const ADAPTER_PROBE = `// handrig/three-vrm (build-time alias): the real adapter, applyToVRM watched.
import { applyToVRM as apply, restPoseFromVRM as rest } from "../node_modules/handrig/three-vrm.js";
import { takesUnset } from "./options.ts";
const qs = (globalThis.__quickstart ??= { detections: 0, applied: 0 });
export function restPoseFromVRM(vrm) {
  const pose = rest(vrm);
  takesUnset(pose).free(); // undefined option fields are taken at run time too
  qs.unsetTaken = true;
  return pose;
}
export function applyToVRM(vrm, result) {
  const written = apply(vrm, result);
  qs.applied++;
${ARM_PROBE}  return written;
}
`;

let env;
let project;
let server;

function link(from, to) {
  assert.ok(existsSync(from), `${from} is missing: run \`make setup\``);
  mkdirSync(join(to, ".."), { recursive: true });
  symlinkSync(from, to);
}

before(async () => {
  assert.ok(mainJs?.includes("rig.solve("), "the README's browser quick start has its main.js block");
  const pkg = findPackageDir();
  if (!pkg) throw new Error("the handrig package is not built: run `make pkg` first");
  project = mkdtempSync(join(tmpdir(), "handrig-readme-app-"));
  const modules = join(project, "node_modules");
  mkdirSync(join(modules, "handrig"), { recursive: true });
  const tarball = execFileSync("npm", ["pack", "--silent", "--pack-destination", project, pkg], { encoding: "utf8" }).trim().split("\n").pop();
  execFileSync("tar", ["-xzf", join(project, tarball), "-C", join(modules, "handrig"), "--strip-components=1"]);
  for (const dep of ["vite", "typescript", "three", "@pixiv", "@mediapipe/tasks-vision"]) link(join(WWW, "node_modules", dep), join(modules, dep));
  // three's types, as a TypeScript user installs them (tests/node's copy, same three version).
  link(join(REPO, "tests", "node", "node_modules", "@types"), join(modules, "@types"));
  writeFileSync(join(project, "package.json"), JSON.stringify({ name: "readme-app", private: true, type: "module" }));
  writeFileSync(join(project, "tsconfig.json"), JSON.stringify(TSCONFIG, null, 2));
  writeFileSync(join(project, "index.html"), INDEX_HTML);
  mkdirSync(join(project, "src"));
  writeFileSync(join(project, "src", "main.ts"), mainJs);
  writeFileSync(join(project, "src", "options.ts"), OPTIONS_TS);
  mkdirSync(join(project, "stand-ins"));
  writeFileSync(join(project, "stand-ins", "tasks-vision.js"), TASKS_VISION_STAND_IN);
  writeFileSync(join(project, "stand-ins", "three-vrm.js"), ADAPTER_PROBE.replace("./options.ts", "../src/options.ts"));
  mkdirSync(join(project, "public"));
  cpSync(join(SHARED, "avatars", "debug-robot.vrm"), join(project, "public", "avatar.vrm"));
  cpSync(join(SHARED, "data", "asl", "again.json"), join(project, "public", "again.json"));
  env = await launch({ args: ["--use-fake-device-for-media-stream", "--use-fake-ui-for-media-stream"] });
});

after(async () => {
  if (server) await new Promise((r) => server.httpServer.close(r));
  await env?.close();
  if (project) rmSync(project, { recursive: true, force: true });
});

test("the README's quick start in a clean Vite + TypeScript (strict, exactOptionalPropertyTypes) app: type-checks, builds, and the avatar's arms move with the hands", async () => {
  try {
    execFileSync(join(WWW, "node_modules", ".bin", "tsc"), ["--noEmit", "-p", join(project, "tsconfig.json")], { encoding: "utf8", cwd: project });
  } catch (e) {
    assert.fail(`tsc --noEmit failed on the README's code:\n${e.stdout}${e.stderr}`);
  }
  await build({
    root: project,
    logLevel: "warn",
    resolve: {
      alias: {
        "@mediapipe/tasks-vision": join(project, "stand-ins", "tasks-vision.js"),
        "handrig/three-vrm": join(project, "stand-ins", "three-vrm.js"),
      },
    },
    build: { outDir: join(project, "dist"), emptyOutDir: true, target: "es2022" },
  });
  server = await preview({ root: project, logLevel: "warn", build: { outDir: join(project, "dist") }, preview: { port: 0, host: "127.0.0.1" } });
  const page = await env.context.newPage();
  const errors = [];
  page.on("pageerror", (e) => errors.push(`pageerror: ${e.message}`));
  page.on("console", (m) => m.type() === "error" && errors.push(`console.error: ${m.text()}`));
  await page.goto(server.resolvedUrls.local[0]);
  await page
    .waitForFunction(() => (globalThis.__quickstart?.applied ?? 0) >= 130, null, { timeout: 120_000 })
    .catch((e) => assert.fail(`${e.message}\nerrors: ${errors.join("\n")}`));
  const png = await page.screenshot({ path: shot("vite-readme.png") });
  const state = await page.evaluate(() => {
    const qs = globalThis.__quickstart;
    return { unsetTaken: qs.unsetTaken, idleFromDown: qs.idleFromDown, armFromTPose: qs.armFromTPose, track: qs.track };
  });
  const stats = await pixelStats(page, png, { x: 0, y: 0, w: 1280, h: 800 });
  await page.close();
  assert.deepEqual(errors, []);
  assert.equal(state.unsetTaken, true);
  assert.ok(stats.nonBg > 100, `the avatar is drawn: ${JSON.stringify(stats)}`);
  assert.ok(state.armFromTPose > 30, `an arm ${state.armFromTPose.toFixed(1)} degrees from the T-pose`);
  assert.ok(state.idleFromDown < 30, `an idle upper arm ${state.idleFromDown.toFixed(1)} degrees from hanging down`);
  for (const side of ["left", "right"]) {
    const ys = state.track[side].map((s) => s.hand[1]);
    assert.ok(ys.length > 40, `${side}: the arm placed from its hand on ${ys.length} frames`);
    assert.ok(Math.max(...ys) - Math.min(...ys) > 0.15, `${side}: the hand rose and fell ${(Math.max(...ys) - Math.min(...ys)).toFixed(2)} m`);
  }
});
