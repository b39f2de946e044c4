// Run by browser-entry.test.mjs as `node --conditions=browser`: "handrig" resolves to the
// browser/bundler entry (index.js, wasm-bindgen --target web), which needs `await init()`.
// Prints one JSON line for the parent test to check.
import fs from "node:fs";
import { createRequire } from "node:module";

import init, { HandRig, initSync, version } from "handrig";

const require = createRequire(import.meta.url);
const out = { version };
const shared = process.env.HANDRIG_SHARED;
const robot = fs.readFileSync(`${shared}/avatars/debug-robot.vrm`);
const mode = process.argv[2];

try {
  HandRig.fromVrm(robot);
  out.beforeInit = "no error";
} catch (e) {
  out.beforeInit = { isError: e instanceof Error, message: e.message };
}

// The .wasm as a bundler would get it: the package's "./handrig_bg.wasm" export.
const wasmPath = require.resolve("handrig/handrig_bg.wasm");
const wasmBytes = fs.readFileSync(wasmPath);
if (mode === "sync") {
  initSync(wasmBytes);
} else {
  // Node's fetch cannot read file: URLs, so hand init the bytes (browsers fetch the default URL).
  await init(wasmBytes);
  await init(); // a second call is a no-op, even without an argument
}

const rig = HandRig.fromVrm(robot);
const frame = JSON.parse(fs.readFileSync(`${shared}/data/hands/right-hand-video-mediapipe.json`, "utf8"))[0];
const result = rig.solve(frame);
out.boneNames = rig.boneNames().length;
out.solved = Object.keys(result.bones);
out.entry = import.meta.resolve ? import.meta.resolve("handrig") : null;
rig.free();
console.log(JSON.stringify(out));
