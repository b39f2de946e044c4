// Run by wasm-builds.test.mjs with HANDRIG_WASM set: solves the four ASL clips through the flat
// path and prints { build, outputs } (every frame's output view, as arrays) as one JSON line.
"use strict";
const fs = require("node:fs");
const { HandRig, wasmBuild } = require("handrig");

const shared = process.env.HANDRIG_SHARED;
const robot = fs.readFileSync(`${shared}/avatars/debug-robot.vrm`);
const frames = ["eat", "thanks", "brother", "sister"].flatMap(
  (n) => JSON.parse(fs.readFileSync(`${shared}/data/asl/${n}.json`, "utf8")).frames,
);
const rig = HandRig.fromVrm(robot);
const outputs = frames.map((f, i) => {
  rig.solve({ ...f, timeMs: i * 33.3 });
  return Array.from(rig.output);
});
console.log(JSON.stringify({ build: wasmBuild(), outputs }));
