// handrig/compat (issue 30): the package's API with the WebAssembly inlined. In a copy of the
// installed package with every .wasm file deleted and `fetch` undefined, its ES module and its
// CommonJS build each `await init()`, load a .vrm and solve a real ASL clip as handrig does.

import assert from "node:assert/strict";
import { spawnSync } from "node:child_process";
import fs from "node:fs";
import { createRequire } from "node:module";
import os from "node:os";
import path from "node:path";
import { after, describe, it } from "node:test";
import { fileURLToPath } from "node:url";

import { HandRig, LAYOUT } from "handrig";
import * as compat from "handrig/compat";
import { codeBlocks, docPage } from "./readme-blocks.mjs";
import { CHILD_NODE_FLAGS, CHILD_TIMEOUT_MS, avatars, shared } from "./support.mjs";

const require = createRequire(import.meta.url);
const installed = path.dirname(require.resolve("handrig/package.json"));
const child = path.join(path.dirname(fileURLToPath(import.meta.url)), "compat.child.mjs");
const clip = path.join(shared, "data", "asl", "thanks.json");

// A copy of the package without its .wasm files (the installed one is shared by the other tests).
const copy = fs.mkdtempSync(path.join(os.tmpdir(), "handrig-compat-"));
fs.cpSync(installed, copy, { recursive: true });
let deleted = 0;
for (const f of fs.readdirSync(path.join(copy, "wasm"))) {
  if (f.endsWith(".wasm")) fs.rmSync(path.join(copy, "wasm", f)), deleted++;
}
after(() => fs.rmSync(copy, { recursive: true, force: true }));

describe("handrig/compat", () => {
  it("exports what handrig exports, less wasmFile (nothing to fetch)", () => {
    const main = Object.keys(require("handrig")).sort();
    assert.deepEqual(Object.keys(compat).filter((k) => k !== "default").sort(), main.filter((k) => k !== "wasmFile"));
    assert.equal(compat.default, compat.init);
  });

  for (const flavor of ["esm", "cjs"]) {
    it(`${flavor}: with the .wasm files deleted and fetch undefined, init() and a real clip solve as handrig does`, () => {
      assert.equal(deleted, 2);
      const res = spawnSync(process.execPath, [...CHILD_NODE_FLAGS, child, copy, flavor, avatars.robot, clip], { encoding: "utf8", maxBuffer: 64 * 1024 * 1024, timeout: CHILD_TIMEOUT_MS });
      assert.equal(res.status, 0, res.stderr);
      const got = JSON.parse(res.stdout);
      assert.match(got.before, /before the WebAssembly module was initialized/);
      assert.equal(got.build, "baseline", "compat inlines the baseline build");
      assert.match(got.rejected, /^frame\.hands\[0\]\.worldLandmarks: these look like image-normalized/);
      // The same frames through handrig (SIMD in Node: the builds differ by float rounding).
      const rig = HandRig.fromVrm(new Uint8Array(fs.readFileSync(avatars.robot)));
      const frames = JSON.parse(fs.readFileSync(clip, "utf8")).frames;
      assert.equal(got.bones.length, frames.length);
      let largest = 0;
      let moved = 0;
      frames.forEach((f, i) => {
        const want = rig.solve(f);
        LAYOUT.bones.forEach((b, k) => {
          const w = want.bones[b];
          const g = got.bones[i][k];
          assert.equal(g === null, w === undefined, `frame ${i} ${b}`);
          if (w) for (let c = 0; c < 4; c++) largest = Math.max(largest, Math.abs(w[c] - g[c]));
          if (w && Math.abs(w[3]) < 0.99) moved++;
        });
      });
      rig.free();
      assert.ok(largest < 1e-4, `largest quaternion component difference ${largest}`);
      assert.ok(moved > frames.length, `${moved} bone rotations away from rest`);
    });
  }

  it("docs/guide/workers.md's block runs as written (fetch undefined), and drives the hand", () => {
    const [block] = codeBlocks(docPage("guide/workers.md"), "## `handrig/compat`: the WebAssembly inlined");
    assert.match(block, /from "handrig\/compat"/);
    const file = path.join(path.dirname(child), "compat-block.generated.mjs");
    const frame = JSON.parse(fs.readFileSync(clip, "utf8")).frames[40];
    fs.writeFileSync(
      file,
      [
        'import fs from "node:fs";',
        "globalThis.fetch = undefined;",
        `const vrmBytes = new Uint8Array(fs.readFileSync(${JSON.stringify(avatars.robot)}));`,
        `const frame = ${JSON.stringify(frame)};`,
        block,
        'process.stdout.write(JSON.stringify({ status: result.hands.right?.status ?? result.hands.left?.status, index: result.bones.rightIndexProximal ?? result.bones.leftIndexProximal }));',
      ].join("\n"),
    );
    const res = spawnSync(process.execPath, [...CHILD_NODE_FLAGS, file], { encoding: "utf8", timeout: CHILD_TIMEOUT_MS });
    fs.rmSync(file);
    assert.equal(res.status, 0, res.stderr);
    const got = JSON.parse(res.stdout);
    assert.equal(got.status, "solved");
    assert.ok(Math.abs(got.index[3]) < 0.999, `a finger bent: ${got.index}`);
  });

  it("in this process too, where the .wasm files exist: init() and initSync() take no argument", async () => {
    assert.throws(() => compat.HandRig.fromVrm(new Uint8Array(8)), /before the WebAssembly module was initialized/);
    compat.initSync();
    await compat.init();
    assert.equal(compat.wasmBuild(), "baseline");
    const rig = compat.HandRig.fromVrm(new Uint8Array(fs.readFileSync(avatars.robot)));
    assert.equal(rig.drivenBones().length, HandRig.fromVrm(new Uint8Array(fs.readFileSync(avatars.robot))).drivenBones().length);
    rig.free();
  });
});
