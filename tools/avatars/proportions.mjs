#!/usr/bin/env node
// The proportions of the generated avatars (their VRM 1.0 files, mesh and skeleton as shipped)
// beside the user proportions handrig's contact and body code assumes, read from src/.
//
//   node tools/avatars/proportions.mjs [DIR]      (DIR: default tests/fixtures/avatars)
//
// Prints the markdown table of docs/guide/avatars.md (tests/node/consumer/avatars.test.mjs checks
// that the page holds this output).

import fs from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";

import { BODIES, DEFAULT_OUT, REPO } from "./generate.mjs";
import { readGlbJson } from "./gltf.mjs";
import { mcompose, mmul } from "./math.mjs";

/** A GLB's JSON, accessor reader and node world matrices. */
export function readGlb(buf) {
  const json = readGlbJson(buf);
  const jsonLen = buf.readUInt32LE(12);
  const binStart = 20 + jsonLen + 8;
  const Types = { 5126: Float32Array, 5121: Uint8Array, 5123: Uint16Array, 5125: Uint32Array };
  const sizes = { SCALAR: 1, VEC3: 3, VEC4: 4, MAT4: 16 };
  const accessor = (i) => {
    const a = json.accessors[i];
    const v = json.bufferViews[a.bufferView];
    const T = Types[a.componentType];
    const bytes = buf.subarray(binStart + v.byteOffset, binStart + v.byteOffset + v.byteLength);
    return new T(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + a.count * sizes[a.type] * T.BYTES_PER_ELEMENT));
  };
  const world = new Array(json.nodes.length);
  const walk = (i, parent) => {
    const n = json.nodes[i];
    let m = n.matrix ?? mcompose(n.translation ?? [0, 0, 0], n.rotation ?? [0, 0, 0, 1]);
    if (n.scale) m = m.map((x, k) => (k < 12 && k % 4 !== 3 ? x * n.scale[Math.floor(k / 4)] : x));
    world[i] = parent ? mmul(parent, m) : m;
    for (const c of n.children ?? []) walk(c, world[i]);
  };
  for (const r of json.scenes[json.scene ?? 0].nodes) walk(r, null);
  return { json, accessor, world, position: (i) => [world[i][12], world[i][13], world[i][14]] };
}

/** Reads `pub const NAME: ... = <number>` or a `canon(x, y, z)` from a Rust source file. */
function rustConst(file, name, { canon = false } = {}) {
  const text = fs.readFileSync(path.join(REPO, file), "utf8");
  const re = canon
    ? new RegExp(`pub const ${name}: Vec3 = canon\\(([-0-9.]+), ([-0-9.]+), ([-0-9.]+)\\)`)
    : new RegExp(`pub const ${name}: f32 = ([-0-9.]+)(?: / 0\\.0)?;`);
  const m = text.match(re);
  if (!m) throw new Error(`${file}: ${name} not found (the proportions table reads it): update tools/avatars/proportions.mjs`);
  return canon ? m.slice(1).map(Number) : Number(m[1]);
}

/** The user proportions handrig assumes (src/contact/face.rs, src/body.rs). */
export function userAssumptions() {
  const headBreadth = rustConst("src/contact/face.rs", "HEAD_BREADTH");
  const faceRs = fs.readFileSync(path.join(REPO, "src/contact/face.rs"), "utf8");
  const armForHead = Number(faceRs.match(/pub const HEAD_PER_ARM: f32 = HEAD_BREADTH \/ ([0-9.]+);/)?.[1]);
  const eyes = Number(faceRs.match(/pub const CANONICAL_EYES: \[Vec3; 2\] = \[canon\(([0-9.]+),/)?.[1]) * 2;
  const eyeball = Number(faceRs.match(/pub const EYEBALL: f32 = ([0-9.]+) \/ HEAD_BREADTH;/)?.[1]);
  const nose = faceRs.match(/pub const CANONICAL_ANCHORS: \[Vec3; ANCHORS\] = \[\s*canon\(([-0-9.]+), ([-0-9.]+), ([-0-9.]+)\)/);
  const eyesFromHead = rustConst("src/contact/face.rs", "EYES_FROM_HEAD", { canon: true });
  const userArm = rustConst("src/body.rs", "REFERENCE_USER_ARM");
  for (const [k, v] of Object.entries({ armForHead, eyes, eyeball, nose: nose && Number(nose[3]) })) {
    if (!Number.isFinite(v)) throw new Error(`src/contact/face.rs: ${k} not found: update tools/avatars/proportions.mjs`);
  }
  return {
    headBreadth,
    armForHead,
    userArm,
    eyeDistance: eyes,
    eyesAboveHead: eyesFromHead[1],
    // Head bone to nose tip, straight ahead: eyes' centers, eyeball radius, nose in front.
    noseDepth: eyesFromHead[2] + eyeball + Number(nose[3]),
  };
}

/** Measures one VRM 1.0 avatar (meters). */
export function measure(file) {
  const g = readGlb(fs.readFileSync(file));
  const bones = g.json.extensions.VRMC_vrm.humanoid.humanBones;
  const at = (b) => g.position(bones[b].node);
  const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
  const prim = g.json.meshes[0].primitives[0];
  const pos = g.accessor(prim.attributes.POSITION);
  const joints = g.accessor(prim.attributes.JOINTS_0);
  const skinJoints = g.json.skins[0].joints;
  const headNode = bones.head.node;
  const n = pos.length / 3;
  const isHead = (i) => skinJoints[joints[4 * i]] === headNode; // largest influence first
  let height = 0;
  for (let i = 0; i < n; i++) height = Math.max(height, pos[3 * i + 1]);
  const arm = (s) => dist(at(`${s}UpperArm`), at(`${s}LowerArm`)) + dist(at(`${s}LowerArm`), at(`${s}Hand`));
  // Hand: wrist joint to the farthest vertex along the arm (T-pose: the middle fingertip).
  let reachL = -Infinity;
  let reachR = Infinity;
  for (let i = 0; i < n; i++) {
    reachL = Math.max(reachL, pos[3 * i]);
    reachR = Math.min(reachR, pos[3 * i]);
  }
  const hand = (reachL - at("leftHand")[0] + (at("rightHand")[0] - reachR)) / 2;
  const eyeL = at("leftEye");
  const eyeR = at("rightEye");
  const eyeY = (eyeL[1] + eyeR[1]) / 2;
  // Skull breadth: the head's widest extent 2 to 6 cm above the eyes' centers (above the ears).
  let minX = Infinity;
  let maxX = -Infinity;
  let noseZ = -Infinity;
  for (let i = 0; i < n; i++) {
    if (!isHead(i)) continue;
    const [x, y, z] = [pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]];
    if (y > eyeY + 0.02 && y < eyeY + 0.06) (minX = Math.min(minX, x)), (maxX = Math.max(maxX, x));
    if (Math.abs(x) < 0.01) noseZ = Math.max(noseZ, z);
  }
  const head = at("head");
  return {
    height,
    arm: (arm("left") + arm("right")) / 2,
    hand,
    headBreadth: maxX - minX,
    eyeDistance: dist(eyeL, eyeR),
    eyesAboveHead: eyeY - head[1],
    noseDepth: noseZ - head[2],
  };
}

const mm = (x) => (x * 1000).toFixed(0);

/** The markdown table: one row per avatar, then the user handrig assumes. */
export function table(dir = DEFAULT_OUT) {
  const u = userAssumptions();
  const rows = [
    "| avatar | height | arm (upper + lower) | hand (wrist to middle tip) | head breadth (skull) | eye distance | head breadth from eyes (handrig) | eyes above head bone | head bone to nose tip (depth) | head breadth / arm |",
    "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |",
  ];
  for (const b of BODIES) {
    const m = measure(path.join(dir, `${b.id}-vrm1.vrm`));
    const fromEyes = (m.eyeDistance / u.eyeDistance) * u.headBreadth;
    rows.push(
      `| \`${b.id}-vrm1.vrm\` | ${mm(m.height)} | ${mm(m.arm)} | ${mm(m.hand)} | ${mm(m.headBreadth)} | ${mm(m.eyeDistance)} | ${mm(fromEyes)} | ${mm(m.eyesAboveHead)} | ${mm(m.noseDepth)} | ${(m.headBreadth / m.arm).toFixed(2)} |`,
    );
  }
  rows.push(
    `| user, as handrig assumes | – | ${mm(u.userArm)} (calibration start), ${mm(u.armForHead)} (face scale) | – (palm ratio, measured live) | ${mm(u.headBreadth)} | ${mm(u.eyeDistance)} | ${mm(u.headBreadth)} | ${mm(u.eyesAboveHead)} | ${mm(u.noseDepth)} | ${(u.headBreadth / u.armForHead).toFixed(2)} |`,
  );
  return `${rows.join("\n")}\n`;
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  process.stdout.write(table(process.argv[2] ? path.resolve(process.argv[2]) : DEFAULT_OUT));
}
