// The MakeHuman body (../shared/data/makehuman, see its README section): base mesh, body-shape
// targets, joints placed from the reshaped mesh, skin weights, and the A-pose to T-pose bake.
//
// Frames: the base mesh's own (+Y up, the body faces +Z, its left at +X), converted from
// decimeters to meters on reading. MPFB's rig files describe bone rolls in Blender's frame
// (Z up, the body faces -Y): `toBlender` / `fromBlender` convert directions.

import fs from "node:fs";
import path from "node:path";
import zlib from "node:zlib";

import { add, cross, normalize, qfromBasis, qfromTo, qmul, qnormalize, qrotate, QUAT_IDENTITY, scale, sub } from "./math.mjs";

const DM = 0.1; // base.obj and the targets are in decimeters

/** The vertex groups kept: the body and the two eyes (helper geometry otherwise dropped). */
export const KEPT_GROUPS = ["body", "helper-l-eye", "helper-r-eye"];

/** Reads base.obj: positions (meters, Float64Array), faces per group (vertex indices). */
export function readBaseMesh(dir) {
  const text = fs.readFileSync(path.join(dir, "base.obj"), "utf8");
  const pos = [];
  const faces = new Map();
  let group = null;
  for (const line of text.split("\n")) {
    if (line.startsWith("v ")) {
      const [, x, y, z] = line.trim().split(/\s+/);
      pos.push(Number(x) * DM, Number(y) * DM, Number(z) * DM);
    } else if (line.startsWith("g ")) {
      group = line.slice(2).trim();
    } else if (line.startsWith("f ")) {
      const idx = line.trim().split(/\s+/).slice(1).map((t) => Number(t.split("/")[0]) - 1);
      if (!faces.has(group)) faces.set(group, []);
      faces.get(group).push(idx);
    }
  }
  const groups = JSON.parse(fs.readFileSync(path.join(dir, "mesh_metadata", "basemesh_vertex_groups.json"), "utf8"));
  return { positions: Float64Array.from(pos), faces, groups };
}

/** Adds a gzipped MakeHuman target (`vertex dx dy dz` lines, decimeters) at `weight`. */
export function applyTarget(positions, file, weight = 1) {
  const text = zlib.gunzipSync(fs.readFileSync(file)).toString("utf8");
  const out = Float64Array.from(positions);
  for (const line of text.split("\n")) {
    const t = line.trim().split(/\s+/);
    if (t.length !== 4) continue;
    const i = Number(t[0]);
    for (let k = 0; k < 3; k++) out[3 * i + k] += Number(t[k + 1]) * DM * weight;
  }
  return out;
}

const vertex = (p, i) => [p[3 * i], p[3 * i + 1], p[3 * i + 2]];

function meanOf(p, indices) {
  let s = [0, 0, 0];
  for (const i of indices) s = add(s, vertex(p, i));
  return scale(s, 1 / indices.length);
}

function rangeIndices(ranges) {
  const out = [];
  for (const [a, b] of ranges) for (let i = a; i <= b; i++) out.push(i);
  return out;
}

/** A joint end per MPFB's strategies: CUBE (center of a joint cube's vertices) or MEAN. */
function place(end, groups, p) {
  if (end.strategy === "CUBE") {
    const ranges = groups[end.cube_name];
    if (!ranges) throw new Error(`no vertex group ${end.cube_name}`);
    return meanOf(p, rangeIndices(ranges));
  }
  if (end.strategy === "MEAN") return meanOf(p, end.vertex_indices);
  throw new Error(`unknown joint strategy ${end.strategy}`);
}

/** Blender frame (Z up, facing -Y) from the mesh frame (Y up, facing +Z), and back. */
export const toBlender = (v) => [v[0], -v[2], v[1]];
export const fromBlender = (v) => [v[0], v[2], -v[1]];

/**
 * The bone's rest rotation as Blender builds it from head, tail and roll (`vec_roll_to_mat3`:
 * the shortest turn of +Y onto the bone, then the roll about it), in the mesh frame: the
 * bone's local +Y runs along the bone, as in Blender's and Mixamo's exports.
 */
export function blenderBoneRotation(head, tail, roll) {
  const [x, y, z] = normalize(toBlender(sub(tail, head)));
  const theta = 1 + y;
  let cx, cy, cz;
  if (theta > 1e-7) {
    cx = [1 - (x * x) / theta, -x, (-x * z) / theta];
    cy = [x, y, z];
    cz = [(-x * z) / theta, -z, 1 - (z * z) / theta];
  } else {
    // The bone points along -Y: Blender's special case (a half turn about Z).
    cx = [-1, 0, 0];
    cy = [0, -1, 0];
    cz = [0, 0, 1];
  }
  const bend = qfromBasis(cx, cy, cz);
  const half = roll / 2;
  const rollQ = qnormalize([x * Math.sin(half), y * Math.sin(half), z * Math.sin(half), Math.cos(half)]);
  const inBlender = qmul(rollQ, bend);
  // The same rotation seen in the mesh frame: C * R * C^-1 applied to the bone's axes
  // gives columns C * (R e_i); the local axes stay the bone's own (e_i), so world = C R.
  const cols = [[1, 0, 0], [0, 1, 0], [0, 0, 1]].map((e) => fromBlender(qrotate(inBlender, e)));
  return qfromBasis(cols[0], cols[1], cols[2]);
}

/**
 * The skeleton of an MPFB rig file, parent-first, joints placed from `positions`.
 * `extra` adds bones (the eyes, which the game-engine rig lacks): { name, parent, head, tail }
 * given as cube names.
 */
export function buildSkeleton(rigFile, groups, positions, extra = []) {
  const raw = JSON.parse(fs.readFileSync(rigFile, "utf8"));
  const rig = raw.bones ?? raw;
  const entries = Object.entries(rig).map(([name, b]) => ({
    name,
    parent: b.parent || null,
    head: place(b.head, groups, positions),
    tail: place(b.tail, groups, positions),
    roll: b.roll ?? 0,
  }));
  for (const e of extra) {
    entries.push({
      name: e.name,
      parent: e.parent,
      head: place({ strategy: "CUBE", cube_name: e.head }, groups, positions),
      tail: place({ strategy: "CUBE", cube_name: e.tail }, groups, positions),
      roll: 0,
    });
  }
  // Parent-first order, siblings by name: deterministic whatever the file's key order.
  const byName = new Map(entries.map((e) => [e.name, e]));
  const order = [];
  const visit = (parent) => {
    for (const e of entries.filter((x) => x.parent === parent).sort((a, b) => (a.name < b.name ? -1 : 1))) {
      order.push(e);
      visit(e.name);
    }
  };
  visit(null);
  if (order.length !== entries.length) throw new Error("rig has bones whose parent is missing");
  order.forEach((b, i) => (b.index = i));
  for (const b of order) b.parentIndex = b.parent ? byName.get(b.parent).index : -1;
  return order;
}

/**
 * Skin weights per vertex from an MPFB weights file: for vertex i, [[boneIndex, weight], ...]
 * (every influence, largest first). `override` maps a vertex range to one bone (the eyes).
 */
export function readWeights(file, skeleton, vertexCount, override = []) {
  const { weights } = JSON.parse(fs.readFileSync(file, "utf8"));
  const index = new Map(skeleton.map((b) => [b.name, b.index]));
  const per = Array.from({ length: vertexCount }, () => []);
  for (const [bone, list] of Object.entries(weights)) {
    const bi = index.get(bone);
    if (bi === undefined) {
      if (list.length) throw new Error(`weights for unknown bone ${bone}`);
      continue;
    }
    for (const [v, w] of list) if (w > 0) per[v].push([bi, w]);
  }
  for (const { ranges, bone } of override) {
    for (const v of rangeIndices(ranges)) per[v] = [[index.get(bone), 1]];
  }
  for (const list of per) list.sort((a, b) => b[1] - a[1] || a[0] - b[0]);
  return per;
}

/**
 * Poses the skeleton by world-space swings: `aims` maps a bone name to the direction its
 * aim vector must point (after its parents are posed); the aim vector runs from the bone's
 * head to `aimEnd(bone)` (its tail by default). Returns per bone the accumulated world
 * rotation and the posed head.
 */
export function poseBySwings(skeleton, aims, aimEnd = (b) => b.tail) {
  const rot = [];
  const head = [];
  for (const b of skeleton) {
    const p = b.parentIndex;
    const parentRot = p < 0 ? QUAT_IDENTITY : rot[p];
    head[b.index] = p < 0 ? b.head : add(head[p], qrotate(parentRot, sub(b.head, skeleton[p].head)));
    let delta = QUAT_IDENTITY;
    const target = aims[b.name];
    if (target) {
      const d = normalize(qrotate(parentRot, sub(aimEnd(b), b.head)));
      delta = qfromTo(d, normalize(target));
    }
    rot[b.index] = qnormalize(qmul(delta, parentRot));
  }
  return { rot, head };
}

/** Linear-blend skinning of rest `positions` into a pose from `poseBySwings` (all influences). */
export function skinPositions(positions, weights, skeleton, pose, vertices) {
  const out = new Float64Array(positions.length);
  for (const v of vertices) {
    const p = vertex(positions, v);
    let total = 0;
    let acc = [0, 0, 0];
    for (const [bi, w] of weights[v]) {
      const moved = add(pose.head[bi], qrotate(pose.rot[bi], sub(p, skeleton[bi].head)));
      acc = add(acc, scale(moved, w));
      total += w;
    }
    const r = total > 0 ? scale(acc, 1 / total) : p;
    out[3 * v] = r[0];
    out[3 * v + 1] = r[1];
    out[3 * v + 2] = r[2];
  }
  return out;
}

/** Posed joint ends: heads from the pose, tails carried by the bone's rotation. */
export function posedTail(skeleton, pose, b) {
  return add(pose.head[b.index], qrotate(pose.rot[b.index], sub(b.tail, b.head)));
}

export { rangeIndices, vertex, cross };
