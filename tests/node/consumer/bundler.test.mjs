// A bundler's view of the package: esbuild bundles an app for the browser, resolving
// "handrig" and "handrig/three-vrm" through the package's browser/import exports (never the
// Node CommonJS build), and the bundle works once init() is given the .wasm.

import assert from "node:assert/strict";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { describe, it } from "node:test";
import { pathToFileURL } from "node:url";
import { createRequire } from "node:module";

import { avatars, readBytes, readRecording } from "./support.mjs";

const require = createRequire(import.meta.url);

const app = `
import init, { HandRig } from "handrig";
import { applyToVRM, restPoseFromVRM } from "handrig/three-vrm";

export async function run(wasmBytes, vrmBytes, frame) {
  let early;
  try { HandRig.fromVrm(vrmBytes); } catch (e) { early = e.message; }
  await init(wasmBytes);
  const rig = HandRig.fromVrm(vrmBytes);
  const result = rig.solve(frame);
  rig.free();
  return { early, bones: Object.keys(result.bones), adapter: typeof restPoseFromVRM + typeof applyToVRM };
}
`;

describe("bundling with esbuild (platform browser)", () => {
  it("resolves the browser entry and the bundle runs after init()", async () => {
    const esbuild = await import("esbuild");
    const dir = fs.mkdtempSync(path.join(process.cwd(), ".bundle-"));
    try {
      const entry = path.join(dir, "app.js");
      fs.writeFileSync(entry, app);
      const outfile = path.join(dir, "out.mjs");
      const built = await esbuild.build({
        entryPoints: [entry],
        bundle: true,
        platform: "browser",
        format: "esm",
        outfile,
        metafile: true,
        logLevel: "silent",
      });
      const inputs = Object.keys(built.metafile.inputs).map((f) => f.replace(/\\/g, "/"));
      assert.ok(inputs.some((f) => f.endsWith("node_modules/handrig/index.js")), `inputs: ${inputs}`);
      assert.ok(inputs.some((f) => f.endsWith("node_modules/handrig/wasm/handrig_wasm.js")));
      assert.ok(inputs.some((f) => f.endsWith("node_modules/handrig/three-vrm.js")));
      assert.ok(!inputs.some((f) => f.endsWith(".cjs")), `a CommonJS file was bundled: ${inputs}`);
      // The glue still finds its .wasm next to itself by default (bundlers that copy assets).
      // Both builds, each a literal URL a bundler can follow; the SIMD one where supported.
      const bundle = fs.readFileSync(outfile, "utf8");
      assert.match(bundle, /new URL\("handrig_bg\.wasm", import\.meta\.url\)/);
      assert.match(bundle, /new URL\("handrig_simd_bg\.wasm", import\.meta\.url\)/);

      const { run } = await import(pathToFileURL(outfile).href);
      const wasm = fs.readFileSync(require.resolve("handrig/handrig_bg.wasm"));
      const out = await run(wasm, readBytes(avatars.robot), readRecording()[0]);
      assert.match(out.early, /init\(\)/);
      assert.ok(out.bones.includes("rightHand"), `${out.bones}`);
      assert.equal(out.adapter, "functionfunction");
    } finally {
      fs.rmSync(dir, { recursive: true, force: true });
    }
  });
});
