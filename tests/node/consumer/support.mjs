// Shared helpers of the consumer tests (run from a temp project that installed the packed
// handrig; see ../run.mjs). Data comes from the shared/ folder (HANDRIG_SHARED).

import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";

export const shared = process.env.HANDRIG_SHARED;
/**
 * How long a test waits for a child process it runs with `spawnSync` (ms): a child that hangs
 * (once seen: `node record.mjs` asleep on a futex for 14 minutes, fine on every rerun) fails
 * its test instead of holding the suite until CI's time runs out. spawnSync blocks the event
 * loop, so node:test's own timeouts cannot fire meanwhile.
 */
export const CHILD_TIMEOUT_MS = 180_000;
/**
 * Node's flags for the children the tests run (users' scripts, tsc; not the `handrig` command,
 * which is tested as a user runs it). Node 20 can hang at exit when a background TurboFan job
 * waits for a garbage collection while the main thread drains the platform's tasks
 * (nodejs/node#54918; the futex above); without concurrent recompilation there is no such job.
 * It must be on the command line: set at run time it only reaches isolates created later.
 */
export const CHILD_NODE_FLAGS = ["--no-concurrent-recompilation"];
export const repo = process.env.HANDRIG_REPO;
if (!shared || !repo) throw new Error("run these tests through tests/node/run.mjs");

export const avatars = {
  robot: path.join(shared, "avatars", "debug-robot.vrm"),
  odd0: path.join(shared, "avatars", "odd-armature-vrm0.vrm"),
};
export const recordingPath = path.join(shared, "data", "hands", "right-hand-video-mediapipe.json");

/** The generated test fixtures (tests/fixtures/*.vrm), sorted; [] when there are none. */
export function fixtureVrms() {
  const dir = path.join(repo, "tests", "fixtures");
  if (!fs.existsSync(dir)) return [];
  return fs
    .readdirSync(dir)
    .filter((f) => f.endsWith(".vrm"))
    .sort()
    .map((f) => path.join(dir, f));
}

/**
 * The generated human avatars (tests/fixtures/avatars: `*.vrm` and `*.glb` made by
 * tools/avatars/generate.mjs from MakeHuman's CC0 body), sorted; `ext` filters by extension.
 */
export function avatarFiles(ext) {
  const dir = path.join(repo, "tests", "fixtures", "avatars");
  if (!fs.existsSync(dir)) return [];
  return fs
    .readdirSync(dir)
    .filter((f) => (ext ? f.endsWith(ext) : /\.(vrm|glb)$/.test(f)))
    .sort()
    .map((f) => path.join(dir, f));
}

export function readBytes(file) {
  return new Uint8Array(fs.readFileSync(file));
}

let recording;
/** The real MediaPipe recording: [{ frame, timeMs, hands: [{ handedness, score, landmarks, worldLandmarks }] }]. */
export function readRecording() {
  recording ??= JSON.parse(fs.readFileSync(recordingPath, "utf8"));
  return recording;
}

/**
 * three-vrm in Node: GLTFLoader + VRMLoaderPlugin on the file's bytes. GLTFLoader decodes
 * textures with DOM image APIs that Node lacks; a plugin hands out empty textures instead
 * (plugins' loadTexture hooks run before the default image path), which leaves the scene graph,
 * and so every bone transform, exactly as in a browser.
 */
export async function loadVRM(file) {
  const THREE = await import("three");
  const { GLTFLoader } = await import("three/examples/jsm/loaders/GLTFLoader.js");
  const { VRMLoaderPlugin } = await import("@pixiv/three-vrm");
  const loader = new GLTFLoader();
  loader.register(() => ({ name: "handrig_test_no_images", loadTexture: async () => new THREE.Texture() }));
  loader.register((parser) => new VRMLoaderPlugin(parser));
  const buf = fs.readFileSync(file);
  const gltf = await loader.parseAsync(buf.buffer.slice(buf.byteOffset, buf.byteOffset + buf.byteLength), "");
  const vrm = gltf.userData.vrm;
  assert.ok(vrm, `${path.basename(file)}: VRMLoaderPlugin found no VRM`);
  return vrm;
}

/** A plain glTF binary through three's GLTFLoader in Node (no VRM plugin). */
export async function loadGltf(file) {
  const { GLTFLoader } = await import("three/examples/jsm/loaders/GLTFLoader.js");
  const buf = fs.readFileSync(file);
  return new GLTFLoader().parseAsync(buf.buffer.slice(buf.byteOffset, buf.byteOffset + buf.byteLength), "");
}

/** World positions of three-vrm's normalized bones from three's own matrices (rest pose). */
export async function threeNormalizedWorldPositions(vrm) {
  const THREE = await import("three");
  vrm.scene.updateMatrixWorld(true);
  const out = {};
  const v = new THREE.Vector3();
  for (const name of Object.keys(vrm.humanoid.normalizedRestPose)) {
    const node = vrm.humanoid.getNormalizedBoneNode(name);
    if (node) out[name] = node.getWorldPosition(v).toArray();
  }
  return out;
}

export function assertFiniteVec(v, n, what) {
  assert.ok(Array.isArray(v) && v.length === n, `${what}: expected ${n} numbers, got ${JSON.stringify(v)}`);
  for (const c of v) assert.ok(Number.isFinite(c), `${what}: not finite: ${JSON.stringify(v)}`);
}

export function assertUnitQuat(q, what) {
  assertFiniteVec(q, 4, what);
  const len = Math.hypot(q[0], q[1], q[2], q[3]);
  assert.ok(Math.abs(len - 1) < 1e-5, `${what}: |q| = ${len}`);
}

/** Checks every number of a solve result: finite positions, unit quaternions. */
export function assertResultWellFormed(result, what) {
  assert.equal(typeof result, "object", what);
  for (const [name, q] of Object.entries(result.bones)) assertUnitQuat(q, `${what} bones.${name}`);
  for (const [name, p] of Object.entries(result.worldPositions)) assertFiniteVec(p, 3, `${what} worldPositions.${name}`);
  for (const [side, t] of Object.entries(result.ikTargets)) {
    assertFiniteVec(t.position, 3, `${what} ikTargets.${side}.position`);
    assertUnitQuat(t.rotation, `${what} ikTargets.${side}.rotation`);
  }
  for (const [side, a] of Object.entries(result.alignment)) {
    for (const k of ["targetDip", "ikWrist", "poseWrist"]) assertFiniteVec(a[k], 3, `${what} alignment.${side}.${k}`);
    assert.ok(a.error === null || Number.isFinite(a.error), `${what} alignment.${side}.error`);
  }
}

/** Rotation angle (radians) of a unit quaternion, q and -q alike. */
export function quatAngle(q) {
  return 2 * Math.acos(Math.min(1, Math.abs(q[3])));
}

/** The hand and finger bones of one avatar side ("left" | "right"). */
export function handBones(side) {
  const fingers = ["Thumb", "Index", "Middle", "Ring", "Little"];
  const joints = { Thumb: ["Metacarpal", "Proximal", "Distal"] };
  const names = [`${side}Hand`];
  for (const f of fingers) {
    for (const j of joints[f] ?? ["Proximal", "Intermediate", "Distal"]) names.push(`${side}${f}${j}`);
  }
  return names;
}

/** Whether unit quaternion `q` is the identity (a bone at rest), q and -q alike. */
export function isIdentity(q, tol = 1e-6) {
  return Math.abs(Math.abs(q[3]) - 1) < tol;
}

/**
 * Solves every frame of the recording, each into an object of its own (`solve(frame, {})`:
 * the rig's own result object is reused by the next call); asserts each is well-formed.
 */
export function solveRecording(rig, { every = 1 } = {}) {
  const frames = readRecording();
  const results = [];
  for (let i = 0; i < frames.length; i += every) {
    const r = rig.solve(frames[i], {});
    assertResultWellFormed(r, `frame ${i}`);
    results.push(r);
  }
  return results;
}

/**
 * The robot's `.vrm` with its glTF JSON edited by `edit(json)`, repacked (the BIN chunk kept):
 * for tests of malformed or hostile files.
 */
export function editedRobot(edit) {
  const glb = fs.readFileSync(avatars.robot);
  const jsonLen = glb.readUInt32LE(12);
  const json = JSON.parse(glb.subarray(20, 20 + jsonLen).toString());
  const bin = glb.subarray(20 + jsonLen);
  edit(json);
  let text = Buffer.from(JSON.stringify(json));
  text = Buffer.concat([text, Buffer.alloc((4 - (text.length % 4)) % 4, 0x20)]);
  const head = Buffer.alloc(20);
  head.write("glTF", 0);
  head.writeUInt32LE(2, 4);
  head.writeUInt32LE(20 + text.length + bin.length, 8);
  head.writeUInt32LE(text.length, 12);
  head.write("JSON", 16);
  return Buffer.concat([head, text, bin]);
}

/** Asserts that `fn` throws an `Error` whose message is `message` (a string: exactly; a RegExp: matching). */
export function throwsWith(fn, message) {
  assert.throws(fn, (e) => {
    assert.ok(e instanceof Error, `threw a non-Error: ${String(e)}`);
    if (message instanceof RegExp) assert.match(e.message, message);
    else assert.equal(e.message, message);
    return true;
  });
}

/** A recorded `[x, y, z, visibility?]` as a MediaPipe landmark object. */
export const landmark = ([x, y, z, visibility]) => (visibility === undefined ? { x, y, z } : { x, y, z, visibility });

/**
 * A tasks-vision HolisticLandmarkerResult of a shared ASL frame: Holistic names hands by the
 * subject's side, so its left hand is the one Hands labelled "Right" (the first of each label).
 */
export function holisticResult(f) {
  const side = (label) => f.hands.filter((h) => h.handedness === label).slice(0, 1);
  return {
    faceLandmarks: [],
    faceBlendshapes: [],
    poseLandmarks: [f.pose.landmarks.map(landmark)],
    poseWorldLandmarks: [f.pose.worldLandmarks.map(landmark)],
    poseSegmentationMasks: [],
    leftHandLandmarks: side("Right").map((h) => h.landmarks.map(landmark)),
    leftHandWorldLandmarks: side("Right").map((h) => h.worldLandmarks.map(landmark)),
    rightHandLandmarks: side("Left").map((h) => h.landmarks.map(landmark)),
    rightHandWorldLandmarks: side("Left").map((h) => h.worldLandmarks.map(landmark)),
  };
}
