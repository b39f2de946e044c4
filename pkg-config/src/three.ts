// handrig <-> plain three.js adapter (`handrig/three`): drives any glTF humanoid loaded with
// three's GLTFLoader (Mixamo, Unreal-mannequin, Blender rigs, Ready Player Me-style) without
// three-vrm. handrig solves three-vrm's *normalized* bones (identity rest rotations, rotations
// local to the parent humanoid bone); a plain skeleton's bones carry their own rest rotations
// (rolls), so each normalized rotation q is carried through the bone's rest frame, as three-vrm
// does internally:   local = P^-1 * q * P * B
// with P the rest rotation of the bone's parent node and B the bone's rest local rotation, both
// in the model's frame (the root passed in). Like `handrig/three-vrm` it imports nothing at run
// time: the scene objects are used through the few members of `Object3DLike`, so the package has
// no dependency on three, and a three `Object3D` fits the types.

import { FACE, bindFace, readFace, type FaceBinding } from "./expression-names.js";
import { LAYOUT } from "./layout.js";
import { mul, type SceneLike, type SkinArrays, skinOfScene } from "./skin.js";

/** The parts of three's `Object3D` the adapter uses. */
export interface Object3DLike {
  name: string;
  parent: Object3DLike | null;
  children: Object3DLike[];
  position: { x: number; y: number; z: number };
  quaternion: { x: number; y: number; z: number; w: number; set(x: number, y: number, z: number, w: number): unknown };
  scale: { x: number; y: number; z: number };
}

/** `{ humanBoneName: nodeName }`: which node of the scene each humanoid bone is. */
export type SkeletonBoneMap = { [humanBone: string]: string };

/** What `restPoseFromSkeleton` returns: a rest pose for `new HandRig(...)` plus the binding. */
export interface SkeletonRestPose {
  /** Rest world positions of the humanoid bones, meters, the model's frame (relative to `root`). */
  bones: { [humanBone: string]: [number, number, number] };
  /** "1": the model faces +Z (its left toward +X); "0": it faces -Z. */
  vrmVersion: "0" | "1";
  /** The binding used (node names as the scene names them): pass it to `applyToSkeleton`. */
  boneMap: SkeletonBoneMap;
  /**
   * The skin at rest from the skinned meshes under `root` (skinned with the bones as they are,
   * in `root`'s frame, like `bones`), for self-contact; absent when there is none.
   */
  skin?: SkinArrays;
}

type Q = [number, number, number, number];
type M = number[]; // 4x4, column-major

const qinv = (a: Q): Q => [-a[0], -a[1], -a[2], a[3]];

/** The local matrix of a node: translation * rotation * scale (three's `Matrix4.compose`). */
function localMatrix(o: Object3DLike): M {
  const { x, y, z, w } = o.quaternion;
  const s = o.scale;
  const x2 = x + x, y2 = y + y, z2 = z + z;
  const xx = x * x2, xy = x * y2, xz = x * z2, yy = y * y2, yz = y * z2, zz = z * z2;
  const wx = w * x2, wy = w * y2, wz = w * z2;
  return [
    (1 - (yy + zz)) * s.x, (xy + wz) * s.x, (xz - wy) * s.x, 0,
    (xy - wz) * s.y, (1 - (xx + zz)) * s.y, (yz + wx) * s.y, 0,
    (xz + wy) * s.z, (yz - wx) * s.z, (1 - (xx + yy)) * s.z, 0,
    o.position.x, o.position.y, o.position.z, 1,
  ];
}

const IDENTITY: M = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];

/** `node`'s transform in `root`'s frame (the product of the local matrices below `root`). */
function matrixIn(root: Object3DLike, node: Object3DLike | null): M {
  const chain: Object3DLike[] = [];
  for (let o = node; o !== null && o !== root; o = o.parent) chain.push(o);
  let m = IDENTITY;
  for (let i = chain.length - 1; i >= 0; i--) m = mul(m, localMatrix(chain[i]!));
  return m;
}

/** The rotation of a transform with positive scale (columns normalized; three's `setFromRotationMatrix`). */
function rotationOf(m: M): Q {
  const col = (c: number) => {
    const v = [m[4 * c]!, m[4 * c + 1]!, m[4 * c + 2]!];
    const n = Math.hypot(v[0]!, v[1]!, v[2]!);
    return v.map((x) => x / n);
  };
  const [m11, m21, m31] = col(0) as [number, number, number];
  const [m12, m22, m32] = col(1) as [number, number, number];
  const [m13, m23, m33] = col(2) as [number, number, number];
  const trace = m11 + m22 + m33;
  if (trace > 0) {
    const s = 0.5 / Math.sqrt(trace + 1);
    return [(m32 - m23) * s, (m13 - m31) * s, (m21 - m12) * s, 0.25 / s];
  } else if (m11 > m22 && m11 > m33) {
    const s = 2 * Math.sqrt(1 + m11 - m22 - m33);
    return [0.25 * s, (m12 + m21) / s, (m13 + m31) / s, (m32 - m23) / s];
  } else if (m22 > m33) {
    const s = 2 * Math.sqrt(1 + m22 - m11 - m33);
    return [(m12 + m21) / s, 0.25 * s, (m23 + m32) / s, (m13 - m31) / s];
  }
  const s = 2 * Math.sqrt(1 + m33 - m11 - m22);
  return [(m13 + m31) / s, (m23 + m32) / s, 0.25 * s, (m21 - m12) / s];
}

// --- names ---------------------------------------------------------------------------------

const SIDES = [["left", "Left", "l"], ["right", "Right", "r"]] as const;
const FINGERS = [
  ["Thumb", "Thumb", "thumb"],
  ["Index", "Index", "index"],
  ["Middle", "Middle", "middle"],
  ["Ring", "Ring", "ring"],
  ["Little", "Pinky", "pinky"],
] as const;

function tables(): { mixamo: Map<string, string>; unreal: Map<string, string> } {
  const mixamo = new Map<string, string>([
    ["Hips", "hips"], ["Spine", "spine"], ["Spine1", "chest"], ["Spine2", "upperChest"], ["Neck", "neck"], ["Head", "head"],
  ]);
  const unreal = new Map<string, string>([
    ["pelvis", "hips"], ["spine_01", "spine"], ["spine_02", "chest"], ["spine_03", "upperChest"], ["neck_01", "neck"], ["head", "head"],
  ]);
  for (const [side, Side, s] of SIDES) {
    const parts: [string, string, string][] = [
      ["Eye", "Eye", "eye"], ["Shoulder", "Shoulder", "clavicle"], ["UpperArm", "Arm", "upperarm"],
      ["LowerArm", "ForeArm", "lowerarm"], ["Hand", "Hand", "hand"], ["UpperLeg", "UpLeg", "thigh"],
      ["LowerLeg", "Leg", "calf"], ["Foot", "Foot", "foot"], ["Toes", "ToeBase", "ball"],
    ];
    for (const [vrm, m, u] of parts) {
      mixamo.set(`${Side}${m}`, `${side}${vrm}`);
      unreal.set(`${u}_${s}`, `${side}${vrm}`);
    }
    for (const [vrm, m, u] of FINGERS) {
      const joints = vrm === "Thumb" ? ["Metacarpal", "Proximal", "Distal"] : ["Proximal", "Intermediate", "Distal"];
      joints.forEach((j, k) => {
        mixamo.set(`${Side}Hand${m}${k + 1}`, `${side}${vrm}${j}`);
        unreal.set(`${u}_0${k + 1}_${s}`, `${side}${vrm}${j}`);
      });
    }
  }
  return { mixamo, unreal };
}
let TABLES: ReturnType<typeof tables> | undefined;

/** three's `PropertyBinding.sanitizeNodeName` (what GLTFLoader names nodes): whitespace to "_", `[ ] . : /` dropped. */
export function sanitizeNodeName(name: string): string {
  return name.replace(/\s/g, "_").replace(/[[\].:/]/g, "");
}

function allNodes(root: Object3DLike): Object3DLike[] {
  const out: Object3DLike[] = [];
  const stack = [root];
  while (stack.length > 0) {
    const o = stack.pop()!;
    out.push(o);
    for (let i = o.children.length - 1; i >= 0; i--) stack.push(o.children[i]!);
  }
  return out;
}

/** The humanoid bone of a node name: Mixamo (with or without "mixamorig:") or Unreal names. */
function bindByNames(nodes: Object3DLike[], fn: string): SkeletonBoneMap {
  TABLES ??= tables();
  const { mixamo, unreal } = TABLES;
  const m = (n: string) => mixamo.get(n.replace(/^mixamorig\d*:?/, ""));
  const u = (n: string) => unreal.get(n.toLowerCase());
  const count = (f: (n: string) => string | undefined) => nodes.filter((o) => f(o.name) !== undefined).length;
  const cm = count(m);
  const cu = count(u);
  if (cm === 0 && cu === 0) {
    throw new Error(
      `${fn}: no humanoid found: no node has a Mixamo ("mixamorig:Hips", ...) or Unreal-mannequin ("pelvis", "upperarm_l", ...) bone name; pass a boneMap`,
    );
  }
  const f = cm >= cu ? m : u;
  const map: SkeletonBoneMap = {};
  for (const o of nodes) {
    const bone = f(o.name);
    if (bone === undefined) continue;
    if (map[bone] !== undefined) {
      throw new Error(`${fn}: duplicate binding: ${bone} matches both "${map[bone]}" and "${o.name}"`);
    }
    map[bone] = o.name;
  }
  return map;
}

/** The node a bone-map entry names (as written in the file, or as three sanitizes it). */
function findNode(nodes: Object3DLike[], name: string, field: string): Object3DLike {
  let found = nodes.filter((o) => o.name === name);
  if (found.length === 0) {
    const s = sanitizeNodeName(name);
    found = nodes.filter((o) => o.name === s);
  }
  if (found.length === 0) throw new Error(`${field}: no node named ${JSON.stringify(name)} under the root`);
  if (found.length > 1) throw new Error(`${field}: ${found.length} nodes are named ${JSON.stringify(name)}`);
  return found[0]!;
}

// --- rest data -----------------------------------------------------------------------------

interface BoneRest {
  bone: string;
  node: Object3DLike;
  /** Parent node's rest rotation in the root's frame, and its inverse. */
  P: Q;
  Pinv: Q;
  /** The node's rest local rotation. */
  B: Q;
}

/**
 * Rest data per root, by binding object (no allocation per frame when the same binding object is
 * passed every frame) and by binding contents (the first lookup of a new binding object).
 */
const REST = new WeakMap<Object3DLike, { byObject: WeakMap<object, BoneRest[]>; byKey: Map<string, BoneRest[]> }>();

function recordRest(root: Object3DLike, boneMap: SkeletonBoneMap, fn: string): BoneRest[] {
  let perRoot = REST.get(root);
  const hit = perRoot?.byObject.get(boneMap);
  if (hit) return hit;
  if (!perRoot) REST.set(root, (perRoot = { byObject: new WeakMap(), byKey: new Map() }));
  const key = JSON.stringify(Object.entries(boneMap).sort());
  let rest = perRoot.byKey.get(key);
  if (!rest) {
    const nodes = allNodes(root);
    rest = [];
    const used = new Map<Object3DLike, string>();
    for (const [bone, name] of Object.entries(boneMap)) {
      if (typeof name !== "string") throw new TypeError(`${fn}: boneMap.${bone} must be a node name (a string)`);
      const node = findNode(nodes, name, `${fn}: boneMap.${bone}`);
      const other = used.get(node);
      if (other !== undefined) throw new Error(`${fn}: duplicate binding: ${other} and ${bone} are both bound to node "${node.name}"`);
      used.set(node, bone);
      const P = rotationOf(matrixIn(root, node.parent));
      const { x, y, z, w } = node.quaternion;
      rest.push({ bone, node, P, Pinv: qinv(P), B: [x, y, z, w] });
    }
    perRoot.byKey.set(key, rest);
  }
  perRoot.byObject.set(boneMap, rest);
  return rest;
}

function checkRoot(root: unknown, fn: string): asserts root is Object3DLike {
  if (root === null || typeof root !== "object" || !Array.isArray((root as { children?: unknown }).children)) {
    throw new TypeError(`${fn}: root must be a three.js Object3D (gltf.scene from GLTFLoader)`);
  }
}

/**
 * The rest pose handrig needs, from a plain glTF scene (`gltf.scene` from GLTFLoader) at rest:
 * `{ bones, vrmVersion, boneMap }` for `new HandRig(rest, options)`. Bones are found by
 * `boneMap` (`{ humanBone: nodeName }`, e.g. `rig.boneMap()` of a `HandRig.fromGltf` rig) or by
 * Mixamo / Unreal-mannequin names. Positions are in `root`'s frame (armature nodes turned or
 * scaled inside the model are followed); `vrmVersion` is "0" when the model faces -Z (its left
 * toward -X). Also records each bone's rest rotations for `applyToSkeleton`, so call it while the
 * model is at rest.
 * @throws Error naming the bone: no humanoid found, a node not found, a duplicate binding.
 */
export function restPoseFromSkeleton(root: Object3DLike, boneMap?: SkeletonBoneMap | null): SkeletonRestPose {
  const fn = "restPoseFromSkeleton";
  checkRoot(root, fn);
  const map = boneMap ?? bindByNames(allNodes(root), fn);
  const rest = recordRest(root, map, fn);
  const bones: SkeletonRestPose["bones"] = {};
  const names: SkeletonBoneMap = {};
  for (const r of rest) {
    const m = matrixIn(root, r.node);
    bones[r.bone] = [m[12]!, m[13]!, m[14]!];
    names[r.bone] = r.node.name;
  }
  let vrmVersion: "0" | "1" = "1";
  for (const [l, r] of [["leftUpperArm", "rightUpperArm"], ["leftUpperLeg", "rightUpperLeg"]] as const) {
    const a = bones[l];
    const b = bones[r];
    if (!a || !b) continue;
    const dx = a[0] - b[0];
    const dz = a[2] - b[2];
    if (Math.abs(dx) <= 2 * Math.abs(dz)) {
      throw new Error(`${fn}: facing: the skeleton's left-right axis (${l} - ${r}) is not along X: the model must face +Z or -Z`);
    }
    vrmVersion = dx > 0 ? "1" : "0";
    break;
  }
  const boneOfNode = new Map<unknown, number>();
  for (const r of rest) {
    const i = (LAYOUT.bones as readonly string[]).indexOf(r.bone);
    if (i >= 0) boneOfNode.set(r.node, i);
  }
  // A three `Object3D` has `traverse` (not in `Object3DLike`; skinOfScene checks for it).
  const skin = skinOfScene(root as unknown as SceneLike, boneOfNode, (bone) => matrixIn(root, bone as Object3DLike));
  return skin ? { bones, vrmVersion, boneMap: names, skin } : { bones, vrmVersion, boneMap: names };
}

/** A result's rotations: `{ bones: { [humanBone]: [x, y, z, w] } }` (what `rig.solve` returns). */
export interface BoneRotationsLike {
  bones: { [humanBone: string]: ArrayLike<number> | undefined };
}

/**
 * Writes `result.bones` (normalized rotations) onto the scene's own bones: each bound node's
 * `quaternion` becomes `P^-1 q P B` (its rest rotation carried through). `binding` is the bone map
 * (`rest.boneMap` of `restPoseFromSkeleton`, or `rig.boneMap()` of a `HandRig.fromGltf` rig);
 * the rest rotations are recorded the first time a root is seen with a binding (at rest!).
 * Bones without a node are skipped. Returns how many bones were written. Call
 * `root.updateMatrixWorld()` (three's renderer does) afterwards.
 */
export function applyToSkeleton(root: Object3DLike, result: BoneRotationsLike, binding: SkeletonBoneMap): number {
  const fn = "applyToSkeleton";
  checkRoot(root, fn);
  if (binding === null || typeof binding !== "object") {
    throw new TypeError(`${fn}: binding must be a bone map { humanBone: nodeName } (restPoseFromSkeleton(root).boneMap or rig.boneMap())`);
  }
  const rest = recordRest(root, binding, fn);
  const bones = result.bones;
  let written = 0;
  for (let i = 0; i < rest.length; i++) {
    const r = rest[i]!;
    const q = bones[r.bone];
    if (!q) continue;
    carry(r, q);
    r.node.quaternion.set(T[0]!, T[1]!, T[2]!, T[3]!);
    written++;
  }
  return written;
}

// Scratch for `carry` (no allocation per frame).
const T = new Float64Array(4);

/** T = P^-1 * q * P * B, in scalars. */
function carry(r: BoneRest, q: ArrayLike<number>): void {
  const P = r.P;
  const B = r.B;
  const px = P[0], py = P[1], pz = P[2], pw = P[3];
  const bx = B[0], by = B[1], bz = B[2], bw = B[3];
  const qx = q[0]!, qy = q[1]!, qz = q[2]!, qw = q[3]!;
  // a = P^-1 * q  (P^-1 = conjugate of the unit P)
  const ax = pw * qx - px * qw - py * qz + pz * qy;
  const ay = pw * qy + px * qz - py * qw - pz * qx;
  const az = pw * qz - px * qy + py * qx - pz * qw;
  const aw = pw * qw + px * qx + py * qy + pz * qz;
  // a = a * P
  const cx = aw * px + ax * pw + ay * pz - az * py;
  const cy = aw * py - ax * pz + ay * pw + az * px;
  const cz = aw * pz + ax * py - ay * px + az * pw;
  const cw = aw * pw - ax * px - ay * py - az * pz;
  // T = a * B
  T[0] = cw * bx + cx * bw + cy * bz - cz * by;
  T[1] = cw * by - cx * bz + cy * bw + cz * bx;
  T[2] = cw * bz + cx * by - cy * bx + cz * bw;
  T[3] = cw * bw - cx * bx - cy * by - cz * bz;
}

/** A mesh with morph targets: the parts of three's `Mesh` the face uses. */
interface MorphMeshLike {
  morphTargetDictionary?: { [name: string]: number };
  morphTargetInfluences?: number[];
}

/** Per mesh: which influence each weight sets (-1: none), the perfect-sync choice made per mesh. */
interface MeshFace {
  influences: number[];
  /** Per ARKit weight, then per preset: the influence's index or -1. */
  arkit: Int32Array;
  presets: Int32Array;
  perfectSync: boolean;
}

const sceneFaces = new WeakMap<object, MeshFace[]>();

function meshFaces(root: Object3DLike): MeshFace[] {
  let faces = sceneFaces.get(root);
  if (faces !== undefined) return faces;
  faces = [];
  const visit = (o: Object3DLike): void => {
    const m = o as unknown as MorphMeshLike;
    if (m.morphTargetDictionary && Array.isArray(m.morphTargetInfluences)) {
      const dict = m.morphTargetDictionary;
      const b: FaceBinding = bindFace(Object.keys(dict));
      faces!.push({
        influences: m.morphTargetInfluences,
        arkit: Int32Array.from(b.arkit, (n) => (n === null ? -1 : dict[n]!)),
        presets: Int32Array.from(b.presets, (n) => (n === null ? -1 : dict[n]!)),
        perfectSync: b.perfectSync,
      });
    }
    for (const c of o.children) visit(c);
  };
  visit(root);
  sceneFaces.set(root, faces);
  return faces;
}

/**
 * The face of a `solve` result (or a flat output) onto the morph targets of every mesh under
 * `root`, by name (issue 50): a mesh with the 52 ARKit shapes (any case, prefixes such as
 * `BlendShape.`, `_L`/`_R` suffixes) gets those (perfect sync), another the VRM presets under
 * their VRM 1.0, VRM 0.x or VRChat viseme names (`aa`, `A`, `vrc.v_aa`; `blink_l`; `joy`). The
 * meshes are bound on the first call (morph targets added later are not seen). Returns how many
 * meshes were written; 0 while no face is tracked (the frame after a face is lost sets them to 0).
 */
export function applyFaceToMorphTargets(root: Object3DLike, result: unknown): number {
  if (!readFace(result)) {
    throw new TypeError("applyFaceToMorphTargets: result must be a HandRig.solve() result or a flat output Float32Array");
  }
  const faces = meshFaces(root);
  const live = FACE.state !== 0;
  const seen = hadFace.get(root) === true;
  hadFace.set(root, live);
  if (!live && !seen) return 0;
  let written = 0;
  for (const f of faces) {
    const map = f.perfectSync ? f.arkit : f.presets;
    const weights = f.perfectSync ? FACE.arkit : FACE.presets;
    let any = false;
    for (let k = 0; k < map.length; k++) {
      const i = map[k]!;
      if (i >= 0) {
        f.influences[i] = weights[k]!;
        any = true;
      }
    }
    if (any) written++;
  }
  return written;
}

const hadFace = new WeakMap<object, boolean>();
