// Issue 30's acceptance: a Vite + TypeScript (strict) app using handrig/compat and one using
// handrig/worker, built for production (`tsc --noEmit`, `vite build`), served from dist/ by
// `vite preview` and run in Chromium, each solving the shared ASL clip eat.json (pose and
// hands) on the generated woman avatar. The apps are in tests/vite-apps/; the packed package
// (`npm pack` of pkg/) is installed into a temporary copy of them.

import { execFileSync } from "node:child_process";
import { cpSync, mkdirSync, mkdtempSync, readFileSync, rmSync, symlinkSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { build, preview } from "vite";
import { findPackageDir } from "../serve.mjs";
import { REPO, SCREENSHOTS, SHARED, WWW, launch } from "./helpers.mjs";

const APPS = join(WWW, "tests", "vite-apps");
let env;
let project;
const reports = {};
// compat's chunk holds the inlined .wasm (about 800 KiB): over Vite's default 500 KiB warning,
// as expected, so the build's limit is raised to 1 MiB.
const built = {};

/** A temporary project: the apps, the packed handrig installed, vite and typescript linked. */
function makeProject() {
  const pkg = findPackageDir();
  if (!pkg) throw new Error("the handrig package is not built: run `make pkg` first");
  const dir = mkdtempSync(join(tmpdir(), "handrig-vite-"));
  cpSync(APPS, dir, { recursive: true });
  const modules = join(dir, "node_modules");
  mkdirSync(join(modules, "handrig"), { recursive: true });
  const tarball = execFileSync("npm", ["pack", "--silent", "--pack-destination", dir, pkg], { encoding: "utf8" }).trim().split("\n").pop();
  execFileSync("tar", ["-xzf", join(dir, tarball), "-C", join(modules, "handrig"), "--strip-components=1"]);
  for (const dep of ["vite", "typescript"]) symlinkSync(join(WWW, "node_modules", dep), join(modules, dep));
  for (const app of ["compat", "worker"]) {
    mkdirSync(join(dir, app, "public"));
    cpSync(join(REPO, "tests", "fixtures", "avatars", "woman-vrm1.vrm"), join(dir, app, "public", "avatar.vrm"));
    cpSync(join(SHARED, "data", "asl", "eat.json"), join(dir, app, "public", "eat.json"));
  }
  // docs/guide/workers.md's handrig/worker blocks, type-checked (strict) with the worker app.
  const [workerBlock, pageBlock] = docBlocks("## `handrig/worker`: a rig in a module Worker");
  writeFileSync(join(dir, "worker", "docs-rig.worker.ts"), workerBlock);
  writeFileSync(
    join(dir, "worker", "docs-page.ts"),
    `${pageBlock.replace('"./rig.worker.ts"', '"./docs-rig.worker.ts"')}\n` +
      "// What the block leaves to the reader's app:\n" +
      "declare const vrmBytes: Uint8Array;\n" +
      'declare const options: import("handrig").HandRigOptions;\n' +
      "declare const vrm: Parameters<typeof applyToVRM>[0];\n" +
      'declare const handLandmarker: { detectForVideo(video: HTMLVideoElement, timeMs: number): NonNullable<import("handrig").FrameInput["hands"]> };\n' +
      "declare const video: HTMLVideoElement;\n",
  );
  writeFileSync(
    join(dir, "worker", "tsconfig.docs.json"),
    JSON.stringify({ extends: "./tsconfig.json", include: ["docs-*.ts"] }),
  );
  return dir;
}

/** The ```ts blocks of docs/guide/workers.md's section under `heading`. */
function docBlocks(heading) {
  const text = readFileSync(join(REPO, "docs", "guide", "workers.md"), "utf8");
  const start = text.indexOf(`${heading}\n`);
  assert.ok(start >= 0, `docs/guide/workers.md has no "${heading}"`);
  const end = text.indexOf("\n## ", start + heading.length);
  const section = text.slice(start, end < 0 ? undefined : end);
  const blocks = [...section.matchAll(/```ts\n([\s\S]*?)```/g)].map((m) => m[1]);
  assert.equal(blocks.length, 2, "the worker's module and the page");
  return blocks;
}

/** tsc --noEmit (strict), vite build, vite preview, the page in Chromium: its window.__result. */
function typeCheck(config) {
  try {
    execFileSync(join(WWW, "node_modules", ".bin", "tsc"), ["--noEmit", "-p", config], { encoding: "utf8" });
  } catch (e) {
    throw new Error(`tsc --noEmit (strict) failed for ${config}:\n${e.stdout}${e.stderr}`);
  }
}

async function runApp(app) {
  const root = join(project, app);
  typeCheck(join(root, "tsconfig.json"));
  await build({ root, logLevel: "warn", build: { outDir: join(root, "dist"), emptyOutDir: true, chunkSizeWarningLimit: 1024 } });
  built[app] = execFileSync("find", [join(root, "dist"), "-type", "f", "-printf", "%P %s\n"], { encoding: "utf8" }).trim().split("\n");
  const server = await preview({ root, logLevel: "warn", build: { outDir: join(root, "dist") }, preview: { port: 0, host: "127.0.0.1" } });
  const page = await env.context.newPage();
  const errors = [];
  page.on("pageerror", (e) => errors.push(e.message));
  page.on("console", (m) => m.type() === "error" && errors.push(m.text()));
  try {
    await page.goto(server.resolvedUrls.local[0]);
    await page.waitForFunction(() => window.__result, null, { timeout: 30_000 });
    const report = await page.evaluate(() => window.__result);
    await page.locator("canvas").screenshot({ path: join(SCREENSHOTS, `vite-${app}.png`) });
    return { report, errors };
  } finally {
    await page.close();
    await new Promise((r) => server.httpServer.close(r));
  }
}

before(async () => {
  project = makeProject();
  env = await launch();
  for (const app of ["compat", "worker"]) reports[app] = await runApp(app);
});

test("docs/guide/workers.md's handrig/worker blocks type-check (strict) against the package", () => {
  typeCheck(join(project, "worker", "tsconfig.docs.json"));
});

after(async () => {
  await env?.close();
  if (project) rmSync(project, { recursive: true, force: true });
});

const clip = JSON.parse(readFileSync(join(SHARED, "data", "asl", "eat.json"), "utf8"));

/** The watched bones moved: the signing hand's arm and fingers, both upper arms (pose). */
function assertMoved(report) {
  assert.equal(report.error, undefined, report.error);
  assert.equal(report.frames, clip.frames.length);
  const { largest } = report;
  console.log(`# ${report.app}: largest angle from rest (deg) ${JSON.stringify(Object.fromEntries(Object.entries(largest).map(([k, v]) => [k, +v.toFixed(1)])))}`);
  for (const bone of ["rightUpperArm", "rightLowerArm", "leftUpperArm"]) assert.ok(largest[bone] > 20, `${bone} turned ${largest[bone]}°`);
  for (const bone of ["rightIndexProximal", "rightThumbProximal"]) assert.ok(largest[bone] > 5, `${bone} turned ${largest[bone]}°`);
  // Not frozen: the signing arm's angle changes over the clip.
  const k = 1; // rightLowerArm
  const seen = report.angles.map((row) => row[k]).filter((a) => a !== null);
  assert.ok(Math.max(...seen) - Math.min(...seen) > 5, "the right forearm moves during the clip");
}

test("a Vite production build with handrig/compat (no .wasm in dist) solves eat.json in Chromium", () => {
  const { report, errors } = reports.compat;
  assert.deepEqual(errors, []);
  assertMoved(report);
  assert.ok(!built.compat.some((f) => f.includes(".wasm ")), `dist has no .wasm: ${built.compat.join(", ")}`);
});

test("a Vite production build with handrig/worker solves eat.json in a module worker, as the main thread does", () => {
  const { report, errors } = reports.worker;
  assert.deepEqual(errors, []);
  assertMoved(report);
  assert.ok(built.worker.some((f) => f.includes(".wasm ")), `Vite emitted handrig's .wasm for the worker: ${built.worker.join(", ")}`);
  // The worker (SIMD build) and the compat app (baseline, main thread) agree frame by frame, up
  // to the builds' float rounding (as tests/node/consumer/compat.test.mjs allows).
  let worst = 0;
  report.rotations.forEach((row, i) =>
    row.forEach((a, k) => {
      const b = reports.compat.report.rotations[i][k];
      assert.equal(a === null, b === null, `frame ${i} bone ${k}`);
      if (a !== null) for (let c = 0; c < 4; c++) worst = Math.max(worst, Math.abs(a[c] - b[c]));
    }),
  );
  assert.ok(worst < 1e-4, `worker and main thread quaternions differ by ${worst}`);
  const n = clip.frames.length;
  const { paced, burst, after } = report.extra;
  assert.deepEqual(paced, { frames: n, sent: n, solved: n, dropped: 0, failed: 0 });
  // A burst of every frame while busy: the first is sent, the newest waits, the rest are dropped.
  assert.deepEqual(burst.stats, { frames: 2 * n, sent: n + 2, solved: n + 2, dropped: n - 2, failed: 0 });
  assert.deepEqual(burst.times, [clip.frames[0].timeMs, clip.frames[n - 1].timeMs]);
  // A bad frame comes back as an error naming the field; the rig solves the next one.
  assert.equal(after.errors.length, 1);
  assert.match(after.errors[0], /hands/);
  assert.equal(after.solvedAfter, n + 3);
  assert.equal(after.lastTime, report.extra.lastTimeMs);
  console.log(`# worker: ${n} frames paced, burst of ${n}: ${burst.stats.dropped} dropped; largest worker/main quaternion component difference ${worst.toExponential(1)}`);
});
