// A dense copy of a generated avatar, for timing `HandRig.fromVrm` on a mesh the size of a
// detailed commercial VRM (issue 52: the rig with its skin built in at most 50 ms for a
// 100k-triangle avatar; the generated ones have 27,036 triangles).
//
//   node eval/dense-avatar.mjs [--avatar FILE] [--min-triangles N] [--out FILE]
//
// Each triangle of every triangle primitive is split in four at its edges' midpoints, as many
// times as it takes to reach N triangles (default 100,000): a midpoint shared by two triangles
// (of any primitive) is one new vertex. Float attributes (positions, normals, UVs) take the
// edge's mean (normals made unit again); integer ones (joints, colours) and the skin weights
// take its first end's, so every new vertex is skinned as an existing one is. Morph targets,
// which the rig does not read, keep their deltas on the old vertices (the new ones get none).
// The skeleton, the VRM extension and every other part of the file are kept as they are.
// Prints the triangle and vertex counts; writes the file (default target/dense/<name>).

import fs from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";
import { packGlb, readGlbJson } from "../tools/avatars/gltf.mjs";

const here = path.dirname(fileURLToPath(import.meta.url));
const repo = path.resolve(here, "..");
const arg = (name, dflt) => {
  const i = process.argv.indexOf(name);
  return i > 0 ? process.argv[i + 1] : dflt;
};

const COMPONENTS = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4 };
const ARRAYS = { 5120: Int8Array, 5121: Uint8Array, 5122: Int16Array, 5123: Uint16Array, 5125: Uint32Array, 5126: Float32Array };

/** The GLB's binary chunk (a copy). */
function readBin(buf) {
  const jsonLength = buf.readUInt32LE(12);
  const at = 20 + jsonLength;
  const length = buf.readUInt32LE(at);
  return buf.subarray(at + 8, at + 8 + length);
}

/** An accessor's elements as a typed array (tightly packed copy), or throws on what this tool does not read. */
function readAccessor(json, bin, index) {
  const a = json.accessors[index];
  if (a.sparse || a.bufferView === undefined) throw new Error(`accessor ${index}: sparse or without data`);
  const view = json.bufferViews[a.bufferView];
  const Type = ARRAYS[a.componentType];
  const width = COMPONENTS[a.type];
  if (!Type || !width) throw new Error(`accessor ${index}: component type ${a.componentType} / ${a.type}`);
  const stride = view.byteStride ?? width * Type.BYTES_PER_ELEMENT;
  const out = new Type(a.count * width);
  const base = (view.byteOffset ?? 0) + (a.byteOffset ?? 0);
  const dv = new DataView(bin.buffer, bin.byteOffset, bin.byteLength);
  const get = {
    5120: (o) => dv.getInt8(o),
    5121: (o) => dv.getUint8(o),
    5122: (o) => dv.getInt16(o, true),
    5123: (o) => dv.getUint16(o, true),
    5125: (o) => dv.getUint32(o, true),
    5126: (o) => dv.getFloat32(o, true),
  }[a.componentType];
  for (let i = 0; i < a.count; i++) {
    for (let c = 0; c < width; c++) out[i * width + c] = get(base + i * stride + c * Type.BYTES_PER_ELEMENT);
  }
  return out;
}

/**
 * Splits every triangle of `file`'s triangle primitives in four until there are at least
 * `minTriangles`; returns { glb, triangles, vertices, before: { triangles, vertices } }.
 */
export function densify(bytes, minTriangles = 100_000) {
  const buf = Buffer.from(bytes);
  const json = readGlbJson(buf);
  const chunks = [Buffer.from(readBin(buf))];
  let binLength = chunks[0].length;
  const append = (typed) => {
    const pad = (4 - (binLength % 4)) % 4;
    if (pad) chunks.push(Buffer.alloc(pad)), (binLength += pad);
    const bytesOf = Buffer.from(typed.buffer, typed.byteOffset, typed.byteLength);
    json.bufferViews.push({ buffer: 0, byteOffset: binLength, byteLength: bytesOf.length });
    chunks.push(Buffer.from(bytesOf));
    binLength += bytesOf.length;
    return json.bufferViews.length - 1;
  };
  const bin = chunks[0];
  // Primitives grouped by their attribute set: they share vertices, so they share midpoints.
  const groups = new Map();
  for (const mesh of json.meshes ?? []) {
    for (const p of mesh.primitives) {
      if ((p.mode ?? 4) !== 4 || p.indices === undefined) continue;
      const key = JSON.stringify(p.attributes);
      if (!groups.has(key)) groups.set(key, []);
      groups.get(key).push(p);
    }
  }
  const count = () => {
    let t = 0;
    for (const prims of groups.values()) for (const p of prims) t += json.accessors[p.indices].count / 3;
    return t;
  };
  const vertexCount = () => [...groups.values()].reduce((n, prims) => n + json.accessors[prims[0].attributes.POSITION].count, 0);
  const before = { triangles: count(), vertices: vertexCount() };
  if (before.triangles === 0) throw new Error("no indexed triangle primitive");
  // Work on arrays in memory, level by level; write once at the end.
  const state = [...groups.values()].map((prims) => ({
    prims,
    attributes: Object.fromEntries(Object.entries(prims[0].attributes).map(([name, index]) => [name, readAccessor(json, bin, index)])),
    widths: Object.fromEntries(Object.entries(prims[0].attributes).map(([name, index]) => [name, COMPONENTS[json.accessors[index].type]])),
    vertices: json.accessors[prims[0].attributes.POSITION].count,
    indices: prims.map((p) => Uint32Array.from(readAccessor(json, bin, p.indices))),
  }));
  let triangles = before.triangles;
  while (triangles < minTriangles) {
    triangles = 0;
    for (const g of state) {
      const edges = new Map();
      const added = [];
      const mid = (a, b) => {
        const key = a < b ? a * 0x100000000 + b : b * 0x100000000 + a;
        let m = edges.get(key);
        if (m === undefined) {
          m = g.vertices + added.length;
          added.push([a, b]);
          edges.set(key, m);
        }
        return m;
      };
      g.indices = g.indices.map((ix) => {
        const out = new Uint32Array(ix.length * 4);
        for (let t = 0; t < ix.length; t += 3) {
          const [a, b, c] = [ix[t], ix[t + 1], ix[t + 2]];
          const [ab, bc, ca] = [mid(a, b), mid(b, c), mid(c, a)];
          out.set([a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca], t * 4);
        }
        triangles += out.length / 3;
        return out;
      });
      const n = g.vertices + added.length;
      for (const [name, old] of Object.entries(g.attributes)) {
        const w = g.widths[name];
        const next = new old.constructor(n * w);
        next.set(old);
        const mean = old instanceof Float32Array && name !== "WEIGHTS_0";
        added.forEach(([a, b], k) => {
          const o = (g.vertices + k) * w;
          for (let c = 0; c < w; c++) next[o + c] = mean ? 0.5 * (old[a * w + c] + old[b * w + c]) : old[a * w + c];
          if (name === "NORMAL") {
            const l = Math.hypot(next[o], next[o + 1], next[o + 2]) || 1;
            for (let c = 0; c < 3; c++) next[o + c] /= l;
          }
        });
        g.attributes[name] = next;
      }
      g.vertices = n;
    }
  }
  // New accessors for the grown attributes and indices; morph targets count the new vertices.
  for (const g of state) {
    const replaced = {};
    for (const [name, index] of Object.entries(g.prims[0].attributes)) {
      const old = json.accessors[index];
      const { bufferView: _v, byteOffset: _o, ...rest } = old;
      const a = { ...rest, bufferView: append(g.attributes[name]), count: g.vertices };
      if (name === "POSITION") {
        const p = g.attributes.POSITION;
        a.min = [0, 1, 2].map((c) => p.filter((_, i) => i % 3 === c).reduce((x, y) => Math.min(x, y)));
        a.max = [0, 1, 2].map((c) => p.filter((_, i) => i % 3 === c).reduce((x, y) => Math.max(x, y)));
      }
      json.accessors.push(a);
      replaced[name] = json.accessors.length - 1;
    }
    g.prims.forEach((p, k) => {
      p.attributes = { ...replaced };
      json.accessors.push({ bufferView: append(g.indices[k]), componentType: 5125, count: g.indices[k].length, type: "SCALAR" });
      p.indices = json.accessors.length - 1;
      for (const target of p.targets ?? []) {
        for (const [name, index] of Object.entries(target)) {
          const old = json.accessors[index];
          if (old.bufferView === undefined) {
            // Zeros, or sparse deltas on the old vertices: the same with more vertices.
            json.accessors.push({ ...old, count: g.vertices });
          } else {
            // Dense deltas: the new vertices' are 0.
            const deltas = new Float32Array(g.vertices * COMPONENTS[old.type]);
            deltas.set(readAccessor(json, bin, index));
            const { byteOffset: _o, ...rest } = old;
            json.accessors.push({ ...rest, bufferView: append(deltas), count: g.vertices });
          }
          target[name] = json.accessors.length - 1;
        }
      }
    });
  }
  json.buffers[0].byteLength = binLength;
  return {
    glb: packGlb(json, Buffer.concat(chunks)),
    triangles,
    vertices: state.reduce((n, g) => n + g.vertices, 0),
    before,
  };
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const file = arg("--avatar", path.join(repo, "tests", "fixtures", "avatars", "woman-vrm1.vrm"));
  const min = Number(arg("--min-triangles", 100_000));
  const out = arg("--out", path.join(repo, "target", "dense", path.basename(file).replace(/(\.\w+)$/, `-dense$1`)));
  const d = densify(fs.readFileSync(file), min);
  fs.mkdirSync(path.dirname(out), { recursive: true });
  fs.writeFileSync(out, d.glb);
  console.log(
    `${path.relative(repo, file)}: ${d.before.triangles} triangles, ${d.before.vertices} vertices -> ${path.relative(repo, out)}: ${d.triangles} triangles, ${d.vertices} vertices, ${(d.glb.length / 1e6).toFixed(1)} MB`,
  );
}
