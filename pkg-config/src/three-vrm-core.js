// handrig <-> three-vrm adapter (`handrig/three-vrm`). The one place that knows three-vrm.
// It reads and writes three-vrm's *normalized* humanoid (identity rest rotations, positions =
// offsets from the nearest existing humanoid ancestor), which is the frame handrig solves in.
// It imports nothing (build.mjs defines `LAYOUT`, the flat layout, before this file): the VRM object is used through the few members named below, so the
// package has no dependency on three or @pixiv/three-vrm. build.mjs wraps this file as an ES
// module or CommonJS, like handrig-core.js.
//
// VRM 0.x: three-vrm keeps a 0.x model's normalized bones in the model's own frame (facing
// -Z). handrig is told the version (restPose.vrmVersion) and returns rotations in that same
// frame, so they are written as they are: do NOT negate x and z here or in user code (that
// negation is for poses authored for VRM 1.0's +Z facing, which handrig already handles).

/* global LAYOUT */
/* exported restPoseFromVRM, applyToVRM */

function humanoidOf(vrm, fn) {
  const humanoid = vrm !== null && typeof vrm === "object" ? vrm.humanoid : undefined;
  if (
    humanoid === null ||
    typeof humanoid !== "object" ||
    typeof humanoid.getNormalizedBoneNode !== "function"
  ) {
    throw new TypeError(
      `${fn}: vrm.humanoid must be a three-vrm VRMHumanoid (pass gltf.userData.vrm from VRMLoaderPlugin)`,
    );
  }
  return humanoid;
}

/**
 * The rest pose handrig needs, read from a three-vrm VRM: `{ bones: { [name]: [x, y, z] },
 * vrmVersion }`, world positions (meters, the model's own frame) of the normalized bones at
 * rest. Built from `humanoid.normalizedRestPose`, so the current pose of the avatar, its scene
 * position and `VRMUtils.rotateVRM0` do not change the answer.
 */
// eslint-disable-next-line no-unused-vars
function restPoseFromVRM(vrm) {
  const fn = "restPoseFromVRM";
  const humanoid = humanoidOf(vrm, fn);
  const metaVersion = vrm.meta ? vrm.meta.metaVersion : undefined;
  if (metaVersion !== "0" && metaVersion !== "1") {
    throw new TypeError(`${fn}: vrm.meta.metaVersion must be "0" or "1", got ${JSON.stringify(metaVersion)}`);
  }
  const rest = humanoid.normalizedRestPose;
  if (rest === null || typeof rest !== "object") {
    throw new TypeError(`${fn}: vrm.humanoid.normalizedRestPose is missing (three-vrm >= 1.0 is required)`);
  }
  // Normalized bone node -> bone name, to follow the normalized hierarchy (each node's parent
  // is the nearest existing humanoid ancestor's node, or the rig root for hips).
  const nameOfNode = new Map();
  for (const name of Object.keys(rest)) {
    const node = humanoid.getNormalizedBoneNode(name);
    if (node) nameOfNode.set(node, name);
  }
  const bones = {};
  const visiting = new Set();
  const worldOf = (name) => {
    const known = bones[name];
    if (known) return known;
    if (visiting.has(name)) {
      throw new Error(`${fn}: the normalized bone hierarchy has a cycle at "${name}"`);
    }
    visiting.add(name);
    const p = rest[name].position || [0, 0, 0];
    const parentName = nameOfNode.get(humanoid.getNormalizedBoneNode(name).parent);
    const base = parentName === undefined ? [0, 0, 0] : worldOf(parentName);
    const world = [base[0] + p[0], base[1] + p[1], base[2] + p[2]];
    for (let i = 0; i < 3; i++) {
      if (!Number.isFinite(world[i])) {
        throw new Error(`${fn}: vrm.humanoid.normalizedRestPose.${name}.position is not finite`);
      }
    }
    visiting.delete(name);
    bones[name] = world;
    return world;
  };
  for (const name of nameOfNode.values()) worldOf(name);
  return { bones, vrmVersion: metaVersion };
}

// Per humanoid: bone name -> normalized bone node (null when the avatar lacks it), so a frame
// does not look every bone up again. Keyed weakly: a disposed VRM takes its entry with it.
const nodeCache = new WeakMap();

function nodesOf(humanoid) {
  let nodes = nodeCache.get(humanoid);
  if (nodes === undefined) {
    nodes = new Map();
    for (const name of LAYOUT.bones) nodes.set(name, humanoid.getNormalizedBoneNode(name) || null);
    nodeCache.set(humanoid, nodes);
  }
  return nodes;
}

/**
 * Writes a solve's rotations to the VRM's normalized bones
 * (`getNormalizedBoneNode(name).quaternion`): `result` is a `HandRig.solve()` result (its
 * `bones`, which hold every bone the rig drives, every frame) or a flat output array
 * (`rig.output`, or the Float32Array given to `solveInto`: every bone whose flag is not 0).
 * Bones the avatar lacks are skipped. Returns how many bones were written. Call
 * `vrm.update(delta)` afterwards as usual: three-vrm copies normalized rotations to the model's
 * bones there. Allocates nothing per frame (the bone nodes are looked up once per VRM).
 */
// eslint-disable-next-line no-unused-vars
function applyToVRM(vrm, result) {
  const fn = "applyToVRM";
  const humanoid = humanoidOf(vrm, fn);
  const nodes = nodesOf(humanoid);
  let written = 0;
  if (result instanceof Float32Array) {
    const O = LAYOUT.output;
    if (result.length !== O.length) {
      throw new TypeError(`${fn}: a flat output must have ${O.length} numbers (LAYOUT.output.length), got ${result.length}`);
    }
    const bones = LAYOUT.bones;
    for (let i = 0; i < bones.length; i++) {
      if (result[O.boneFlags + i] === 0) continue;
      const node = nodes.get(bones[i]);
      if (!node) continue;
      const at = O.boneRotations + 4 * i;
      node.quaternion.set(result[at], result[at + 1], result[at + 2], result[at + 3]);
      written++;
    }
    return written;
  }
  const bones = result !== null && typeof result === "object" ? result.bones : undefined;
  if (bones === null || typeof bones !== "object") {
    throw new TypeError(`${fn}: result.bones must be the bones of a HandRig.solve() result (or pass a flat output Float32Array)`);
  }
  // for..in over the result's own plain object: no per-frame allocation.
  for (const name in bones) {
    const q = bones[name];
    const node = nodes.get(name);
    if (!node || !q) continue;
    node.quaternion.set(q[0], q[1], q[2], q[3]);
    written++;
  }
  return written;
}
