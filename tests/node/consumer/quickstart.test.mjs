// The README's "Quick start: Node" runs as written (and its "Quick start: HolisticLandmarker",
// below): its two blocks are saved as main.mjs and
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
import { CHILD_NODE_FLAGS, CHILD_TIMEOUT_MS, avatars, recordingPath } from "./support.mjs";

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
  const res = spawnSync(process.execPath, [...CHILD_NODE_FLAGS, "--import", "./probe.mjs", file], { cwd: dir, encoding: "utf8", timeout: CHILD_TIMEOUT_MS });
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

// The README's "Quick start: HolisticLandmarker" block (the tracker and the loop of main.js) runs
// as written in Node, on the shared `thanks` sign-language clip: the names it takes from main.js
// (vision, video, rig, vrm, renderer, scene, camera, lastMs, applyToVRM) are defined before it,
// HolisticLandmarker is a stand-in whose detectForVideo returns the clip's frames as tasks-vision
// HolisticLandmarkerResults (hands by the subject's side), and the rig is the quick start's
// (`mirror: true`, the robot).
const HOLISTIC_HARNESS = (clipPath, robotPath) => `
import { readFileSync } from "node:fs";
import { HandRig } from "handrig";
const clip = JSON.parse(readFileSync(${JSON.stringify(clipPath)}, "utf8"));
const pt = ([x, y, z, visibility]) => (visibility === undefined ? { x, y, z } : { x, y, z, visibility });
let next = 0;
class HolisticLandmarker {
  static async createFromOptions(fileset, options) {
    if (options.runningMode !== "VIDEO" || !/holistic_landmarker\\.task$/.test(options.baseOptions.modelAssetPath)) {
      throw new Error("unexpected options " + JSON.stringify(options));
    }
    return new HolisticLandmarker();
  }
  detectForVideo(video, timestamp) {
    if (!(timestamp > (this.last ?? -Infinity))) throw new Error("detectForVideo: timestamps must increase");
    this.last = timestamp;
    const f = clip.frames[next++];
    // Holistic names hands by the subject's side: the hand MediaPipe Hands labels "Left" is its right.
    const side = (label) => f.hands.filter((h) => h.handedness === label).slice(0, 1);
    return {
      faceLandmarks: [], faceBlendshapes: [], poseSegmentationMasks: [],
      poseLandmarks: [f.pose.landmarks.map(pt)],
      poseWorldLandmarks: [f.pose.worldLandmarks.map(pt)],
      leftHandLandmarks: side("Right").map((h) => h.landmarks.map(pt)),
      leftHandWorldLandmarks: side("Right").map((h) => h.worldLandmarks.map(pt)),
      rightHandLandmarks: side("Left").map((h) => h.landmarks.map(pt)),
      rightHandWorldLandmarks: side("Left").map((h) => h.worldLandmarks.map(pt)),
    };
  }
}
const vision = {};
const video = {};
const scene = {};
const camera = {};
const vrm = { update() {} };
let lastMs = 0;
let t = 0;
const performance = { now: () => (t += 1000 / 30) };
const renderer = { setAnimationLoop(loop) { for (const _ of clip.frames) loop(); }, render() {} };
const rig = HandRig.fromVrm(readFileSync(${JSON.stringify(robotPath)}), { mirror: true });
const seen = { frames: clip.frames.length, applied: 0, handsInClip: 0, handsSolved: 0, armRaised: 0 };
function applyToVRM(vrm, result) {
  seen.applied++;
  for (const side of ["left", "right"]) if (result.hands[side]?.status === "solved") seen.handsSolved++;
  // An arm reaching a wrist target: the pose drives the arms (an arm without one rests down).
  if (result.ikTargets.left || result.ikTargets.right) seen.armRaised++;
  return 0;
}
for (const f of clip.frames) seen.handsInClip += Math.min(1, f.hands.filter((h) => h.handedness === "Left").length) + Math.min(1, f.hands.filter((h) => h.handedness === "Right").length);
`;

describe("README quick start (HolisticLandmarker)", () => {
  it("has one block, and it runs on a recorded clip: every frame applied, hands solved, arms moved", async () => {
    const { shared } = await import("./support.mjs");
    const holistic = codeBlocks(readme, "## Quick start: HolisticLandmarker (arms and hands)");
    assert.equal(holistic.length, 1);
    const clipPath = path.join(shared, "data", "asl", "thanks.json");
    const code = `${HOLISTIC_HARNESS(clipPath, avatars.robot)}\n${holistic[0]}\nconsole.log("SEEN " + JSON.stringify(seen));\n`;
    fs.writeFileSync(path.join(dir, "holistic.mjs"), code);
    const res = spawnSync(process.execPath, [...CHILD_NODE_FLAGS, "holistic.mjs"], { cwd: dir, encoding: "utf8", timeout: CHILD_TIMEOUT_MS });
    assert.equal(res.status, 0, `holistic.mjs exited ${res.status}:\n${res.stderr}`);
    const line = res.stdout.split("\n").find((l) => l.startsWith("SEEN "));
    assert.ok(line, res.stdout);
    const seen = JSON.parse(line.slice(5));
    assert.equal(seen.applied, seen.frames);
    assert.ok(seen.handsSolved >= 0.8 * seen.handsInClip, JSON.stringify(seen));
    assert.ok(seen.armRaised >= 0.5 * seen.frames, JSON.stringify(seen));
  });
});
