// The README's "Quick start: Node" runs as written: its two blocks are saved as main.mjs and
// main.cjs in a folder inside the consumer project (so "handrig" resolves to the installed
// package) next to avatar.vrm (the shared robot) and right-hand-video-mediapipe.json (the shared
// recording), and run with `node`, unchanged. A preloaded probe (`--import`) wraps
// HandRig.prototype.solve to count the frames solved and the right hands tracked, and prints
// that at exit: the README code itself is not touched.

import assert from "node:assert/strict";
import { spawnSync } from "node:child_process";
import fs from "node:fs";
import path from "node:path";
import { after, before, describe, it } from "node:test";

import { codeBlocks, readme } from "./readme-blocks.mjs";
import { avatars, recordingPath } from "./support.mjs";

const PROBE = `
import { HandRig } from "handrig";
const solve = HandRig.prototype.solve;
const seen = { solves: 0, rightHands: 0, rightIndex: null };
HandRig.prototype.solve = function (...args) {
  const result = solve.apply(this, args);
  seen.solves++;
  if (result.hands.right && result.hands.right.status === "solved") seen.rightHands++;
  seen.rightIndex = result.bones.rightIndexProximal;
  return result;
};
process.on("exit", () => console.log("PROBE " + JSON.stringify(seen)));
`;

let dir;
let blocks;

before(() => {
  blocks = codeBlocks(readme, "## Quick start: Node");
  dir = fs.mkdtempSync(path.join(process.cwd(), "quickstart-"));
  fs.copyFileSync(avatars.robot, path.join(dir, "avatar.vrm"));
  fs.copyFileSync(recordingPath, path.join(dir, "right-hand-video-mediapipe.json"));
  fs.writeFileSync(path.join(dir, "probe.mjs"), PROBE);
});

after(() => fs.rmSync(dir, { recursive: true, force: true }));

/** Runs `file` (written from `code`) with node in the quick-start folder. */
function run(file, code) {
  fs.writeFileSync(path.join(dir, file), code);
  const res = spawnSync(process.execPath, ["--import", "./probe.mjs", file], { cwd: dir, encoding: "utf8" });
  assert.equal(res.status, 0, `${file} exited ${res.status}:\n${res.stderr}`);
  assert.equal(res.stderr, "", `${file} wrote to stderr`);
  const line = res.stdout.split("\n").find((l) => l.startsWith("PROBE "));
  assert.ok(line, `${file}: the probe did not report:\n${res.stdout}`);
  return { probe: JSON.parse(line.slice(6)), stdout: res.stdout };
}

describe("README quick start (Node)", () => {
  it("has an ES module block and a CommonJS block", () => {
    assert.equal(blocks.length, 2);
    assert.match(blocks[0], /^\/\/ main\.mjs/);
    assert.match(blocks[1], /^\/\/ main\.cjs/);
  });

  it("main.mjs runs as written: every frame of the recording solved, the right hand tracked", () => {
    const { probe } = run("main.mjs", blocks[0]);
    const frames = JSON.parse(fs.readFileSync(recordingPath, "utf8")).length;
    assert.equal(probe.solves, frames);
    assert.ok(probe.rightHands >= frames - 10, `${probe.rightHands} of ${frames} frames with a solved right hand`);
  });

  it("main.cjs runs as written and prints the right index proximal rotation", () => {
    const { probe, stdout } = run("main.cjs", blocks[1]);
    assert.equal(probe.solves, 1);
    const printed = stdout.slice(0, stdout.indexOf("PROBE "));
    assert.match(printed, /^\[[-\d.e,\s]+\]\s*$/, `printed ${printed}`);
    const q = printed.match(/-?[\d.]+(e-?\d+)?/g).map(Number);
    assert.equal(q.length, 4);
    assert.ok(Math.abs(Math.hypot(...q) - 1) < 1e-5, printed);
    assert.deepEqual(q, probe.rightIndex);
  });
});
