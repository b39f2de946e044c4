// The package's two WebAssembly builds (pkg-config/build.mjs): Node, which has WebAssembly
// SIMD, loads the simd128 build; HANDRIG_WASM=baseline loads the fallback, and both solve the
// real ASL clips alike (the SIMD build only reorders floating-point operations).

import assert from "node:assert/strict";
import { spawnSync } from "node:child_process";
import path from "node:path";
import { describe, it } from "node:test";
import { fileURLToPath } from "node:url";

import { wasmBuild, LAYOUT } from "handrig";
import { CHILD_NODE_FLAGS, CHILD_TIMEOUT_MS } from "./support.mjs";

const child = path.join(path.dirname(fileURLToPath(import.meta.url)), "wasm-builds.child.cjs");

function run(build) {
  const res = spawnSync(process.execPath, [...CHILD_NODE_FLAGS, child], {
    encoding: "utf8",
    timeout: CHILD_TIMEOUT_MS,
    env: { ...process.env, HANDRIG_WASM: build },
    maxBuffer: 256 * 1024 * 1024,
  });
  return res;
}

describe("WebAssembly builds", () => {
  it("Node loads the SIMD build by default", () => {
    assert.equal(wasmBuild(), "simd128");
  });

  it("the baseline and SIMD builds solve the ASL clips alike", () => {
    const got = {};
    for (const build of ["baseline", "simd128"]) {
      const res = run(build);
      assert.equal(res.status, 0, res.stderr);
      got[build] = JSON.parse(res.stdout);
      assert.equal(got[build].build, build);
    }
    const [a, b] = [got.baseline.outputs, got.simd128.outputs];
    assert.equal(a.length, 250);
    assert.equal(b.length, a.length);
    // Local rotations and world positions of every bone, frame by frame (measured: 6e-6 and
    // 2e-6 m apart at most).
    const { boneRotations, bonePositions } = LAYOUT.output;
    const n = LAYOUT.bones.length;
    let rot = 0;
    let pos = 0;
    for (let f = 0; f < a.length; f++) {
      for (let k = boneRotations; k < boneRotations + 4 * n; k++) rot = Math.max(rot, Math.abs(a[f][k] - b[f][k]));
      for (let k = bonePositions; k < bonePositions + 3 * n; k++) pos = Math.max(pos, Math.abs(a[f][k] - b[f][k]));
    }
    assert.ok(rot < 1e-4, `largest quaternion component difference ${rot}`);
    assert.ok(pos < 1e-4, `largest position difference ${pos} m`);
  });

  it("HANDRIG_WASM must name a build", () => {
    const res = run("sse4");
    assert.notEqual(res.status, 0);
    assert.match(res.stderr, /HANDRIG_WASM must be "baseline" or "simd128", got "sse4"/);
  });
});

describe("wasmFile()", () => {
  it("names the file the process loaded, before and without init", async () => {
    const { wasmFile } = await import("handrig");
    assert.equal(wasmFile(), "handrig_simd_bg.wasm");
    const res = spawnSync(process.execPath, [...CHILD_NODE_FLAGS, "-e", 'console.log(require("handrig").wasmFile())'], {
      encoding: "utf8",
      timeout: CHILD_TIMEOUT_MS,
      env: { ...process.env, HANDRIG_WASM: "baseline" },
    });
    assert.equal(res.status, 0, res.stderr);
    assert.equal(res.stdout.trim(), "handrig_bg.wasm");
  });
});
