// Skin contact as a user sees it (issue 26): an avatar loaded with three + @pixiv/three-vrm,
// posed through its normalized humanoid, skinned on the CPU (three's
// SkinnedMesh.getVertexPosition), its vertices sorted into body parts by the dominant bone of
// their skin weights, and per frame: the gap between each hand's surface and the face, chest and
// other hand surfaces (three-mesh-bvh point queries), and how deep hand vertices are
// inside the head and torso (generalized winding number; depth = distance to that surface).
//
// Shared by eval/skin-contact.mjs (the tables of docs/measurements/2026-12-06-contact.md) and
// tests/node/consumer/skin-contact.test.mjs (checks of the measurement itself). It imports three,
// three-vrm and three-mesh-bvh (tests/node's dev dependencies) but not handrig: callers pass the
// rig's results in. Not part of the package.

import fs from "node:fs";
import path from "node:path";

import * as THREE from "three";
import { GLTFLoader } from "three/examples/jsm/loaders/GLTFLoader.js";
import { VRMLoaderPlugin } from "@pixiv/three-vrm";
import { MeshBVH } from "three-mesh-bvh";

/** three-vrm in Node: GLTFLoader + VRMLoaderPlugin, empty textures (Node has no image decoder). */
export async function loadVrm(file) {
  const loader = new GLTFLoader();
  loader.register(() => ({ name: "handrig_skin_no_images", loadTexture: async () => new THREE.Texture() }));
  loader.register((parser) => new VRMLoaderPlugin(parser));
  const buf = fs.readFileSync(file);
  const gltf = await loader.parseAsync(buf.buffer.slice(buf.byteOffset, buf.byteOffset + buf.byteLength), "");
  const vrm = gltf.userData.vrm;
  if (!vrm) throw new Error(`${path.basename(file)}: no VRM in the file`);
  return vrm;
}

// Body parts by humanoid bone (non-humanoid bones count as their nearest humanoid ancestor).
const PART_OF_BONE = {
  head: "head", jaw: "head", leftEye: "head", rightEye: "head",
  neck: "neck",
  spine: "chest", chest: "chest", upperChest: "chest", leftShoulder: "chest", rightShoulder: "chest",
  hips: "hips",
};
for (const side of ["left", "right"]) {
  PART_OF_BONE[`${side}Hand`] = `${side}Hand`;
  for (const f of ["Thumb", "Index", "Middle", "Ring", "Little"]) {
    for (const p of ["Metacarpal", "Proximal", "Intermediate", "Distal"]) PART_OF_BONE[`${side}${f}${p}`] = `${side}Hand`;
  }
}
/** The parts measured: face (head skin), chest (spine, chest, upper chest, shoulders), hands; body = head, neck, chest, hips (the inside test's surface). */
export const PARTS = ["head", "neck", "chest", "hips", "leftHand", "rightHand"];
const BODY_PARTS = new Set(["head", "neck", "chest", "hips"]);

/** Hand-written linear blend skinning of vertex `i` of `mesh` (mesh-local result), to check three's. */
export function skinByHand(mesh, i, target = new THREE.Vector3()) {
  const g = mesh.geometry;
  const p = new THREE.Vector3().fromBufferAttribute(g.attributes.position, i).applyMatrix4(mesh.bindMatrix);
  const sum = new THREE.Vector3();
  const m = new THREE.Matrix4();
  for (let k = 0; k < g.attributes.skinIndex.itemSize; k++) {
    const w = g.attributes.skinWeight.getComponent(i, k);
    if (w === 0) continue;
    const b = g.attributes.skinIndex.getComponent(i, k);
    m.multiplyMatrices(mesh.skeleton.bones[b].matrixWorld, mesh.skeleton.boneInverses[b]);
    sum.addScaledVector(p.clone().applyMatrix4(m), w);
  }
  return target.copy(sum.applyMatrix4(mesh.bindMatrixInverse));
}

// Solid angle of triangle (a, b, c) seen from the origin (Van Oosterom & Strackee), over 4 pi.
function triangleWinding(ax, ay, az, bx, by, bz, cx, cy, cz) {
  const la = Math.hypot(ax, ay, az);
  const lb = Math.hypot(bx, by, bz);
  const lc = Math.hypot(cx, cy, cz);
  const det = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
  const den = la * lb * lc + (ax * bx + ay * by + az * bz) * lc + (bx * cx + by * cy + bz * cz) * la + (cx * ax + cy * ay + cz * az) * lb;
  return Math.atan2(det, den) / (2 * Math.PI);
}

/**
 * An avatar's skin, posed and measured. `new SkinBody(vrm)` reads every SkinnedMesh (rigid meshes
 * are ignored: an avatar without skin has no parts), sorts vertices into PARTS by their dominant
 * bone and triangles by the part most of their corners have, and builds one BVH per part (refit
 * per frame). `update()` skins the parts' vertices into `positions` (world space) after the
 * caller posed the VRM and updated matrices.
 */
export class SkinBody {
  constructor(vrm, { clusterSize = 0.03, farRatio = 2.5 } = {}) {
    this.vrm = vrm;
    this.farRatio = farRatio;
    const humanoidOfNode = new Map();
    for (const name of Object.keys(vrm.humanoid.humanBones)) {
      const node = vrm.humanoid.getRawBoneNode(name);
      if (node) humanoidOfNode.set(node, name);
    }
    const partOfNode = (node) => {
      for (let n = node; n; n = n.parent) {
        const name = humanoidOfNode.get(n);
        if (name !== undefined) return PART_OF_BONE[name] ?? "other";
      }
      return "other";
    };
    vrm.scene.updateMatrixWorld(true);
    this.meshes = [];
    vrm.scene.traverse((o) => {
      if (o.isSkinnedMesh && o.geometry.attributes.skinIndex) this.meshes.push(o);
    });
    const total = this.meshes.reduce((s, m) => s + m.geometry.attributes.position.count, 0);
    this.vertexCount = total;
    this.positions = new Float32Array(total * 3);
    this.part = new Int8Array(total).fill(-1);
    this.meshOf = new Int32Array(total);
    this.offsets = [];
    const tris = Object.fromEntries(PARTS.map((p) => [p, []]));
    const used = new Uint8Array(total);
    let offset = 0;
    this.meshes.forEach((mesh, mi) => {
      const g = mesh.geometry;
      const n = g.attributes.position.count;
      this.offsets.push(offset);
      const si = g.attributes.skinIndex;
      const sw = g.attributes.skinWeight;
      for (let i = 0; i < n; i++) {
        let best = -1;
        let bestW = -1;
        for (let k = 0; k < si.itemSize; k++) {
          const w = sw.getComponent(i, k);
          if (w > bestW) (bestW = w), (best = si.getComponent(i, k));
        }
        this.part[offset + i] = PARTS.indexOf(partOfNode(mesh.skeleton.bones[best]));
        this.meshOf[offset + i] = mi;
      }
      const index = g.index ? g.index.array : Array.from({ length: n }, (_, i) => i);
      const groups = g.groups.length ? g.groups : [{ start: 0, count: index.length }];
      for (const grp of groups) {
        for (let t = grp.start; t + 2 < grp.start + grp.count && t + 2 < index.length; t += 3) {
          const v = [index[t] + offset, index[t + 1] + offset, index[t + 2] + offset];
          const ps = v.map((x) => this.part[x]);
          const p = ps[1] === ps[2] ? ps[1] : ps[0];
          if (p < 0) continue;
          tris[PARTS[p]].push(...v);
          for (const x of v) used[x] = 1;
        }
      }
      offset += n;
    });
    // Only vertices of measured triangles are skinned each frame.
    this.skinned = Uint32Array.from(used.reduce((a, u, i) => (u && a.push(i), a), []));
    this.positionAttribute = new THREE.BufferAttribute(this.positions, 3);
    this.update(); // rest pose (or whatever pose the VRM holds now)
    this.geometry = {};
    this.bvh = {};
    this.triangles = {};
    this.vertices = {};
    for (const p of PARTS) {
      const idx = Uint32Array.from(tris[p]);
      this.triangles[p] = idx.slice();
      this.vertices[p] = Uint32Array.from(new Set(tris[p]));
      if (idx.length === 0) continue;
      const geo = new THREE.BufferGeometry();
      geo.setAttribute("position", this.positionAttribute);
      geo.setIndex(new THREE.BufferAttribute(idx, 1));
      this.bvh[p] = new MeshBVH(geo);
      geo.boundsTree = this.bvh[p];
      this.geometry[p] = geo;
    }
    this.#refit();
    const body = PARTS.filter((p) => BODY_PARTS.has(p)).flatMap((p) => Array.from(this.triangles[p]));
    this.bodyTriangles = Uint32Array.from(body);
    this.hasBody = body.length > 0;
    if (this.hasBody) {
      const geo = new THREE.BufferGeometry();
      geo.setAttribute("position", this.positionAttribute);
      geo.setIndex(new THREE.BufferAttribute(Uint32Array.from(body), 1));
      this.bodyBvh = new MeshBVH(geo);
    }
    this.#buildClusters(clusterSize);
    this.#refreshClusters();
  }

  /** Skins the parts' vertices (world space) and refits the BVHs; call after posing + updateMatrixWorld. */
  update() {
    const v = new THREE.Vector3();
    const P = this.positions;
    for (const mesh of this.meshes) mesh.skeleton.update?.();
    for (let k = 0; k < this.skinned.length; k++) {
      const i = this.skinned[k];
      const mi = this.meshOf[i];
      const mesh = this.meshes[mi];
      mesh.getVertexPosition(i - this.offsets[mi], v).applyMatrix4(mesh.matrixWorld);
      P[3 * i] = v.x;
      P[3 * i + 1] = v.y;
      P[3 * i + 2] = v.z;
    }
    this.positionAttribute.needsUpdate = true;
    if (this.bvh) this.#refit();
  }

  // BVHs follow the moved vertices; so do the parts' bounding boxes, which three-mesh-bvh's
  // geometry-to-geometry distance reads for the other geometry (a stale box gives wrong gaps).
  #refit() {
    const P = this.positions;
    for (const p of Object.keys(this.bvh)) {
      this.bvh[p].refit();
      const box = (this.geometry[p].boundingBox ??= new THREE.Box3()).makeEmpty();
      const v = new THREE.Vector3();
      for (const i of this.vertices[p]) box.expandByPoint(v.set(P[3 * i], P[3 * i + 1], P[3 * i + 2]));
    }
    if (this.bodyBvh) this.bodyBvh.refit();
    this.#refreshClusters();
  }

  // Fast winding number (after Barill et al. 2018, "Fast winding numbers for soups and clouds"):
  // the body's triangles are grouped once by a grid over their rest centroids; per frame each
  // group has its area-weighted normal sum, centroid and radius; a group seen from farther than
  // farRatio x its radius contributes its dipole term, a near one its exact solid angles.
  #buildClusters(h) {
    const T = this.bodyTriangles;
    const P = this.positions;
    const cells = new Map();
    for (let t = 0; t < T.length; t += 3) {
      let cx = 0;
      let cy = 0;
      let cz = 0;
      for (let k = 0; k < 3; k++) (cx += P[3 * T[t + k]]), (cy += P[3 * T[t + k] + 1]), (cz += P[3 * T[t + k] + 2]);
      const key = `${Math.floor(cx / 3 / h)},${Math.floor(cy / 3 / h)},${Math.floor(cz / 3 / h)}`;
      if (!cells.has(key)) cells.set(key, []);
      cells.get(key).push(t);
    }
    this.clusters = [...cells.keys()].map((k) => Uint32Array.from(cells.get(k)));
    this.clusterData = new Float64Array(this.clusters.length * 7); // nx ny nz px py pz r
    // Coarse groups of 4 x 4 x 4 clusters, for a second level of the same test.
    const groups = new Map();
    [...cells.keys()].forEach((k, c) => {
      const g = k.split(",").map((x) => Math.floor(Number(x) / 4)).join(",");
      if (!groups.has(g)) groups.set(g, []);
      groups.get(g).push(c);
    });
    this.groups = [...groups.values()].map((cs) => Uint32Array.from(cs));
    this.groupData = new Float64Array(this.groups.length * 7);
  }

  #refreshClusters() {
    if (!this.clusters) return;
    const T = this.bodyTriangles;
    const P = this.positions;
    const D = this.clusterData;
    const box = (this.bodyBox ??= new THREE.Box3()).makeEmpty();
    for (let c = 0; c < this.clusters.length; c++) {
      let nx = 0, ny = 0, nz = 0, px = 0, py = 0, pz = 0, area = 0;
      for (const t of this.clusters[c]) {
        const a = 3 * T[t], b = 3 * T[t + 1], d = 3 * T[t + 2];
        const ux = P[b] - P[a], uy = P[b + 1] - P[a + 1], uz = P[b + 2] - P[a + 2];
        const vx = P[d] - P[a], vy = P[d + 1] - P[a + 1], vz = P[d + 2] - P[a + 2];
        const ax = 0.5 * (uy * vz - uz * vy), ay = 0.5 * (uz * vx - ux * vz), az = 0.5 * (ux * vy - uy * vx);
        const A = Math.hypot(ax, ay, az);
        nx += ax, ny += ay, nz += az, area += A;
        px += (A * (P[a] + P[b] + P[d])) / 3, py += (A * (P[a + 1] + P[b + 1] + P[d + 1])) / 3, pz += (A * (P[a + 2] + P[b + 2] + P[d + 2])) / 3;
      }
      if (area > 0) (px /= area), (py /= area), (pz /= area);
      let r = 0;
      for (const t of this.clusters[c]) {
        for (let k = 0; k < 3; k++) {
          const i = 3 * T[t + k];
          r = Math.max(r, Math.hypot(P[i] - px, P[i + 1] - py, P[i + 2] - pz));
        }
      }
      D.set([nx, ny, nz, px, py, pz, r], 7 * c);
      box.expandByPoint(new THREE.Vector3(px - r, py - r, pz - r)).expandByPoint(new THREE.Vector3(px + r, py + r, pz + r));
    }
    const G = this.groupData;
    for (let g = 0; g < this.groups.length; g++) {
      let nx = 0, ny = 0, nz = 0, px = 0, py = 0, pz = 0, wsum = 0;
      for (const c of this.groups[g]) {
        const o = 7 * c;
        const a = Math.hypot(D[o], D[o + 1], D[o + 2]) + 1e-12;
        nx += D[o], ny += D[o + 1], nz += D[o + 2];
        px += a * D[o + 3], py += a * D[o + 4], pz += a * D[o + 5], wsum += a;
      }
      px /= wsum, py /= wsum, pz /= wsum;
      let r = 0;
      for (const c of this.groups[g]) {
        const o = 7 * c;
        r = Math.max(r, Math.hypot(D[o + 3] - px, D[o + 4] - py, D[o + 5] - pz) + D[o + 6]);
      }
      G.set([nx, ny, nz, px, py, pz, r], 7 * g);
    }
  }

  /** Generalized winding number of the body surface (head, neck, chest, hips) at p, exact: ~1 inside, ~0 outside. */
  windingExact(x, y, z, triangles = this.bodyTriangles) {
    const P = this.positions;
    let w = 0;
    for (let t = 0; t < triangles.length; t += 3) {
      const a = 3 * triangles[t], b = 3 * triangles[t + 1], c = 3 * triangles[t + 2];
      w += triangleWinding(P[a] - x, P[a + 1] - y, P[a + 2] - z, P[b] - x, P[b + 1] - y, P[b + 2] - z, P[c] - x, P[c + 1] - y, P[c + 2] - z);
    }
    return w;
  }

  /** The same, with far triangle groups as dipoles (what measure() uses). */
  winding(x, y, z) {
    const P = this.positions;
    const T = this.bodyTriangles;
    const D = this.clusterData;
    const G = this.groupData;
    const far = this.farRatio;
    let w = 0;
    for (let g = 0; g < this.groups.length; g++) {
      const o = 7 * g;
      const dx = G[o + 3] - x, dy = G[o + 4] - y, dz = G[o + 5] - z;
      const d = Math.hypot(dx, dy, dz);
      if (d > far * G[o + 6]) {
        w += (G[o] * dx + G[o + 1] * dy + G[o + 2] * dz) / (4 * Math.PI * d * d * d);
        continue;
      }
      for (const c of this.groups[g]) w += this.#clusterWinding(c, x, y, z, D, P, T, far);
    }
    return w;
  }

  #clusterWinding(c, x, y, z, D, P, T, far) {
    const o = 7 * c;
    const dx = D[o + 3] - x, dy = D[o + 4] - y, dz = D[o + 5] - z;
    const d = Math.hypot(dx, dy, dz);
    if (d > far * D[o + 6]) return (D[o] * dx + D[o + 1] * dy + D[o + 2] * dz) / (4 * Math.PI * d * d * d);
    let w = 0;
    {
      for (const t of this.clusters[c]) {
        const a = 3 * T[t], b = 3 * T[t + 1], e = 3 * T[t + 2];
        w += triangleWinding(P[a] - x, P[a + 1] - y, P[a + 2] - z, P[b] - x, P[b + 1] - y, P[b + 2] - z, P[e] - x, P[e + 1] - y, P[e + 2] - z);
      }
    }
    return w;
  }

  /** How deep p is inside the body surface: 0 outside (winding number <= 0.5), else its distance to that surface (m). */
  depthAt(x, y, z, scratch = { point: new THREE.Vector3() }) {
    if (!this.hasBody || this.winding(x, y, z) <= 0.5) return 0;
    const hit = this.bodyBvh.closestPointToPoint(new THREE.Vector3(x, y, z), scratch);
    return hit ? hit.distance : 0;
  }

  /**
   * Gap (m) between two parts' surfaces: the smallest distance from a vertex of either to the
   * other's triangles (three-mesh-bvh point queries, each bounded by the best so far), which is
   * the triangle-to-triangle distance up to the edge-to-edge case (under a millimetre on these
   * meshes). A hand crossing a surface has vertices within half an edge of it. Infinity when
   * either part is missing. (three-mesh-bvh's closestPointToGeometry gives the same figures but
   * took 0.3-0.8 s per pair here.)
   */
  gap(partA, partB) {
    if (!this.bvh[partA] || !this.bvh[partB]) return Infinity;
    const P = this.positions;
    const q = new THREE.Vector3();
    const hit = { point: new THREE.Vector3() };
    let best = Infinity;
    // B's vertices to A's triangles, then,
    // near contact only (under 5 cm), A's vertices to B's triangles.
    for (const [from, to] of [[partB, partA], [partA, partB]]) {
      if (from === partA && best > 0.05) break;
      const bvh = this.bvh[to];
      const box = this.geometry[to].boundingBox;
      const verts = this.vertices[from];
      // Distances of every 16th vertex; the others are skipped when that vertex's distance
      // minus their distance to it (a lower bound of theirs) is no better than the best so far.
      const anchor = new Float64Array(Math.ceil(verts.length / 16));
      for (let k = 0; k < verts.length; k += 16) {
        const i = verts[k];
        q.set(P[3 * i], P[3 * i + 1], P[3 * i + 2]);
        // Bounded query: no triangle within the bound means a distance of at least the bound.
        const bound = best + 0.05;
        const h = bvh.closestPointToPoint(q, hit, 0, bound);
        anchor[k >> 4] = h ? h.distance : bound;
        if (h && h.distance < best) best = h.distance;
      }
      for (let k = 0; k < verts.length; k++) {
        if ((k & 15) === 0) continue;
        const i = verts[k];
        const a = 3 * verts[k & ~15];
        const near = anchor[k >> 4] - Math.hypot(P[3 * i] - P[a], P[3 * i + 1] - P[a + 1], P[3 * i + 2] - P[a + 2]);
        if (near >= best) continue;
        q.set(P[3 * i], P[3 * i + 1], P[3 * i + 2]);
        if (box.distanceToPoint(q) >= best) continue;
        const h = bvh.closestPointToPoint(q, hit, 0, best);
        if (h && h.distance < best) best = h.distance;
      }
    }
    return best;
  }

  /**
   * Deepest hand vertex inside the body (m) for `side`. Hand vertices outside the body's box are
   * skipped; each other vertex gets its distance d to the body surface (BVH), and a winding number
   * only when no earlier vertex's ball (a vertex with its own d: no surface inside it) holds it,
   * since every point of such a ball is on that vertex's side.
   */
  handDepth(side) {
    const verts = this.vertices[`${side}Hand`];
    if (!this.hasBody || !verts || verts.length === 0) return 0;
    const box = this.bodyBox;
    const P = this.positions;
    const q = new THREE.Vector3();
    const hit = { point: new THREE.Vector3() };
    const balls = []; // x, y, z, r, inside
    let deepest = 0;
    for (const i of verts) {
      const x = P[3 * i], y = P[3 * i + 1], z = P[3 * i + 2];
      if (x < box.min.x || y < box.min.y || z < box.min.z || x > box.max.x || y > box.max.y || z > box.max.z) continue;
      const h = this.bodyBvh.closestPointToPoint(q.set(x, y, z), hit);
      if (!h) continue;
      const d = h.distance;
      let inside = null;
      for (let b = 0; b < balls.length; b += 5) {
        const dx = balls[b] - x, dy = balls[b + 1] - y, dz = balls[b + 2] - z;
        if (dx * dx + dy * dy + dz * dz < balls[b + 3] * balls[b + 3]) {
          inside = balls[b + 4] === 1;
          break;
        }
      }
      if (inside === null) {
        inside = this.winding(x, y, z) > 0.5;
        balls.push(x, y, z, d, inside ? 1 : 0);
      }
      if (inside) deepest = Math.max(deepest, d);
    }
    return deepest;
  }

  /** Per hand: gaps to face, chest and other hand (m), deepest vertex inside head/torso (m). */
  measure() {
    const out = {};
    for (const side of ["left", "right"]) {
      const hand = `${side}Hand`;
      out[side] = {
        face: this.gap("head", hand),
        chest: this.gap("chest", hand),
        hand: this.gap(side === "left" ? "rightHand" : "leftHand", hand),
        depth: this.handDepth(side),
      };
    }
    return out;
  }

  /** Moves every vertex of `part` by (dx, dy, dz) (tests build touches by construction) and refits. */
  translatePart(part, dx, dy, dz) {
    const P = this.positions;
    for (const i of this.vertices[part]) (P[3 * i] += dx), (P[3 * i + 1] += dy), (P[3 * i + 2] += dz);
    this.#refit();
  }

  /** World position of vertex i. */
  point(i) {
    return [this.positions[3 * i], this.positions[3 * i + 1], this.positions[3 * i + 2]];
  }
}

const IDENTITY = new THREE.Matrix4();

/** The visual contact labels of a clip (eval/labels/contact-<clip>.json): { right: [...], left: [...] } per frame. */
export function readLabels(repo, clip) {
  return JSON.parse(fs.readFileSync(path.join(repo, "eval", "labels", `contact-${clip}.json`), "utf8"));
}

/** The ASL clips that have labels. */
export function labeledClips(repo) {
  return fs
    .readdirSync(path.join(repo, "eval", "labels"))
    .map((f) => f.match(/^contact-(.+)\.json$/)?.[1])
    .filter(Boolean)
    .sort();
}

/**
 * Drives `vrm` with `rig` over the clip's frames (rig.solve, applyToVRM, humanoid update), skins
 * and measures each frame. Returns per frame { left, right } measures plus `alignment` errors.
 */
export function runClip({ vrm, body, rig, applyToVRM, frames, onFrame }) {
  vrm.humanoid.resetNormalizedPose();
  const out = [];
  for (const f of frames) {
    const result = rig.solve({ timeMs: f.timeMs, hands: f.hands, pose: f.pose });
    applyToVRM(vrm, result);
    vrm.humanoid.update();
    vrm.scene.updateMatrixWorld(true);
    body.update();
    const m = body.measure();
    for (const side of ["left", "right"]) {
      const a = result.alignment?.[side];
      m[side].alignmentError = a && Number.isFinite(a.error) ? a.error : null;
      m[side].tracked = Boolean(result.hands?.[side]);
    }
    out.push(m);
    onFrame?.(m, result);
  }
  return out;
}

const median = (xs) => {
  if (xs.length === 0) return NaN;
  const s = [...xs].sort((a, b) => a - b);
  const k = s.length >> 1;
  return s.length % 2 ? s[k] : (s[k - 1] + s[k]) / 2;
};

/**
 * Scores of one clip's measures against its labels: for face / chest / hand touches the
 * hand-frames, the share within `touch` (m) of that surface and the median gap; false touches
 * (labeled none, within `touch` of face, chest or other hand); frames with a hand vertex deeper
 * than `deep` (m) inside head/torso and the deepest; the median alignment error on "none"
 * hand-frames (m); how many touch hand-frames had the hand tracked (`tracked` in the measures). Accumulates into `acc` when given (for totals).
 */
export function score(measures, labels, { touch = 0.02, deep = 0.01 } = {}, acc = newScore()) {
  measures.forEach((m, i) => {
    let deepFrame = false;
    for (const side of ["left", "right"]) {
      const l = labels[side][i];
      const g = m[side];
      if (l === "face" || l === "chest" || l === "hand") {
        acc[l].n++;
        if (g.tracked) acc[l].tracked++;
        if (g[l] <= touch) acc[l].hit++;
        // Issue 52: the touch lands on the skin, not sunk into the body (this hand no deeper than `deep`).
        if (g[l] <= touch && !(g.depth > deep)) acc[l].clean++;
        acc[l].gaps.push(g[l]);
      } else if (l === "none") {
        acc.none.n++;
        if (Math.min(g.face, g.chest, g.hand) <= touch) acc.none.hit++;
        if (g.alignmentError !== null) acc.alignment.push(g.alignmentError);
      }
      if (g.depth > deep) deepFrame = true;
      acc.maxDepth = Math.max(acc.maxDepth, g.depth);
    }
    acc.frames++;
    if (deepFrame) acc.deepFrames++;
  });
  return acc;
}

export function newScore() {
  const t = () => ({ n: 0, hit: 0, clean: 0, tracked: 0, gaps: [] });
  return { face: t(), chest: t(), hand: t(), none: t(), frames: 0, deepFrames: 0, maxDepth: 0, alignment: [] };
}

/** Score -> printable figures (percentages, mm). */
export function figures(s) {
  const pct = (t) => (t.n ? (100 * t.hit) / t.n : NaN);
  // cleanPct: within `touch` and this hand no more than `deep` inside head or torso (issue 52).
  const clean = (t) => (t.n ? (100 * t.clean) / t.n : NaN);
  return {
    face: { n: s.face.n, pct: pct(s.face), cleanPct: clean(s.face), medianMm: 1000 * median(s.face.gaps) },
    chest: { n: s.chest.n, pct: pct(s.chest), cleanPct: clean(s.chest), medianMm: 1000 * median(s.chest.gaps) },
    hand: { n: s.hand.n, pct: pct(s.hand), cleanPct: clean(s.hand), medianMm: 1000 * median(s.hand.gaps) },
    falseTouch: { n: s.none.n, pct: pct(s.none) },
    // Touch hand-frames where the rig had a tracked hand on that side (the others are held or eased).
    touchTracked: (() => {
      const n = s.face.n + s.chest.n + s.hand.n;
      return n ? (100 * (s.face.tracked + s.chest.tracked + s.hand.tracked)) / n : NaN;
    })(),
    deep: { frames: s.frames, pct: s.frames ? (100 * s.deepFrames) / s.frames : NaN, maxMm: 1000 * s.maxDepth },
    alignmentMedianMm: 1000 * median(s.alignment),
  };
}
