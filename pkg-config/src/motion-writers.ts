// The writers of MotionRecorder (motion-recorder.ts): a VRM Animation file (glTF binary with
// `VRMC_vrm_animation` 1.0, https://github.com/vrm-c/vrm-specification/tree/master/specification/VRMC_vrm_animation-1.0)
// and BVH text, from the recorded frames (already in VRM 1.0's convention). No dependency: the
// glTF holds nodes, accessors and one animation, the GLB container is a header and two chunks.

import { describe, givenFields, isObject } from "./errors.js";
import type { HumanBoneName } from "./layout.js";

/** Options of `MotionRecorder.toVRMA`. */
export interface VRMAOptions {
  /**
   * Key reduction: a key is dropped where interpolating between the keys kept reproduces every
   * recorded rotation of that bone within this angle, radians (0.0087 = 0.5 degrees). Default 0:
   * every recorded frame is a key.
   */
  tolerance?: number;
}

/** Options of `MotionRecorder.toBVH`. */
export interface BVHOptions {
  /** Length unit of the offsets and the hips position: "cm" (default) or "m". */
  unit?: "cm" | "m";
  /** Frames per second of the BVH's constant frame time; default: from the recording's median frame interval. */
  fps?: number;
}

/** The recorded frames, VRM 1.0's convention (MotionRecorder's storage, read only). */
export interface MotionData {
  /** The avatar's bones, parent-first. */
  bones: readonly HumanBoneName[];
  /** Rest world positions of `bones`, 3 per bone, meters. */
  rest: Float64Array;
  /** The bones with rotations, parent-first. */
  driven: readonly HumanBoneName[];
  count: number;
  /** Milliseconds, `count` of them, increasing. */
  times: Float64Array;
  /** Per frame, per driven bone: x, y, z, w. */
  rotations: Float32Array;
  /** Per frame: the hips position, meters. */
  hips: Float32Array;
  restHips: Float64Array;
  /** The face (issue 50), when a frame had one: per frame the presets' weights, then yaw and pitch (degrees). */
  face?: { presets: readonly string[]; values: Float32Array } | undefined;
}

// VRM 1.0 humanoid: each bone's parent (VRMC_vrm-1.0/humanoid.md). A bone the avatar lacks is
// skipped: a bone hangs from its nearest existing ancestor (as in three-vrm's normalized rig).
const PARENT: { readonly [bone: string]: string } = (() => {
  const p: { [bone: string]: string } = {
    spine: "hips", chest: "spine", upperChest: "chest", neck: "upperChest", head: "neck",
    leftEye: "head", rightEye: "head", jaw: "head",
  };
  for (const side of ["left", "right"]) {
    Object.assign(p, {
      [`${side}UpperLeg`]: "hips", [`${side}LowerLeg`]: `${side}UpperLeg`, [`${side}Foot`]: `${side}LowerLeg`,
      [`${side}Toes`]: `${side}Foot`, [`${side}Shoulder`]: "upperChest", [`${side}UpperArm`]: `${side}Shoulder`,
      [`${side}LowerArm`]: `${side}UpperArm`, [`${side}Hand`]: `${side}LowerArm`,
      [`${side}ThumbMetacarpal`]: `${side}Hand`, [`${side}ThumbProximal`]: `${side}ThumbMetacarpal`,
      [`${side}ThumbDistal`]: `${side}ThumbProximal`,
    });
    for (const f of ["Index", "Middle", "Ring", "Little"]) {
      Object.assign(p, {
        [`${side}${f}Proximal`]: `${side}Hand`, [`${side}${f}Intermediate`]: `${side}${f}Proximal`,
        [`${side}${f}Distal`]: `${side}${f}Intermediate`,
      });
    }
  }
  return p;
})();

/** Per bone (index into `bones`): the index of its nearest existing ancestor, -1 for the hips. */
function parents(bones: readonly string[]): number[] {
  const index = new Map(bones.map((b, i) => [b, i]));
  return bones.map((b) => {
    let p = PARENT[b];
    while (p !== undefined && !index.has(p)) p = PARENT[p];
    return p === undefined ? -1 : index.get(p)!;
  });
}

function check(options: unknown, method: string, known: readonly string[]): { [k: string]: unknown } {
  if (options === undefined || options === null) return {};
  if (!isObject(options) || Array.isArray(options)) throw new TypeError(`${method}: options must be an object, got ${describe(options)}`);
  const given = givenFields(options, `${method}: options`);
  for (const k of Object.keys(given)) {
    if (!known.includes(k)) throw new TypeError(`${method}: unknown option ${JSON.stringify(k)} (known: ${known.join(", ")})`);
  }
  return given;
}

// ---------------------------------------------------------------------------------------------
// Quaternions (x, y, z, w), unit.

function angleBetween(r: Float32Array | Float64Array, a: number, b: Float64Array): number {
  const d = Math.abs(r[a]! * b[0]! + r[a + 1]! * b[1]! + r[a + 2]! * b[2]! + r[a + 3]! * b[3]!);
  return 2 * Math.acos(Math.min(1, d));
}

/** Spherical interpolation from r[a] to r[b] at t into out (the short way). */
function slerp(r: Float32Array, a: number, b: number, t: number, out: Float64Array): Float64Array {
  let bx = r[b]!, by = r[b + 1]!, bz = r[b + 2]!, bw = r[b + 3]!;
  const ax = r[a]!, ay = r[a + 1]!, az = r[a + 2]!, aw = r[a + 3]!;
  let cos = ax * bx + ay * by + az * bz + aw * bw;
  if (cos < 0) (cos = -cos), (bx = -bx), (by = -by), (bz = -bz), (bw = -bw);
  let s0 = 1 - t;
  let s1 = t;
  if (cos < 0.9999) {
    const angle = Math.acos(cos);
    const sin = Math.sin(angle);
    s0 = Math.sin(s0 * angle) / sin;
    s1 = Math.sin(s1 * angle) / sin;
  }
  out[0] = s0 * ax + s1 * bx;
  out[1] = s0 * ay + s1 * by;
  out[2] = s0 * az + s1 * bz;
  out[3] = s0 * aw + s1 * bw;
  const len = Math.hypot(out[0], out[1], out[2], out[3]);
  for (let c = 0; c < 4; c++) out[c]! /= len;
  return out;
}

/**
 * The frames kept as keys of driven bone `b`: greedy, from each kept key the furthest frame
 * such that every frame in between is within `tolerance` of the interpolation (windows of at
 * most 256 frames, so a long recording stays linear in time).
 */
function reduceKeys(d: MotionData, b: number, tolerance: number): number[] {
  const n = d.count;
  if (tolerance <= 0 || n <= 2) return Array.from({ length: n }, (_, i) => i);
  const stride = 4 * d.driven.length;
  const q = new Float64Array(4);
  const keys = [0];
  let a = 0;
  while (a < n - 1) {
    let end = a + 1;
    for (let c = a + 2; c < n && c - a <= 256; c++) {
      let ok = true;
      for (let i = a + 1; i < c && ok; i++) {
        const t = (d.times[i]! - d.times[a]!) / (d.times[c]! - d.times[a]!);
        slerp(d.rotations, a * stride + 4 * b, c * stride + 4 * b, t, q);
        ok = angleBetween(d.rotations, i * stride + 4 * b, q) <= tolerance;
      }
      if (!ok) break;
      end = c;
    }
    keys.push(end);
    a = end;
  }
  return keys;
}

// ---------------------------------------------------------------------------------------------
// VRM Animation (.vrma)

/** Accessors and buffer views over one binary buffer, each 4-byte aligned. */
class Bin {
  parts: Float32Array[] = [];
  length = 0;
  bufferViews: object[] = [];
  accessors: object[] = [];
  add(data: Float32Array, type: "SCALAR" | "VEC3" | "VEC4", minMax: boolean): number {
    this.bufferViews.push({ buffer: 0, byteOffset: this.length, byteLength: data.byteLength });
    this.parts.push(data);
    this.length += data.byteLength;
    const width = type === "SCALAR" ? 1 : type === "VEC3" ? 3 : 4;
    const accessor: { [k: string]: unknown } = {
      bufferView: this.bufferViews.length - 1,
      componentType: 5126, // FLOAT
      count: data.length / width,
      type,
    };
    if (minMax) {
      const min = new Array<number>(width).fill(Infinity);
      const max = new Array<number>(width).fill(-Infinity);
      for (let i = 0; i < data.length; i++) {
        const c = i % width;
        min[c] = Math.min(min[c]!, data[i]!);
        max[c] = Math.max(max[c]!, data[i]!);
      }
      accessor.min = min;
      accessor.max = max;
    }
    this.accessors.push(accessor);
    return this.accessors.length - 1;
  }
}

/** Seconds from the first frame as float32, frames whose float32 time would not increase dropped. */
function keyTimes(d: MotionData): { frames: number[]; seconds: number[] } {
  const frames: number[] = [];
  const seconds: number[] = [];
  const f32 = new Float32Array(1);
  let last = -Infinity;
  for (let i = 0; i < d.count; i++) {
    f32[0] = (d.times[i]! - d.times[0]!) / 1000;
    if (f32[0] <= last) continue;
    last = f32[0];
    frames.push(i);
    seconds.push(last);
  }
  return { frames, seconds };
}

export function writeVRMA(d: MotionData, options: VRMAOptions | undefined, generator: string): Uint8Array {
  const o = check(options, "toVRMA", ["tolerance"]);
  const tolerance = o.tolerance ?? 0;
  if (typeof tolerance !== "number" || !(tolerance >= 0 && tolerance < Math.PI)) {
    throw new RangeError(`toVRMA: options.tolerance must be an angle in radians, 0 or more (and below pi), got ${describe(tolerance)}`);
  }
  // Frames kept (distinct float32 times), as a MotionData of its own for the key reduction.
  const { frames, seconds } = keyTimes(d);
  const stride = 4 * d.driven.length;
  const kept: MotionData = { ...d, count: frames.length, times: new Float64Array(frames.map((i) => d.times[i]!)) };
  if (frames.length !== d.count) {
    kept.rotations = new Float32Array(frames.length * stride);
    kept.hips = new Float32Array(frames.length * 3);
    frames.forEach((i, k) => {
      kept.rotations.set(d.rotations.subarray(i * stride, (i + 1) * stride), k * stride);
      kept.hips.set(d.hips.subarray(3 * i, 3 * i + 3), 3 * k);
    });
  }

  // Nodes: the avatar's bones at rest, each translated from its parent, no rotation.
  const up = parents(d.bones);
  const nodes = d.bones.map((name, k) => {
    const node: { name: string; translation: number[]; children?: number[] } = { name, translation: [0, 0, 0] };
    const p = up[k]!;
    for (let c = 0; c < 3; c++) node.translation[c] = d.rest[3 * k + c]! - (p < 0 ? 0 : d.rest[3 * p + c]!);
    return node;
  });
  up.forEach((p, k) => {
    if (p >= 0) (nodes[p]!.children ??= []).push(k);
  });
  const roots = up.flatMap((p, k) => (p < 0 ? [k] : []));
  const nodeOf = new Map(d.bones.map((b, k) => [b, k]));
  const humanBones: { [name: string]: { node: number } } = {};
  d.bones.forEach((b, k) => (humanBones[b] = { node: k }));

  const bin = new Bin();
  const channels: object[] = [];
  const samplers: object[] = [];
  const allTimes = bin.add(new Float32Array(seconds), "SCALAR", true);
  d.driven.forEach((bone, b) => {
    const keys = reduceKeys(kept, b, tolerance);
    const input = keys.length === kept.count ? allTimes : bin.add(new Float32Array(keys.map((k) => seconds[k]!)), "SCALAR", true);
    const values = new Float32Array(4 * keys.length);
    keys.forEach((k, j) => values.set(kept.rotations.subarray(k * stride + 4 * b, k * stride + 4 * b + 4), 4 * j));
    const output = bin.add(values, "VEC4", false);
    samplers.push({ input, output, interpolation: "LINEAR" });
    channels.push({ sampler: samplers.length - 1, target: { node: nodeOf.get(bone)!, path: "rotation" } });
  });
  // The hips translation, when the hips left their rest position (1e-5 m).
  let moved = false;
  for (let i = 0; i < kept.count && !moved; i++) {
    for (let c = 0; c < 3; c++) if (Math.abs(kept.hips[3 * i + c]! - d.restHips[c]!) > 1e-5) moved = true;
  }
  if (moved) {
    const output = bin.add(kept.hips.slice(0, 3 * kept.count), "VEC3", false);
    samplers.push({ input: allTimes, output, interpolation: "LINEAR" });
    channels.push({ sampler: samplers.length - 1, target: { node: nodeOf.get("hips")!, path: "translation" } });
  }

  // The face: a node per preset (its translation's x the weight) and a look-at node (its rotation
  // three-vrm's yaw and pitch as Euler YXZ), roots of their own, every kept frame a key.
  const extension: { specVersion: string; humanoid: object; expressions?: object; lookAt?: { node: number } } = { specVersion: "1.0", humanoid: { humanBones } };
  if (d.face) {
    const { presets, values } = d.face;
    const stride = presets.length + 2;
    const preset: { [name: string]: { node: number } } = {};
    presets.forEach((name, e) => {
      const node = nodes.push({ name: `expression.${name}`, translation: [0, 0, 0] }) - 1;
      roots.push(node);
      preset[name] = { node };
      const out = new Float32Array(3 * frames.length);
      frames.forEach((i, k) => (out[3 * k] = values[i * stride + e]!));
      samplers.push({ input: allTimes, output: bin.add(out, "VEC3", false), interpolation: "LINEAR" });
      channels.push({ sampler: samplers.length - 1, target: { node, path: "translation" } });
    });
    const look = nodes.push({ name: "lookAt", translation: [0, 0, 0] }) - 1;
    roots.push(look);
    const q = new Float32Array(4 * frames.length);
    frames.forEach((i, k) => {
      const y = (values[i * stride + presets.length]! * Math.PI) / 360; // half angles
      const x = (values[i * stride + presets.length + 1]! * Math.PI) / 360;
      // Ry(yaw) * Rx(pitch)
      q[4 * k] = Math.cos(y) * Math.sin(x);
      q[4 * k + 1] = Math.sin(y) * Math.cos(x);
      q[4 * k + 2] = -Math.sin(y) * Math.sin(x);
      q[4 * k + 3] = Math.cos(y) * Math.cos(x);
    });
    samplers.push({ input: allTimes, output: bin.add(q, "VEC4", false), interpolation: "LINEAR" });
    channels.push({ sampler: samplers.length - 1, target: { node: look, path: "rotation" } });
    extension.expressions = { preset };
    extension.lookAt = { node: look };
  }

  const gltf = {
    asset: { version: "2.0", generator: `handrig ${generator} MotionRecorder` },
    extensionsUsed: ["VRMC_vrm_animation"],
    extensions: { VRMC_vrm_animation: extension },
    scene: 0,
    scenes: [{ nodes: roots }],
    nodes,
    animations: [{ name: "handrig", channels, samplers }],
    accessors: bin.accessors,
    bufferViews: bin.bufferViews,
    buffers: [{ byteLength: bin.length }],
  };
  return glb(JSON.stringify(gltf), bin);
}

/** The GLB container: 12-byte header, JSON chunk (space-padded), BIN chunk (zero-padded). */
function glb(json: string, bin: Bin): Uint8Array {
  // ASCII only (non-ASCII escaped as JSON allows), so each character is one byte of UTF-8.
  const ascii = json.replace(/[\u0080-\uffff]/g, (ch) => `\\u${ch.charCodeAt(0).toString(16).padStart(4, "0")}`);
  const text = new Uint8Array(ascii.length);
  for (let i = 0; i < ascii.length; i++) text[i] = ascii.charCodeAt(i);
  const jsonLength = (text.length + 3) & ~3;
  const binLength = (bin.length + 3) & ~3;
  const total = 12 + 8 + jsonLength + 8 + binLength;
  const out = new Uint8Array(total);
  const view = new DataView(out.buffer);
  view.setUint32(0, 0x46546c67, true); // "glTF"
  view.setUint32(4, 2, true);
  view.setUint32(8, total, true);
  view.setUint32(12, jsonLength, true);
  view.setUint32(16, 0x4e4f534a, true); // "JSON"
  out.set(text, 20);
  out.fill(0x20, 20 + text.length, 20 + jsonLength);
  let at = 20 + jsonLength;
  view.setUint32(at, binLength, true);
  view.setUint32(at + 4, 0x004e4942, true); // "BIN\0"
  at += 8;
  for (const part of bin.parts) {
    out.set(new Uint8Array(part.buffer, part.byteOffset, part.byteLength), at);
    at += part.byteLength;
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// BVH

const DEG = 180 / Math.PI;

/**
 * Euler angles (radians) of unit quaternion q for the rotation Rz(z) * Rx(x) * Ry(y) (BVH's
 * `Zrotation Xrotation Yrotation`), into out as [z, x, y]: of the two solutions, the one nearest
 * `prev` (each angle also moved by whole turns towards it), so that curves stay continuous.
 */
function eulerZXY(q: Float64Array, prev: Float64Array, out: Float64Array): void {
  const x = q[0]!, y = q[1]!, z = q[2]!, w = q[3]!;
  const m11 = 1 - 2 * (y * y + z * z), m12 = 2 * (x * y - w * z);
  const m21 = 2 * (x * y + w * z), m22 = 1 - 2 * (x * x + z * z);
  const m31 = 2 * (x * z - w * y), m32 = 2 * (y * z + w * x), m33 = 1 - 2 * (x * x + y * y);
  const c = Math.hypot(m31, m33);
  const ax = Math.atan2(m32, c);
  let az: number, ay: number;
  if (c > 1e-6) {
    ay = Math.atan2(-m31, m33);
    az = Math.atan2(-m12, m22);
  } else {
    // Gimbal lock (x = +-90 degrees): only z +- y is defined; keep y where it was.
    ay = prev[2]!;
    const zy = Math.atan2(m21, m11); // z + y (x = +90) or z - y (x = -90)
    az = ax > 0 ? zy - ay : zy + ay;
  }
  const near = (v: number, ref: number) => v + 2 * Math.PI * Math.round((ref - v) / (2 * Math.PI));
  const a = [near(az, prev[0]!), near(ax, prev[1]!), near(ay, prev[2]!)];
  const b = [near(az + Math.PI, prev[0]!), near(Math.PI - ax, prev[1]!), near(ay + Math.PI, prev[2]!)];
  const dist = (s: number[]) => Math.abs(s[0]! - prev[0]!) + Math.abs(s[1]! - prev[1]!) + Math.abs(s[2]! - prev[2]!);
  const best = dist(b) < dist(a) ? b : a;
  out[0] = best[0]!;
  out[1] = best[1]!;
  out[2] = best[2]!;
}

function median(values: number[]): number {
  const s = values.slice().sort((a, b) => a - b);
  return s.length === 0 ? NaN : s[s.length >> 1]!;
}

/** The most characters a BVH text may have (V8's longest string is 2^29 - 24). */
const BVH_MAX_CHARS = 2 ** 29 - 2 ** 20;

export function writeBVH(d: MotionData, options: BVHOptions | undefined): string {
  const o = check(options, "toBVH", ["unit", "fps"]);
  const unit = o.unit ?? "cm";
  if (unit !== "cm" && unit !== "m") throw new RangeError(`toBVH: options.unit must be "cm" or "m", got ${describe(unit)}`);
  const scale = unit === "cm" ? 100 : 1;
  let frameTime: number; // seconds
  if (o.fps !== undefined) {
    if (typeof o.fps !== "number" || !(o.fps > 0 && o.fps <= 1000)) throw new RangeError(`toBVH: options.fps must be a number in (0, 1000], got ${describe(o.fps)}`);
    frameTime = 1 / o.fps;
  } else {
    const gaps: number[] = [];
    for (let i = 1; i < d.count; i++) gaps.push(d.times[i]! - d.times[i - 1]!);
    const m = median(gaps);
    frameTime = m > 0 ? m / 1000 : 1 / 30;
  }

  const up = parents(d.bones);
  const children = d.bones.map(() => [] as number[]);
  up.forEach((p, k) => p >= 0 && children[p]!.push(k));
  const drivenIndex = new Map(d.driven.map((b, i) => [b, i]));
  const f = (v: number) => (Math.abs(v) < 5e-7 ? "0" : v.toFixed(6).replace(/\.?0+$/, ""));
  const lines: string[] = ["HIERARCHY"];
  const order: number[] = []; // joints in the order of the MOTION columns
  const offset = (k: number): number[] => {
    const p = up[k]!;
    return [0, 1, 2].map((c) => (d.rest[3 * k + c]! - (p < 0 ? 0 : d.rest[3 * p + c]!)) * scale);
  };
  const joint = (k: number, depth: number) => {
    const pad = "  ".repeat(depth);
    const root = up[k]! < 0;
    // The root at the origin: its position channels carry the hips position (absolute), which
    // importers that add the offset and those that do not read alike.
    const off = root ? [0, 0, 0] : offset(k);
    lines.push(`${pad}${root ? "ROOT" : "JOINT"} ${d.bones[k]}`, `${pad}{`, `${pad}  OFFSET ${off.map(f).join(" ")}`);
    lines.push(`${pad}  CHANNELS ${root ? "6 Xposition Yposition Zposition " : "3 "}Zrotation Xrotation Yrotation`);
    order.push(k);
    if (children[k]!.length === 0) {
      // End site: the bone continued by half its length (or 5 cm up where it has none).
      const own = offset(k);
      const len = Math.hypot(own[0]!, own[1]!, own[2]!);
      const end = len > 1e-4 * scale ? own.map((v) => v / 2) : [0, 0.05 * scale, 0];
      lines.push(`${pad}  End Site`, `${pad}  {`, `${pad}    OFFSET ${end.map(f).join(" ")}`, `${pad}  }`);
    }
    for (const c of children[k]!) joint(c, depth + 1);
    lines.push(`${pad}}`);
  };
  up.forEach((p, k) => p < 0 && joint(k, 0));

  const t0 = d.times[0]!;
  const span = (d.times[d.count - 1]! - t0) / 1000;
  const frames = Math.floor(span / frameTime + 1e-6) + 1;
  // The text must fit one JavaScript string (about 2^29 characters): a recording resampled at a
  // tiny frame time, or spanning years, would not (and would take as long to write). At most
  // about 12 characters per channel value.
  const channels = 3 * d.bones.length + 3;
  if (!(frames * (channels * 12 + 1) <= BVH_MAX_CHARS)) {
    throw new RangeError(
      `toBVH: ${frames} frames of ${channels} channels (${(span).toFixed(3)} s at ${(1 / frameTime).toPrecision(6)} fps) is more BVH text than a string holds; ` +
        "give options.fps a lower rate, or record less",
    );
  }
  lines.push("MOTION", `Frames: ${frames}`, `Frame Time: ${frameTime.toFixed(6)}`);
  const stride = 4 * d.driven.length;
  const q = new Float64Array(4);
  const euler = new Float64Array(3);
  const prev = d.bones.map(() => new Float64Array(3));
  const row: string[] = [];
  let seg = 0;
  for (let k = 0; k < frames; k++) {
    // Sample the recording at t0 + k * frameTime (between frames seg and seg + 1).
    const t = t0 + k * frameTime * 1000;
    while (seg < d.count - 1 && d.times[seg + 1]! <= t) seg++;
    const next = Math.min(seg + 1, d.count - 1);
    const dt = d.times[next]! - d.times[seg]!;
    const u = dt > 0 ? Math.min(1, Math.max(0, (t - d.times[seg]!) / dt)) : 0;
    row.length = 0;
    for (const j of order) {
      if (up[j]! < 0) {
        for (let c = 0; c < 3; c++) {
          const a = d.hips[3 * seg + c]!;
          row.push(f((a + (d.hips[3 * next + c]! - a) * u) * scale));
        }
      }
      const b = drivenIndex.get(d.bones[j]!);
      if (b === undefined) {
        row.push("0", "0", "0");
        continue;
      }
      slerp(d.rotations, seg * stride + 4 * b, next * stride + 4 * b, u, q);
      eulerZXY(q, prev[j]!, euler);
      prev[j]!.set(euler);
      row.push(f(euler[0]! * DEG), f(euler[1]! * DEG), f(euler[2]! * DEG));
    }
    lines.push(row.join(" "));
  }
  return `${lines.join("\n")}\n`;
}
