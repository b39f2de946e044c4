// Run by compat.test.mjs in a child process: handrig/compat from a copy of the package whose
// .wasm files are deleted, with `fetch` undefined. argv: the copy's folder, "esm" or "cjs", the
// avatar file, the ASL clip. Prints { build, bones: [frame][flat rotations], rejected }.
import fs from "node:fs";
import { createRequire } from "node:module";
import path from "node:path";
import { pathToFileURL } from "node:url";

const [dir, flavor, avatar, clip] = process.argv.slice(2);
globalThis.fetch = undefined;
if (typeof fetch !== "undefined") throw new Error("fetch is still defined");
for (const f of fs.readdirSync(path.join(dir, "wasm"))) {
  if (f.endsWith(".wasm")) throw new Error(`${f} is still there`);
}
const api =
  flavor === "cjs"
    ? createRequire(import.meta.url)(path.join(dir, "compat.cjs"))
    : await import(pathToFileURL(path.join(dir, "compat.js")).href);
const { HandRig, LAYOUT, init, wasmBuild } = api;
let before = "";
try {
  HandRig.fromVrm(new Uint8Array(8));
} catch (e) {
  before = e.message;
}
await init();
await init(); // a no-op
const rig = HandRig.fromVrm(new Uint8Array(fs.readFileSync(avatar)));
const frames = JSON.parse(fs.readFileSync(clip, "utf8")).frames;
const bones = [];
for (const f of frames) {
  const r = rig.solve(f, {}); // an object of its own: the rig's own result is updated in place
  bones.push(LAYOUT.bones.map((b) => r.bones[b] ?? null));
}
let rejected = "";
try {
  rig.solve({ timeMs: 1, hands: [{ ...frames[0].hands[0], worldLandmarks: frames[0].hands[0].landmarks }] });
} catch (e) {
  rejected = e.message;
}
rig.free();
process.stdout.write(JSON.stringify({ build: wasmBuild(), before, bones, rejected }));
