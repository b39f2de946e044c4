// handrig <-> three-vrm adapter (`handrig/three-vrm`): the one place that knows three-vrm. It
// reads and writes three-vrm's *normalized* humanoid (identity rest rotations, positions =
// offsets from the nearest existing humanoid ancestor), which is the frame handrig solves in. It
// imports nothing at run time but the layout (inlined by build.mjs): the VRM object is used
// through the few members of `VRMLike`, so the package has no dependency on three or
// @pixiv/three-vrm, and a three-vrm `VRM` fits the types.
//
// VRM 0.x: three-vrm keeps a 0.x model's normalized bones in the model's own frame (facing -Z).
// handrig is told the version (restPose.vrmVersion) and returns rotations in that same frame, so
// they are written as they are: do NOT negate x and z here or in user code (that negation is for
// poses authored for VRM 1.0's +Z facing, which handrig already handles).

/**
 * The `handrig/three-vrm` entry point (TypeDoc: `make docs`).
 * @packageDocumentation
 * @module handrig/three-vrm
 */

import { FACE, bindFace, readFace, type FaceBinding } from "./expression-names.js";
import { LAYOUT } from "./layout.js";
import { skinOfScene } from "./skin.js";

/** A normalized bone node: the parts of three's `Object3D` the adapter uses. */
interface BoneNodeLike {
  parent: unknown;
  quaternion: { set(x: number, y: number, z: number, w: number): unknown };
  /** The hips' position is written while the rig drives the legs (root motion). */
  position?: { set(x: number, y: number, z: number): unknown };
}

/** The parts of three-vrm's `VRM` the adapter uses. */
export interface VRMLike {
  meta: { metaVersion: "0" | "1" | string };
  /** The model's scene (its skinned meshes are the skin `restPoseFromVRM` reads). */
  scene?: { traverse(callback: (object: unknown) => void): void };
  humanoid: {
    /** The model's own bone node of a humanoid bone (three-vrm `getRawBoneNode`). */
    getRawBoneNode?(name: string): unknown;
    /** Local positions of the normalized bones at rest (offsets from the nearest existing humanoid ancestor). */
    normalizedRestPose: { [boneName: string]: { position?: ArrayLike<number> } | undefined };
    getNormalizedBoneNode(name: string): BoneNodeLike | null | undefined;
  };
  /** three-vrm's `VRMExpressionManager` (the face's expressions, issue 50). */
  expressionManager?: {
    expressions: ReadonlyArray<{ expressionName: string }>;
    setValue(name: string, weight: number): void;
  } | null;
  /**
   * three-vrm's `VRMLookAt` (the face's look-at: `yaw`, `pitch` in degrees; `offsetFromHeadBone`,
   * the point between the eyes from the head bone, which `restPoseFromVRM` passes on).
   */
  lookAt?: { yaw: number; pitch: number; offsetFromHeadBone?: { x: number; y: number; z: number } } | null;
}

/** Same shape as handrig's `RestPose` (import that type from "handrig"). */
export interface VRMRestPose {
  /** Rest world positions of the normalized bones, meters, the model's own frame. */
  bones: { [boneName: string]: [number, number, number] };
  /** `vrm.meta.metaVersion`: "0" models face -Z, "1" models face +Z. */
  vrmVersion: "0" | "1";
  /** `vrm.lookAt.offsetFromHeadBone` (absent when the model has no look-at). */
  lookAtOffset?: [number, number, number];
  /** The skin at rest from the model's skinned meshes (absent when it has none). */
  skin?: { positions: Float32Array; bones: Uint8Array; triangles: Uint32Array };
}

/**
 * The skin at rest: every skinned mesh's vertices in bind pose (the model's frame, as the
 * normalized rest pose), each with its dominant humanoid bone (the nearest humanoid ancestor of
 * the bone with the largest weight; vertices with none are left out), and the triangles.
 */
function skinOf(vrm: VRMLike, humanoid: Humanoid): VRMRestPose["skin"] {
  const raw = humanoid.getRawBoneNode;
  if (typeof raw !== "function") return undefined;
  const boneOfNode = new Map<unknown, number>();
  LAYOUT.bones.forEach((name, i) => {
    const node = raw.call(humanoid, name);
    if (node) boneOfNode.set(node, i);
  });
  return skinOfScene(vrm.scene, boneOfNode);
}

type Humanoid = VRMLike["humanoid"];

function humanoidOf(vrm: unknown, fn: string): Humanoid {
  const humanoid: unknown = vrm !== null && typeof vrm === "object" ? (vrm as { humanoid?: unknown }).humanoid : undefined;
  if (
    humanoid === null ||
    typeof humanoid !== "object" ||
    typeof (humanoid as { getNormalizedBoneNode?: unknown }).getNormalizedBoneNode !== "function"
  ) {
    throw new TypeError(`${fn}: vrm.humanoid must be a three-vrm VRMHumanoid (pass gltf.userData.vrm from VRMLoaderPlugin)`);
  }
  return humanoid as Humanoid;
}

/**
 * The rest pose handrig needs, from three-vrm's normalized humanoid (`normalizedRestPose`): world
 * positions of the normalized bones at rest in the model's own frame (meters), plus the VRM
 * version: `{ bones: { [name]: [x, y, z] }, vrmVersion }`. Unaffected by the avatar's current
 * pose, its scene transform and `VRMUtils.rotateVRM0`. Use it as
 * `new HandRig(restPoseFromVRM(vrm), options)`.
 * @throws TypeError when `vrm` is not a three-vrm VRM.
 */
export function restPoseFromVRM(vrm: VRMLike): VRMRestPose {
  const fn = "restPoseFromVRM";
  const humanoid = humanoidOf(vrm, fn);
  const metaVersion = vrm.meta ? vrm.meta.metaVersion : undefined;
  if (metaVersion !== "0" && metaVersion !== "1") {
    throw new TypeError(`${fn}: vrm.meta.metaVersion must be "0" or "1", got ${JSON.stringify(metaVersion)}`);
  }
  const rest = humanoid.normalizedRestPose as VRMLike["humanoid"]["normalizedRestPose"] | null | undefined;
  if (rest === null || typeof rest !== "object") {
    throw new TypeError(`${fn}: vrm.humanoid.normalizedRestPose is missing (three-vrm >= 1.0 is required)`);
  }
  // Normalized bone node -> bone name, to follow the normalized hierarchy (each node's parent is
  // the nearest existing humanoid ancestor's node, or the rig root for hips).
  const nameOfNode = new Map<unknown, string>();
  for (const name of Object.keys(rest)) {
    const node = humanoid.getNormalizedBoneNode(name);
    if (node) nameOfNode.set(node, name);
  }
  const bones: { [name: string]: [number, number, number] } = {};
  const visiting = new Set<string>();
  const worldOf = (name: string): [number, number, number] => {
    const known = bones[name];
    if (known) return known;
    if (visiting.has(name)) {
      throw new Error(`${fn}: the normalized bone hierarchy has a cycle at "${name}"`);
    }
    visiting.add(name);
    const p: ArrayLike<number> = rest[name]!.position || [0, 0, 0];
    const parentName = nameOfNode.get(humanoid.getNormalizedBoneNode(name)!.parent);
    const base = parentName === undefined ? [0, 0, 0] : worldOf(parentName);
    const world: [number, number, number] = [base[0]! + p[0]!, base[1]! + p[1]!, base[2]! + p[2]!];
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
  const out: VRMRestPose = { bones, vrmVersion: metaVersion };
  // The point between the eyes, as HandRig.fromVrm reads it from the file (lookAt's
  // offsetFromHeadBone; VRM 0.x: firstPersonBoneOffset, z negated as three-vrm stores it):
  // self-contact places the face with it on an avatar without eye bones.
  const o = vrm.lookAt?.offsetFromHeadBone;
  if (o && Number.isFinite(o.x) && Number.isFinite(o.y) && Number.isFinite(o.z)) out.lookAtOffset = [o.x, o.y, o.z];
  const skin = skinOf(vrm, humanoid);
  if (skin) out.skin = skin;
  return out;
}

// Per humanoid: bone name -> normalized bone node (null when the avatar lacks it), so a frame
// does not look every bone up again. Keyed weakly: a disposed VRM takes its entry with it.
const nodeCache = new WeakMap<object, Map<string, BoneNodeLike | null>>();

function nodesOf(humanoid: Humanoid): Map<string, BoneNodeLike | null> {
  let nodes = nodeCache.get(humanoid);
  if (nodes === undefined) {
    nodes = new Map();
    for (const name of LAYOUT.bones) nodes.set(name, humanoid.getNormalizedBoneNode(name) || null);
    nodeCache.set(humanoid, nodes);
  }
  return nodes;
}

/**
 * Writes a solve's rotations to `vrm.humanoid.getNormalizedBoneNode(name).quaternion`: `result`
 * is a `HandRig.solve` result (its `bones`: every bone the rig drives, every frame) or a flat
 * output array (`rig.output`, or what `solveInto` filled: every bone whose flag is not 0). Bones
 * the avatar lacks are skipped. While the rig drives the legs (`legs.enabled`), the normalized hips'
 * position is set to its rest position plus the result's `hipsOffset` (root motion). No VRM 0.x sign flip is applied or needed: handrig already
 * returns rotations in the model's own frame. Call `vrm.update(delta)` afterwards as usual
 * (three-vrm copies normalized rotations to the model's bones there). Returns how many bones were
 * written. A result with a face (issue 50) also sets `vrm.expressionManager` (the 52 ARKit
 * expressions on a perfect-sync avatar, else the VRM presets, 1.0 or 0.x names) and
 * `vrm.lookAt.yaw` / `.pitch`; while no face is tracked they are left to the app. Allocates nothing per frame: the bone nodes are looked up once per VRM and cached.
 * @throws TypeError when `vrm` or `result` has the wrong shape.
 */
export function applyToVRM(
  vrm: VRMLike,
  result: { bones: { [boneName: string]: ArrayLike<number> | undefined } } | Float32Array,
): number {
  const fn = "applyToVRM";
  const humanoid = humanoidOf(vrm, fn);
  const nodes = nodesOf(humanoid);
  applyFace(vrm, result);
  let written = 0;
  if (result instanceof Float32Array) {
    const O = LAYOUT.output;
    if (result.length !== O.length) {
      throw new TypeError(`${fn}: a flat output must have ${O.length} numbers (LAYOUT.output.length), got ${result.length}`);
    }
    const bones = LAYOUT.bones;
    for (let i = 0; i < bones.length; i++) {
      if (result[O.boneFlags + i] === 0) continue;
      const node = nodes.get(bones[i]!);
      if (!node) continue;
      const at = O.boneRotations + 4 * i;
      node.quaternion.set(result[at]!, result[at + 1]!, result[at + 2]!, result[at + 3]!);
      written++;
    }
    if (result[O.boneFlags + LEFT_UPPER_LEG] !== 0) moveHips(humanoid, nodes, result, O.hipsOffset);
    return written;
  }
  const bones: unknown = result !== null && typeof result === "object" ? result.bones : undefined;
  if (bones === null || typeof bones !== "object") {
    throw new TypeError(`${fn}: result.bones must be the bones of a HandRig.solve() result (or pass a flat output Float32Array)`);
  }
  // for..in over the result's own plain object: no per-frame allocation.
  const map = bones as { [boneName: string]: ArrayLike<number> | undefined };
  for (const name in map) {
    const q = map[name];
    const node = nodes.get(name);
    if (!node || !q) continue;
    node.quaternion.set(q[0]!, q[1]!, q[2]!, q[3]!);
    written++;
  }
  const offset = (result as { hipsOffset?: ArrayLike<number> }).hipsOffset;
  if (map.leftUpperLeg !== undefined && offset !== undefined) moveHips(humanoid, nodes, offset, 0);
  return written;
}

// The face (issue 50): per expression manager, which of its expressions each weight sets; per
// VRM, whether the last frame had a face (the frame after one is lost sets them to 0 once).
const faceBindings = new WeakMap<object, FaceBinding>();
const hadFace = new WeakMap<object, boolean>();

/**
 * The face of a result onto the VRM: with the 52 ARKit expressions (perfect sync, names in any
 * case or with a prefix such as `BlendShape.`) those, otherwise the presets (VRM 1.0 names, or
 * VRM 0.x names kept as custom expressions); the look-at's yaw and pitch on `vrm.lookAt` (its
 * applier turns the eyes or sets lookUp/Down/Left/Right within the avatar's range), or the look*
 * presets on an avatar without one. Nothing while no face was tracked.
 */
function applyFace(vrm: VRMLike, result: unknown): void {
  if (!readFace(result)) return;
  const live = FACE.state !== 0;
  if (!live && hadFace.get(vrm) !== true) return;
  hadFace.set(vrm, live);
  const manager = vrm.expressionManager;
  const look = vrm.lookAt;
  if (manager) {
    let binding = faceBindings.get(manager);
    if (binding === undefined) {
      binding = bindFace(manager.expressions.map((e) => e.expressionName));
      faceBindings.set(manager, binding);
    }
    if (binding.perfectSync) {
      const names = binding.arkit;
      for (let k = 0; k < names.length; k++) {
        const name = names[k];
        if (name) manager.setValue(name, FACE.arkit[k]!);
      }
    } else {
      const names = binding.presets;
      // lookUp / Down / Left / Right: vrm.lookAt sets them when the avatar has one.
      const n = look ? LOOK_PRESETS_FROM : names.length;
      for (let k = 0; k < n; k++) {
        const name = names[k];
        if (name) manager.setValue(name, FACE.presets[k]!);
      }
    }
  }
  if (look) {
    look.yaw = FACE.yaw;
    look.pitch = FACE.pitch;
  }
}

const LOOK_PRESETS_FROM = LAYOUT.expressions.indexOf("lookUp");
// Legs (issue 51): the hips' position while the rig drives the legs.
const LEFT_UPPER_LEG = LAYOUT.bones.indexOf("leftUpperLeg");

/** The normalized hips at their rest position plus the offset at `offset[at..at + 3]`. */
function moveHips(humanoid: Humanoid, nodes: Map<string, BoneNodeLike | null>, offset: ArrayLike<number>, at: number): void {
  const hips = nodes.get("hips");
  const rest = humanoid.normalizedRestPose.hips?.position;
  if (!hips?.position || !rest) return;
  hips.position.set(rest[0]! + offset[at]!, rest[1]! + offset[at + 1]!, rest[2]! + offset[at + 2]!);
}
