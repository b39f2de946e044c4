// Issue 49: in every options object an optional field given as `undefined` means absent, as
// TypeScript's optional fields do (`new ChainSolver({ method, joints, constraints: undefined })`
// threw `options.constraints: TypeError: Reflect.get called on non-object`). One table: every
// optional field of every options object (HandRig's options from optionDescriptions(), nested and
// dotted, and their groups; fromGltf's skeleton; ChainSolver's; toVRMA's and toBVH's;
// createRigWorker's), each set to undefined, against the same call with the field left out: the
// same result, or the same error.

import assert from "node:assert/strict";
import path from "node:path";
import { after, describe, it } from "node:test";
import * as handrig from "handrig";
import { createRigWorker, serveRig } from "handrig/worker";
import { avatars, readBytes, readRecording, repo } from "./support.mjs";

const { ChainSolver, HandRig, MotionRecorder } = handrig;
const robot = readBytes(avatars.robot);
const frames = readRecording().slice(100, 104);
const glb = readBytes(path.join(repo, "tests", "fixtures", "avatars", "man-mixamo.glb"));

/** What a call gives: its value as JSON-comparable data, or its error message. */
function outcome(call) {
  try {
    return { ok: call() };
  } catch (e) {
    return { error: String(e?.message ?? e) };
  }
}

/** Outputs of a rig over a few frames (then freed). */
function rigOutputs(rig) {
  const out = frames.map((f) => {
    rig.solve(f);
    return Array.from(rig.output);
  });
  return { bones: rig.boneNames(), boneMap: rig.boneMap(), out, freed: rig.free() };
}

/** Sets `path` (dotted) to `value` in a fresh nested object. */
function nested(pathString, value) {
  const parts = pathString.split(".");
  const root = {};
  let o = root;
  for (const p of parts.slice(0, -1)) o = o[p] = {};
  o[parts.at(-1)] = value;
  return root;
}

// Every HandRig option path and every group of paths (`filter`, `contact.faceAnchors`).
const optionPaths = HandRig.optionDescriptions().map((d) => d.path);
const groups = [...new Set(optionPaths.flatMap((p) => p.split(".").slice(0, -1).map((_, i, a) => a.slice(0, i + 1).join("."))))];

const chainJoints = [
  [0, 0, 0],
  [0, 0.1, 0],
  [0, 0.2, 0],
  [0, 0.3, 0],
];
const chainSolve = (options) => {
  const s = new ChainSolver(options);
  const r = s.solve({ target: [0.15, 0.2, 0.05] }, {});
  s.free();
  return r;
};

const recorder = (() => {
  const rig = HandRig.fromVrm(robot);
  const rec = new MotionRecorder(rig);
  const result = {};
  readRecording()
    .slice(0, 20)
    .forEach((f) => {
      rig.solve(f, result);
      rec.add(f.timeMs, result);
    });
  rig.free();
  return rec;
})();

const gltfMap = HandRig.fromGltf(glb).boneMap();
const lastBone = Object.keys(gltfMap).at(-1);
const { [lastBone]: _dropped, ...gltfMapWithout } = gltfMap;

/**
 * The table: [surface, field, call with the field set to undefined, call with it left out].
 * Calls return comparable data.
 */
const CASES = [
  ...optionPaths.flatMap((p) => [
    ["HandRig.fromVrm", `options.${p} (nested)`, () => rigOutputs(HandRig.fromVrm(robot, nested(p, undefined))), () => rigOutputs(HandRig.fromVrm(robot, {}))],
    ["HandRig.fromVrm", `options["${p}"] (dotted)`, () => rigOutputs(HandRig.fromVrm(robot, { [p]: undefined })), () => rigOutputs(HandRig.fromVrm(robot, {}))],
  ]),
  ...groups.map((g) => ["HandRig.fromVrm", `options.${g}`, () => rigOutputs(HandRig.fromVrm(robot, nested(g, undefined))), () => rigOutputs(HandRig.fromVrm(robot))]),
  // A set field next to an undefined one: the set one still applies.
  ["HandRig.fromVrm", "options.torso beside a set mirror", () => rigOutputs(HandRig.fromVrm(robot, { mirror: true, torso: undefined })), () => rigOutputs(HandRig.fromVrm(robot, { mirror: true }))],
  ["HandRig.fromVrm", "options (the argument)", () => rigOutputs(HandRig.fromVrm(robot, undefined)), () => rigOutputs(HandRig.fromVrm(robot))],
  ["HandRig.fromGltf", "options.skeleton", () => rigOutputs(HandRig.fromGltf(glb, { skeleton: undefined, mirror: true })), () => rigOutputs(HandRig.fromGltf(glb, { mirror: true }))],
  ["HandRig.fromGltf", "options.skeleton.boneMap", () => rigOutputs(HandRig.fromGltf(glb, { skeleton: { boneMap: undefined } })), () => rigOutputs(HandRig.fromGltf(glb, { skeleton: {} }))],
  [
    "HandRig.fromGltf",
    `options.skeleton.boneMap.${lastBone}`,
    () => rigOutputs(HandRig.fromGltf(glb, { skeleton: { boneMap: { ...gltfMapWithout, [lastBone]: undefined } } })),
    () => rigOutputs(HandRig.fromGltf(glb, { skeleton: { boneMap: gltfMapWithout } })),
  ],
  ["ChainSolver", "options.method", () => chainSolve({ joints: chainJoints, method: undefined }), () => chainSolve({ joints: chainJoints })],
  ["ChainSolver", "options.constraints", () => chainSolve({ method: "fabrik", joints: chainJoints, constraints: undefined }), () => chainSolve({ method: "fabrik", joints: chainJoints })],
  ["ChainSolver", "options.constraints (ccd)", () => chainSolve({ method: "ccd", joints: chainJoints, constraints: undefined }), () => chainSolve({ method: "ccd", joints: chainJoints })],
  ["ChainSolver", "options.iterations", () => chainSolve({ joints: chainJoints, iterations: undefined }), () => chainSolve({ joints: chainJoints })],
  ["ChainSolver", "options.tolerance", () => chainSolve({ joints: chainJoints, tolerance: undefined }), () => chainSolve({ joints: chainJoints })],
  ["ChainSolver", "options.maxStepAngle", () => chainSolve({ method: "ccd", joints: chainJoints, maxStepAngle: undefined }), () => chainSolve({ method: "ccd", joints: chainJoints })],
  [
    "ChainSolver",
    "options.constraints[1] (an entry)",
    () => chainSolve({ joints: chainJoints, constraints: [{ type: "cone", maxAngle: 0.3 }, undefined, null] }),
    () => chainSolve({ joints: chainJoints, constraints: [{ type: "cone", maxAngle: 0.3 }, null, null] }),
  ],
  [
    "ChainSolver",
    "options.constraints[0] with an undefined extra field",
    () => chainSolve({ joints: chainJoints, constraints: [{ type: "cone", maxAngle: 0.3, axis: undefined }, null, null] }),
    () => chainSolve({ joints: chainJoints, constraints: [{ type: "cone", maxAngle: 0.3 }, null, null] }),
  ],
  ["MotionRecorder.toVRMA", "options.tolerance", () => Array.from(recorder.toVRMA({ tolerance: undefined })), () => Array.from(recorder.toVRMA({}))],
  ["MotionRecorder.toVRMA", "options (the argument)", () => Array.from(recorder.toVRMA(undefined)), () => Array.from(recorder.toVRMA())],
  ["MotionRecorder.toBVH", "options.unit", () => recorder.toBVH({ unit: undefined, fps: 30 }), () => recorder.toBVH({ fps: 30 })],
  ["MotionRecorder.toBVH", "options.fps", () => recorder.toBVH({ fps: undefined, unit: "m" }), () => recorder.toBVH({ unit: "m" })],
];

describe("undefined means absent (issue 49)", () => {
  it(`covers every HandRig option (${optionPaths.length} paths, ${groups.length} groups)`, () => {
    assert.ok(optionPaths.length > 20 && groups.length > 3);
    assert.ok(lastBone !== undefined && Object.keys(gltfMapWithout).length > 20);
  });

  for (const [surface, field, withUndefined, without] of CASES) {
    it(`${surface}: ${field}`, () => {
      const a = outcome(withUndefined);
      const b = outcome(without);
      assert.equal(a.error, b.error, `${field}: undefined gave ${a.error ?? "a result"}, left out ${b.error ?? "a result"}`);
      assert.deepEqual(a.ok, b.ok);
    });
  }

  it("the reference calls succeed (so the comparisons above compare results, not two errors)", () => {
    for (const [surface, field, , without] of CASES) {
      const r = outcome(without);
      assert.equal(r.error, undefined, `${surface} ${field}`);
    }
  });

  // createRigWorker's fields (async: the worker side answers over a MessageChannel).
  const open = [];
  after(() => open.forEach((p) => p.close()));
  const workerOutput = async (options) => {
    const { port1, port2 } = new MessageChannel();
    serveRig(handrig, port2);
    port1.terminate = () => port1.close();
    open.push(port1, port2);
    const rig = await createRigWorker(port1, options);
    const got = new Promise((resolve) => {
      rig.onResult = ({ output }) => resolve(Array.from(output));
    });
    rig.solve(frames[0]);
    return got;
  };
  for (const field of ["options", "wasm"]) {
    it(`createRigWorker: options.${field}`, async () => {
      const a = await workerOutput({ avatar: robot.slice(), [field]: undefined });
      const b = await workerOutput({ avatar: robot.slice() });
      assert.deepEqual(a, b);
    });
  }
  it("createRigWorker: an undefined field inside options.options", async () => {
    const a = await workerOutput({ avatar: robot.slice(), options: { mirror: true, torso: undefined } });
    const b = await workerOutput({ avatar: robot.slice(), options: { mirror: true } });
    assert.deepEqual(a, b);
  });
});
