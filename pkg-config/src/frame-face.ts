// Packing a face tracker's face (issue 50) into the rig's flat input: a FaceLandmarkerResult
// (`faceLandmarks`, `faceBlendshapes`, `facialTransformationMatrixes`) or a
// HolisticLandmarkerResult's `faceLandmarks` / `faceBlendshapes` spread into the frame, a legacy
// Holistic result's `faceLandmarks` (one list of 468 or 478) or a legacy FaceMesh result's
// `multiFaceLandmarks`. Only the blendshapes (by name), the matrix and the few landmarks
// `LAYOUT.faceMesh` lists are read, the landmarks only in frames without blendshapes (and a
// rig's first frames); the first face drives the avatar.

import { at, describe, fail, isFiniteNumber, isObject, isView, notFinite, type Bag } from "./errors.js";
import { LAYOUT, LI } from "./layout.js";

const ARKIT_NAMES = LAYOUT.arkit;
const SHAPE_INDEX = new Map<string, number>(ARKIT_NAMES.map((name, i) => [name, i]));
const MESH = LAYOUT.faceMesh;

/** Whether the last `firstFace` found a list of faces (rather than one face's points). */
let nested = false;

/** The first face of a list of faces, or the list itself when it is one face's points; undefined for none. */
function firstFace(v: unknown, field: string): unknown {
  if (!Array.isArray(v)) fail(field, `must be an array of faces (MediaPipe's result), got ${describe(v)}`);
  nested = true;
  if (v.length === 0) return undefined;
  const first: unknown = v[0];
  if (Array.isArray(first) || isView(first)) return first;
  nested = false;
  return v;
}

/** The landmark list's name (built only for a message): `fieldName`, with `[face]` when face >= 0. */
function meshField(fieldName: string, face: number): string {
  return face < 0 ? fieldName : `${fieldName}[${face}]`;
}

function packMesh(list: unknown, fieldName: string, face: number, input: Float32Array): void {
  if (!Array.isArray(list)) fail(meshField(fieldName, face), `must be an array of 468 or 478 landmarks, got ${describe(list)}`);
  const n = list.length;
  if (n !== 468 && n !== 478) {
    fail(meshField(fieldName, face), `must have 468 or 478 landmarks (MediaPipe's face mesh), got ${n}`);
  }
  for (let k = 0; k < MESH.length; k++) {
    const i = MESH[k]!;
    const p: unknown = list[i];
    let x: unknown;
    let y: unknown;
    let z: unknown;
    if (Array.isArray(p)) {
      x = p[0];
      y = p[1];
      z = p[2];
    } else if (isObject(p)) {
      x = p.x;
      y = p.y;
      z = p.z;
    } else fail(`${meshField(fieldName, face)}[${i}]`, `must be {x, y, z} or [x, y, z], got ${describe(p)}`);
    if (!isFiniteNumber(x)) notFinite(x, `${meshField(fieldName, face)}[${i}].x`);
    if (!isFiniteNumber(y)) notFinite(y, `${meshField(fieldName, face)}[${i}].y`);
    if (!isFiniteNumber(z)) notFinite(z, `${meshField(fieldName, face)}[${i}].z`);
    // Normalized image coordinates: a face is within the image, give or take its size.
    if (x < -2 || x > 3 || y < -2 || y > 3) {
      fail(
        `${meshField(fieldName, face)}[${i}]`,
        `x and y must be normalized image coordinates (0..1 across the image), got ${x}, ${y}: pixels given? ` +
          "MediaPipe's faceLandmarks are normalized (divide pixels by the image's width and height)",
      );
    }
    const d = LI.faceMesh + 3 * k;
    input[d] = x;
    input[d + 1] = y;
    input[d + 2] = z as number;
  }
  input[LI.faceHasMesh] = 1;
}

/**
 * `byIndex`: a category carrying MediaPipe's `index` equal to its place in a list of 52 is
 * taken by it (its name checked in a rig's first frames only).
 */
function packShapes(list: unknown, field: string, input: Float32Array, byIndex: boolean): void {
  let categories: unknown = list;
  let sub = "";
  if (isObject(list) && !Array.isArray(list)) {
    categories = list.categories;
    sub = ".categories";
  }
  if (!Array.isArray(categories)) {
    fail(field + sub, `must be MediaPipe's blendshapes ({ categories: [{ categoryName, score }] }), got ${describe(categories)}`);
  }
  const shapes = LI.faceShapes;
  input.fill(0, shapes, shapes + LAYOUT.arkit.length);
  const n = categories.length;
  for (let k = 0; k < n; k++) {
    const c: unknown = categories[k];
    if (!isObject(c)) fail(`${field}${sub}[${k}]`, `must be a category { categoryName, score }, got ${describe(c)}`);
    let i: number;
    if (byIndex && c.index === k && n === 52) {
      // MediaPipe's category: its index is the blendshape's place in MediaPipe's order
      // (`_neutral`, then the ARKit names), its name not read (a string elsewhere in memory).
      if (k === 0) continue;
      i = k - 1;
    } else {
      i = shapeIndex(c.categoryName, n, k, field, sub);
      if (i < 0) continue;
    }
    const s = c.score;
    if (!isFiniteNumber(s)) notFinite(s, `${field}${sub}[${k}].score`);
    if (s < 0 || s > 1) fail(`${field}${sub}[${k}].score`, `must be in 0..1, got ${s}`);
    input[shapes + i] = s;
  }
  input[LI.faceHasShapes] = 1;
}

/** Category `k`'s place in `LAYOUT.arkit` found by its name; -1 to skip it (`_neutral`). */
function shapeIndex(catName: unknown, n: number, k: number, field: string, sub: string): number {
  // MediaPipe's order (`_neutral`, then the ARKit names): the name checked where it should be,
  // without a lookup.
  if (k > 0 && catName === ARKIT_NAMES[k - 1]) return k - 1;
  if (typeof catName === "string") {
    if (catName === "_neutral") return -1;
    const i = SHAPE_INDEX.get(catName);
    if (i === undefined) {
      fail(`${field}${sub}[${k}].categoryName`, `"${catName}" is not an ARKit blendshape name (MediaPipe's FaceLandmarker with outputFaceBlendshapes)`);
    }
    return i;
  }
  // No name, 52 categories: MediaPipe's order, _neutral then the ARKit names alphabetically.
  return n === 52 && k > 0 ? k - 1 : -1;
}

function packMatrix(m: unknown, field: string, input: Float32Array): void {
  let data: unknown = m;
  let sub = "";
  if (isObject(m) && !Array.isArray(m) && !isView(m)) {
    const rows = m.rows;
    const columns = m.columns;
    if ((rows !== undefined && rows !== 4) || (columns !== undefined && columns !== 4)) {
      fail(field, `must be a 4x4 matrix, got ${String(rows)}x${String(columns)}`);
    }
    data = m.data ?? m.elements;
    sub = m.data !== undefined ? ".data" : ".elements";
  }
  if (!(Array.isArray(data) || isView(data))) {
    fail(field + sub, `must be MediaPipe's matrix { rows: 4, columns: 4, data: [16 numbers, column-major] }, got ${describe(data)}`);
  }
  const a = data as Bag;
  const len = a.length as number;
  if (len !== 16) fail(field + sub, `must have 16 numbers (a 4x4 matrix, column-major), got ${String(len)}`);
  for (let k = 0; k < 16; k++) {
    const v = a[k];
    if (!isFiniteNumber(v)) notFinite(v, `${field}${sub}[${k}]`);
    input[LI.faceMatrix + k] = v;
  }
  input[LI.faceHasMatrix] = 1;
}

/**
 * Packs the frame's face-tracker fields, if any. Returns whether any was given (a result with
 * no face detected counts as given: its face is lost this frame). `checkAll`: also read the
 * landmarks of a frame with blendshapes (a rig's first frames), where the rig does not use them.
 */
export function packFaceTracking(frame: Bag, input: Float32Array, checkAll: boolean): boolean {
  input[LI.faceTracked] = 0;
  const landmarks = frame.faceLandmarks;
  const shapes = frame.faceBlendshapes;
  const matrices = frame.facialTransformationMatrixes;
  const multi = frame.multiFaceLandmarks;
  if (landmarks == null && shapes == null && matrices == null && multi == null) return false;
  input[LI.faceHasShapes] = 0;
  input[LI.faceHasMatrix] = 0;
  input[LI.faceHasMesh] = 0;
  const hasLandmarks = landmarks !== undefined && landmarks !== null;
  const hasMulti = multi !== undefined && multi !== null;
  let tracked = false;
  if (shapes !== undefined && shapes !== null) {
    at("frame.faceBlendshapes", -1, "");
    if (!Array.isArray(shapes)) fail("frame.faceBlendshapes", `must be an array (one entry per face), got ${describe(shapes)}`);
    if (shapes.length > 0) {
      const first: unknown = shapes[0];
      // One face's categories given without the list of faces.
      if (isObject(first) && "categoryName" in first) packShapes(shapes, "frame.faceBlendshapes", input, !checkAll);
      else packShapes(first, "frame.faceBlendshapes[0]", input, !checkAll);
      tracked = true;
    }
  }
  // The landmarks measure the weights only without blendshapes (the rig's fallback): with
  // them, the 20 points are read (and checked) only in a rig's first frames. Reading them
  // was half the face's cost in the object API (docs/measurements/2026-12-06-face.md).
  if ((hasLandmarks || hasMulti) && (!tracked || checkAll)) {
    const field = hasLandmarks ? "frame.faceLandmarks" : "frame.multiFaceLandmarks";
    at(field, -1, "");
    const face = firstFace(hasLandmarks ? landmarks : multi, field);
    if (face !== undefined) {
      packMesh(face, field, nested ? 0 : -1, input);
      tracked = true;
    }
  }
  if (matrices !== undefined && matrices !== null) {
    at("frame.facialTransformationMatrixes", -1, "");
    if (Array.isArray(matrices) && matrices.length === 16 && typeof matrices[0] === "number") {
      packMatrix(matrices, "frame.facialTransformationMatrixes", input);
    } else if (Array.isArray(matrices)) {
      if (matrices.length > 0) packMatrix(matrices[0], "frame.facialTransformationMatrixes[0]", input);
    } else packMatrix(matrices, "frame.facialTransformationMatrixes", input);
    if (input[LI.faceHasMatrix] === 1) tracked = true;
  }
  input[LI.faceTracked] = tracked ? 1 : 0;
  return true;
}

/** A FaceLandmarker result nested under `frame.face` (which is a body tracker's face points). */
export function faceResultAsFace(face: Bag): void {
  if ("faceLandmarks" in face || "faceBlendshapes" in face || "facialTransformationMatrixes" in face) {
    fail(
      "frame.face",
      "holds a FaceLandmarker result: spread it into the frame, rig.solve({ timeMs, ...faceResult }) " +
        "(frame.face is for a body tracker's face points: nose, leftEye, ...)",
    );
  }
}
