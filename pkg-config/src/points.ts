// Points and rotations read from user objects into a Float32Array (or any number array): lists
// of landmarks, [x, y, z] / {x, y, z} vectors and unit quaternions. Every element is checked
// (finite, within the coordinate limit) and a bad one is reported with its full path; a good
// list builds no strings and allocates nothing.

import {
  COORDINATE_LIMIT,
  fail,
  isFiniteNumber,
  isObject,
  isView,
  notFinite,
  outOfBounds,
  path,
  reading,
  within,
  describe,
  type Bag,
} from "./errors.js";

/** Where points are written: the rig's input view, a goal buffer or a plain array. */
export type NumberSink = { [index: number]: number };

/**
 * The common shapes without naming fields: `n` points, every one {x, y, z(, visibility)} or
 * every one [x, y, z(, visibility)], all finite (visibility in 0..1). Returns false at the first
 * point that is anything else, and packPoints' checking loop then reads the list again and names
 * the field (what was written so far is overwritten or the frame is rejected). One loop per
 * shape, so that each loop's property reads see one kind of element and V8 keeps them
 * monomorphic (a loop branching per point is the checking pass's).
 */
function packPlain(list: readonly unknown[], out: NumberSink, o: number, n: number, stride: number, withVisibility: boolean): boolean {
  const first = list[0];
  if (Array.isArray(first)) {
    for (let k = 0; k < n; k++) {
      const p: unknown = list[k];
      if (!Array.isArray(p)) return false;
      const m = p.length;
      const x: unknown = p[0];
      const y: unknown = p[1];
      const z: unknown = p[2];
      if (!(within(x, COORDINATE_LIMIT) && within(y, COORDINATE_LIMIT) && within(z, COORDINATE_LIMIT))) return false;
      const d = o + k * stride;
      out[d] = x;
      out[d + 1] = y;
      out[d + 2] = z;
      if (m === 3) {
        if (stride === 4) out[d + 3] = 1;
      } else if (m === 4 && withVisibility) {
        if (stride === 4) {
          const v: unknown = p[3];
          if (!(isFiniteNumber(v) && v >= 0 && v <= 1)) return false;
          out[d + 3] = v;
        }
      } else return false;
    }
    return true;
  }
  if (first === null || typeof first !== "object" || ArrayBuffer.isView(first)) return false;
  for (let k = 0; k < n; k++) {
    const p: unknown = list[k];
    if (p === null || typeof p !== "object" || Array.isArray(p) || ArrayBuffer.isView(p)) return false;
    const b = p as Bag;
    const x = b.x;
    const y = b.y;
    const z = b.z;
    if (!(within(x, COORDINATE_LIMIT) && within(y, COORDINATE_LIMIT) && within(z, COORDINATE_LIMIT))) return false;
    const d = o + k * stride;
    out[d] = x;
    out[d + 1] = y;
    out[d + 2] = z;
    if (stride === 4) {
      const v = b.visibility;
      if (v === undefined || v === null) out[d + 3] = 1;
      else if (isFiniteNumber(v) && v >= 0 && v <= 1) out[d + 3] = v;
      else return false;
    }
  }
  return true;
}

/**
 * Writes `n` points of `stride` floats from `list` at `out[o..]` (x y z, then visibility when
 * `stride` is 4). Accepts arrays of {x, y, z} or [x, y, z] (pose landmarks also
 * [x, y, z, visibility], `withVisibility`) and flat typed arrays / number arrays of n * 3. Each
 * element is read once (twice when packPlain turns the list down). The field's path is
 * `path(fa, fi, fb)`.
 */
export function packPoints(
  list: unknown,
  out: NumberSink,
  o: number,
  n: number,
  stride: number,
  fa: string,
  fi: number,
  fb: string,
  withVisibility: boolean = stride === 4,
): void {
  if (Array.isArray(list) && list.length === n && packPlain(list, out, o, n, stride, withVisibility)) return;
  const flatLength = n * 3;
  if (isView(list) || (Array.isArray(list) && list.length === flatLength && typeof list[0] === "number")) {
    const flat = list as Bag;
    const len = flat.length;
    if (len !== flatLength) {
      fail(path(fa, fi, fb), `flat array must have ${flatLength} numbers (${n} points x 3), got ${String(len)}`);
    }
    for (let k = 0; k < n; k++) {
      const d = o + k * stride;
      for (let c = 0; c < 3; c++) {
        const v = flat[k * 3 + c];
        if (!within(v, COORDINATE_LIMIT)) outOfBounds(v, COORDINATE_LIMIT, `${path(fa, fi, fb)}[${k * 3 + c}]`);
        out[d + c] = v;
      }
      if (stride === 4) out[d + 3] = 1;
    }
    return;
  }
  if (!Array.isArray(list)) {
    fail(path(fa, fi, fb), `must be an array of ${n} points or a Float32Array of ${flatLength}, got ${describe(list)}`);
  }
  const len = list.length;
  if (len !== n) fail(path(fa, fi, fb), `must have ${n} points, got ${len}`);
  for (let k = 0; k < n; k++) {
    const p: unknown = list[k];
    const d = o + k * stride;
    let x: unknown;
    let y: unknown;
    let z: unknown;
    let visibility: unknown;
    let array = false;
    if (Array.isArray(p) || isView(p)) {
      array = true;
      const a = p as Bag;
      const m = a.length;
      if (m !== 3 && !(withVisibility && m === 4)) {
        fail(`${path(fa, fi, fb)}[${k}]`, `must have 3 numbers [x, y, z]${withVisibility ? " (or 4 with visibility)" : ""}, got ${String(m)}`);
      }
      x = a[0];
      y = a[1];
      z = a[2];
      if (m === 4) visibility = a[3];
    } else if (isObject(p)) {
      x = p.x;
      y = p.y;
      z = p.z;
      if (stride === 4) visibility = p.visibility;
    } else {
      fail(`${path(fa, fi, fb)}[${k}]`, `must be [x, y, z] or {x, y, z} (three finite numbers), got ${describe(p)}`);
    }
    if (!within(x, COORDINATE_LIMIT)) outOfBounds(x, COORDINATE_LIMIT, `${path(fa, fi, fb)}[${k}]${array ? "[0]" : ".x"}`);
    if (!within(y, COORDINATE_LIMIT)) outOfBounds(y, COORDINATE_LIMIT, `${path(fa, fi, fb)}[${k}]${array ? "[1]" : ".y"}`);
    if (!within(z, COORDINATE_LIMIT)) outOfBounds(z, COORDINATE_LIMIT, `${path(fa, fi, fb)}[${k}]${array ? "[2]" : ".z"}`);
    out[d] = x;
    out[d + 1] = y;
    out[d + 2] = z;
    if (stride === 4) {
      if (visibility === undefined || visibility === null) out[d + 3] = 1;
      else {
        if (!isFiniteNumber(visibility) || visibility < 0 || visibility > 1) {
          const field = `${path(fa, fi, fb)}[${k}]${array ? "[3]" : ".visibility"}`;
          if (!isFiniteNumber(visibility)) notFinite(visibility, field);
          fail(field, `must be in 0..1, got ${visibility}`);
        }
        out[d + 3] = visibility;
      }
    }
  }
}

/**
 * [x, y, z] or {x, y, z} into out[o..o + 3], every number finite and within -limit..limit (by
 * default any finite number: Infinity is beyond Number.MAX_VALUE).
 */
export function readVec3(v: unknown, field: string, out: NumberSink, o: number, limit: number = Number.MAX_VALUE): void {
  if (Array.isArray(v) || isView(v)) {
    const a = v as Bag;
    if (a.length !== 3) fail(field, `must have 3 numbers [x, y, z], got ${String(a.length)}`);
    for (let c = 0; c < 3; c++) {
      const x = a[c];
      if (!within(x, limit)) outOfBounds(x, limit, `${field}[${c}]`);
      out[o + c] = x;
    }
  } else if (isObject(v)) {
    const x = v.x;
    const y = v.y;
    const z = v.z;
    if (!within(x, limit)) outOfBounds(x, limit, `${field}.x`);
    if (!within(y, limit)) outOfBounds(y, limit, `${field}.y`);
    if (!within(z, limit)) outOfBounds(z, limit, `${field}.z`);
    out[o] = x;
    out[o + 1] = y;
    out[o + 2] = z;
  } else {
    fail(field, `must be [x, y, z] or {x, y, z} (three finite numbers), got ${describe(v)}`);
  }
}

/** A unit quaternion [x, y, z, w] or {x, y, z, w} into out[o..o + 4]. */
export function readQuat(v: unknown, field: string, out: Float32Array, o: number): void {
  if (Array.isArray(v) || isView(v)) {
    const a = v as Bag;
    if (a.length !== 4) fail(field, `must be a quaternion [x, y, z, w], got ${String(a.length)} numbers`);
    for (let c = 0; c < 4; c++) {
      // Read as before the TypeScript port: checked, then read again to store.
      if (!isFiniteNumber(a[c])) notFinite(a[c], `${field}[${c}]`);
      out[o + c] = a[c] as number;
    }
  } else if (isObject(v)) {
    const x = v.x;
    const y = v.y;
    const z = v.z;
    const w = v.w;
    if (!isFiniteNumber(x)) notFinite(x, `${field}.x`);
    if (!isFiniteNumber(y)) notFinite(y, `${field}.y`);
    if (!isFiniteNumber(z)) notFinite(z, `${field}.z`);
    if (!isFiniteNumber(w)) notFinite(w, `${field}.w`);
    out[o] = x;
    out[o + 1] = y;
    out[o + 2] = z;
    out[o + 3] = w;
  } else {
    fail(field, `must be a quaternion [x, y, z, w], got ${describe(v)}`);
  }
  const len = Math.sqrt(out[o]! * out[o]! + out[o + 1]! * out[o + 1]! + out[o + 2]! * out[o + 2]! + out[o + 3]! * out[o + 3]!);
  if (Math.abs(len - 1) > 1e-2) fail(field, `must be a unit quaternion [x, y, z, w] (length ${len.toPrecision(3)})`);
}

/** A fresh [x, y, z] from [x, y, z] or {x, y, z} (setup-time reads: options, ChainSolver). */
export function point3(v: unknown, field: string, limit: number = Number.MAX_VALUE): [number, number, number] {
  reading.part = field;
  const out: [number, number, number] = [0, 0, 0];
  readVec3(v, field, out, 0, limit);
  return out;
}
