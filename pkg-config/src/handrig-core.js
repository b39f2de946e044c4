// The idiomatic JS layer over the raw wasm-bindgen `HandRig` (rapier.js style: the wasm class
// stays thin, users get this one). Shared by every entry point: build.mjs wraps this file as
// an ES module (browsers, bundlers) or CommonJS (Node), so it has no imports or exports itself;
// build.mjs defines `LAYOUT` (the flat frame layout, read from the built wasm) before it.
//
// Per frame nothing crosses the wasm boundary but numbers. The rig owns a flat input and
// output buffer in wasm memory (`LAYOUT`, src/flat.rs); this file
// - packs MediaPipe's result shapes into the input through a Float32Array view (reading every
//   user property once, in JavaScript: a throwing getter or a lying `length` throws here, with
//   the field named, before wasm is entered, so it can never leave the rig half-borrowed);
// - calls `solveFlat(timeMs)`;
// - builds the result object from the output view, reusing one object per rig (or the
//   caller's) so that a frame allocates nothing once warmed up.
// It also turns every failure into an `Error` naming the field, checks options against
// `optionDescriptions()` (nested objects or dotted paths), and reads rest poses.

/* global LAYOUT */
/* exported createHandRigApi */
// eslint-disable-next-line no-unused-vars
function createHandRigApi(raw, isReady) {
  "use strict";
  const RawHandRig = raw.HandRig;
  const L = LAYOUT;
  const LI = L.input;
  const LO = L.output;
  const BONES = L.bones;
  const BONE_COUNT = BONES.length;
  const BONE_INDEX = new Map(BONES.map((name, i) => [name, i]));
  const HAND_POINTS = 21;
  const POSE_POINTS = 33;
  const MAX_HANDS = (LI.pose - LI.hands) / LI.handStride;
  const SIDES = ["left", "right"];
  // The torso section's bones and the body section's joints, in their flat order.
  const TORSO_BONES = L.torsoBones;
  const TORSO_INDEX = new Map(TORSO_BONES.map((name, i) => [name, i]));
  const TORSO_FIELDS = TORSO_BONES.map((name) => `frame.torso.${name}`);
  const BODY_JOINTS = L.bodyJoints;
  const BODY_INDEX = new Map(BODY_JOINTS.map((name, i) => [name, i]));
  const BODY_FIELDS = BODY_JOINTS.map((name) => ({
    joint: `frame.body.${name}`,
    confidence: `frame.body.${name}.confidence`,
    confidenceAt: `frame.body.${name}[3]`,
  }));
  // Constructor token for wrapping a raw rig made by a static factory (fromVrm).
  const ADOPT = {};

  function ensureReady(what) {
    if (!isReady()) {
      throw new Error(
        `handrig: ${what} was called before the WebAssembly module was initialized. ` +
          "In browsers and bundlers, `await init()` (the package's default export) first.",
      );
    }
  }

  function asError(e) {
    if (e instanceof Error) return e;
    // Errors from another realm (iframe, vm context) are still errors: keep them.
    if (e !== null && typeof e === "object" && typeof e.message === "string") return e;
    return new Error(typeof e === "string" ? e : `handrig: ${String(e)}`);
  }

  // ---------------------------------------------------------------------------------------
  // Input problems: an Error whose message starts with the field's path.
  //
  // Paths are passed as pieces (`fa`, `fi`, `fb`: "frame.hands", 1, ".worldLandmarks") and
  // joined only when something is wrong, so a good frame builds no strings. `where` remembers
  // the part of the frame being read, to name it when a user getter throws.

  class FieldError extends Error {}

  function path(fa, fi, fb) {
    return fi < 0 ? fa + fb : `${fa}[${fi}]${fb}`;
  }

  function fail(field, problem) {
    throw new FieldError(`${field}: ${problem}`);
  }

  const where = { a: "frame", i: -1, b: "" };
  function at(a, i, b) {
    where.a = a;
    where.i = i;
    where.b = b;
  }

  function describe(v) {
    if (v === null) return "null";
    if (v === undefined) return "undefined";
    if (Array.isArray(v)) return `an array of ${v.length}`;
    if (ArrayBuffer.isView(v)) return `a ${tag(v)} of ${v.length}`;
    if (typeof v === "object") return tag(v) === "Object" ? "an object" : `a ${tag(v)}`;
    if (typeof v === "string") return `string ${JSON.stringify(v.length > 40 ? `${v.slice(0, 40)}...` : v)}`;
    return `${typeof v} ${String(v)}`;
  }

  function tag(v) {
    return Object.prototype.toString.call(v).slice(8, -1);
  }

  function isObject(v) {
    return v !== null && typeof v === "object";
  }

  function isFiniteNumber(v) {
    return typeof v === "number" && v - v === 0;
  }

  // A frame's points (meters; image landmarks in image units) lie within this of the origin,
  // as Rust checks (rig.rs COORDINATE_LIMIT): larger finite numbers overflow the solvers.
  const COORDINATE_LIMIT = 1000;
  const RANGE_MESSAGE = `must be within -${COORDINATE_LIMIT}..${COORDINATE_LIMIT} (meters; image landmarks in image units)`;

  function notFinite(v, field) {
    fail(field, typeof v === "number" ? "must be a finite number" : `must be a number, got ${describe(v)}`);
  }

  // A finite number, for fields read once per frame (the path is a constant string).
  function finite(v, field) {
    if (!isFiniteNumber(v)) notFinite(v, field);
    return v;
  }

  // The common shapes without naming fields: `n` points, every one {x, y, z(, visibility)} or
  // every one [x, y, z(, visibility)], all finite (visibility in 0..1). Returns false at the
  // first point that is anything else, and packPoints' checking loop then reads the list again
  // and names the field (what was written so far is overwritten or the frame is rejected).
  // One loop per shape, so that each loop's property reads see one kind of element and V8
  // keeps them monomorphic (a loop branching per point is the checking pass's).
  function packPlain(list, out, o, n, stride, withVisibility) {
    const first = list[0];
    if (Array.isArray(first)) {
      for (let k = 0; k < n; k++) {
        const p = list[k];
        if (!Array.isArray(p)) return false;
        const m = p.length;
        const x = p[0];
        const y = p[1];
        const z = p[2];
        if (!(within(x, COORDINATE_LIMIT) && within(y, COORDINATE_LIMIT) && within(z, COORDINATE_LIMIT))) return false;
        const d = o + k * stride;
        out[d] = x;
        out[d + 1] = y;
        out[d + 2] = z;
        if (m === 3) {
          if (stride === 4) out[d + 3] = 1;
        } else if (m === 4 && withVisibility) {
          if (stride === 4) {
            const v = p[3];
            if (!(isFiniteNumber(v) && v >= 0 && v <= 1)) return false;
            out[d + 3] = v;
          }
        } else return false;
      }
      return true;
    }
    if (first === null || typeof first !== "object" || ArrayBuffer.isView(first)) return false;
    for (let k = 0; k < n; k++) {
      const p = list[k];
      if (p === null || typeof p !== "object" || Array.isArray(p) || ArrayBuffer.isView(p)) return false;
      const x = p.x;
      const y = p.y;
      const z = p.z;
      if (!(within(x, COORDINATE_LIMIT) && within(y, COORDINATE_LIMIT) && within(z, COORDINATE_LIMIT))) return false;
      const d = o + k * stride;
      out[d] = x;
      out[d + 1] = y;
      out[d + 2] = z;
      if (stride === 4) {
        const v = p.visibility;
        if (v === undefined || v === null) out[d + 3] = 1;
        else if (isFiniteNumber(v) && v >= 0 && v <= 1) out[d + 3] = v;
        else return false;
      }
    }
    return true;
  }

  // Writes `n` points of `stride` floats from `list` at `out[o..]` (x y z, then visibility
  // when `stride` is 4). Accepts arrays of {x, y, z} or [x, y, z] (pose landmarks also
  // [x, y, z, visibility], `withVisibility`) and flat typed arrays / number arrays of n * 3.
  // Each element is read once (twice when packPlain turns the list down).
  function packPoints(list, out, o, n, stride, fa, fi, fb, withVisibility = stride === 4) {
    if (Array.isArray(list) && list.length === n && packPlain(list, out, o, n, stride, withVisibility)) return;
    const flatLength = n * 3;
    if (ArrayBuffer.isView(list) || (Array.isArray(list) && list.length === flatLength && typeof list[0] === "number")) {
      const len = list.length;
      if (len !== flatLength) {
        fail(path(fa, fi, fb), `flat array must have ${flatLength} numbers (${n} points x 3), got ${len}`);
      }
      for (let k = 0; k < n; k++) {
        const d = o + k * stride;
        for (let c = 0; c < 3; c++) {
          const v = list[k * 3 + c];
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
      const p = list[k];
      const d = o + k * stride;
      let x;
      let y;
      let z;
      let visibility;
      let array = false;
      if (Array.isArray(p) || ArrayBuffer.isView(p)) {
        array = true;
        const m = p.length;
        if (m !== 3 && !(withVisibility && m === 4)) {
          fail(`${path(fa, fi, fb)}[${k}]`, `must have 3 numbers [x, y, z]${withVisibility ? " (or 4 with visibility)" : ""}, got ${m}`);
        }
        x = p[0];
        y = p[1];
        z = p[2];
        if (m === 4) visibility = p[3];
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

  // Whether `v` is a number within -limit..limit (the frame's points: COORDINATE_LIMIT;
  // ChainSolver's: CHAIN_LIMIT, 1e9). NaN fails the comparison.
  function within(v, limit) {
    return typeof v === "number" && Math.abs(v) <= limit;
  }

  // Throws the error for a `v` that is not `within(v, limit)`. Callers build `field` only then:
  // a template string per good number would be garbage every frame.
  function outOfBounds(v, limit, field) {
    if (!isFiniteNumber(v)) notFinite(v, field);
    fail(field, limit === COORDINATE_LIMIT ? `${RANGE_MESSAGE}, got ${v}` : `must be within -1e9..1e9, got ${v}`);
  }

  // [x, y, z] or {x, y, z} into out[o..o + 3], every number finite and within -limit..limit
  // (by default any finite number: Infinity is beyond Number.MAX_VALUE).
  function readVec3(v, field, out, o, limit = Number.MAX_VALUE) {
    if (Array.isArray(v) || ArrayBuffer.isView(v)) {
      if (v.length !== 3) fail(field, `must have 3 numbers [x, y, z], got ${v.length}`);
      for (let c = 0; c < 3; c++) {
        const x = v[c];
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

  function readQuat(v, field, out, o) {
    if (Array.isArray(v) || ArrayBuffer.isView(v)) {
      if (v.length !== 4) fail(field, `must be a quaternion [x, y, z, w], got ${v.length} numbers`);
      for (let c = 0; c < 4; c++) {
        if (!isFiniteNumber(v[c])) notFinite(v[c], `${field}[${c}]`);
        out[o + c] = v[c];
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
    const len = Math.sqrt(out[o] * out[o] + out[o + 1] * out[o + 1] + out[o + 2] * out[o + 2] + out[o + 3] * out[o + 3]);
    if (Math.abs(len - 1) > 1e-2) fail(field, `must be a unit quaternion [x, y, z, w] (length ${len.toPrecision(3)})`);
  }

  // "Left" / "Right" (either case), a category { categoryName | label, score }, or
  // tasks-vision's [category] (the first, best one). Returns 0 for "Left", 1 for "Right", plus 2
  // when the category carried a score, which is then written to `input[scoreAt]` (scores go
  // straight into the Float32Array: a double kept in a JS array or returned would be boxed, a
  // per-frame allocation).
  function readHandedness(v, fa, fi, fb, input, scoreAt) {
    let item = v;
    if (Array.isArray(v)) {
      if (v.length === 0) fail(path(fa, fi, fb), "is an empty array (expected [{ categoryName, score }])");
      item = v[0];
    }
    let label = item;
    let scored = 0;
    if (isObject(item)) {
      const name = item.categoryName;
      label = name !== undefined && name !== null ? name : item.label;
      const score = item.score;
      if (score !== undefined && score !== null) {
        if (!isFiniteNumber(score)) notFinite(score, `${path(fa, fi, fb)}.score`);
        input[scoreAt] = score;
        scored = 2;
      }
    }
    if (label === "Left" || label === "left") return scored;
    if (label === "Right" || label === "right") return scored + 1;
    if (typeof label !== "string") {
      fail(path(fa, fi, fb), `must be "Left" or "Right" (or a category { categoryName, score }), got ${describe(label)}`);
    }
    return fail(path(fa, fi, fb), `must be "Left" or "Right", got ${JSON.stringify(label)}`);
  }

  function checkScore(score, fa, fi, fb) {
    if (!isFiniteNumber(score)) notFinite(score, path(fa, fi, fb));
    if (score < 0 || score > 1) fail(path(fa, fi, fb), `must be in 0..1, got ${score}`);
  }

  // One hand into slot `slot`: world and/or image landmarks (either may be absent, not both).
  // Field paths: `path(wa, fi, wb)` and `path(ia, fi, ib)`.
  function packHand(input, slot, label, world, image, fi, wa, wb, ia, ib) {
    const o = LI.hands + slot * LI.handStride;
    const H = LI.hand;
    input[o + H.handedness] = label;
    const hasImage = image !== undefined && image !== null;
    const hasWorld = world !== undefined && world !== null;
    if (!hasWorld && !hasImage) {
      fail(path(wa, fi, wb), "is missing (21 points [x, y, z] in meters, or image landmarks)");
    }
    if (hasImage) {
      at(ia, fi, ib);
      packPoints(image, input, o + H.image, HAND_POINTS, 3, ia, fi, ib);
    }
    if (hasWorld) {
      at(wa, fi, wb);
      packPoints(world, input, o + H.world, HAND_POINTS, 3, wa, fi, wb);
    }
    input[o + H.hasWorld] = hasWorld ? 1 : 0;
    input[o + H.hasImage] = hasImage ? 1 : 0;
  }

  // handrig's own shape: [{ handedness, score?, worldLandmarks, landmarks? }].
  function packHandList(hands, input) {
    at("frame.hands", -1, "");
    const n = hands.length;
    if (!(n <= MAX_HANDS)) fail("frame.hands", `at most ${MAX_HANDS} hands per frame, got ${n}`);
    for (let i = 0; i < n; i++) {
      at("frame.hands", i, "");
      const h = hands[i];
      if (!isObject(h) || Array.isArray(h)) {
        fail(path("frame.hands", i, ""), `must be a hand object { handedness, worldLandmarks }, got ${describe(h)}`);
      }
      const hv = h.handedness;
      if (hv === undefined || hv === null) fail(path("frame.hands", i, ".handedness"), 'is missing ("Left" or "Right")');
      const scoreAt = LI.hands + i * LI.handStride + LI.hand.score;
      const label = readHandedness(hv, "frame.hands", i, ".handedness", input, scoreAt);
      const s = h.score;
      if (s !== undefined && s !== null) {
        checkScore(s, "frame.hands", i, ".score");
        input[scoreAt] = s;
      } else if (label & 2) checkScore(input[scoreAt], "frame.hands", i, ".handedness.score");
      else input[scoreAt] = 1;
      packHand(input, i, label & 1, h.worldLandmarks, h.landmarks, i, "frame.hands", ".worldLandmarks", "frame.hands", ".landmarks");
    }
    return n;
  }

  // Whether `v` is a list of landmark lists ([[...points], ...]) rather than one list of
  // points: its first element is itself a list.
  function isListOfLists(v) {
    if (!Array.isArray(v) || v.length === 0) return false;
    const first = v[0];
    return ArrayBuffer.isView(first) || (Array.isArray(first) && first.length > 0 && typeof first[0] !== "number");
  }

  // A per-hand list of a result shape (one landmark list per hand): as many as labels.
  function checkPerHandList(list, listPath, n, labelPath) {
    if (list === undefined || list === null) return;
    if (!Array.isArray(list)) fail(listPath, `must be an array (one list per hand), got ${describe(list)}`);
    if (list.length !== n) fail(listPath, `has ${list.length} hand(s) but ${labelPath} has ${n}: one entry per hand`);
  }

  // Field paths of MediaPipe result shapes, made once (a good frame builds no strings).
  const RESULT_FIELDS = ["multiHandedness", "multiHandWorldLandmarks", "multiHandLandmarks", "handedness",
    "handednesses", "worldLandmarks", "landmarks", "leftHandLandmarks", "rightHandLandmarks",
    "leftHandWorldLandmarks", "rightHandWorldLandmarks"];
  const RESULT_PATHS = {};
  for (const name of ["frame", "frame.hands"]) {
    const p = {};
    for (const f of RESULT_FIELDS) p[f] = `${name}.${f}`;
    RESULT_PATHS[name] = p;
  }

  // tasks-vision HandLandmarkerResult, legacy Hands or legacy Holistic results (`name`:
  // "frame.hands" or "frame"). Returns the number of hands packed, or -1 when `r` has none of
  // their fields.
  function packResultShape(r, input, name) {
    const P = RESULT_PATHS[name];
    at(name, -1, "");
    let labels;
    let labelPath;
    let world;
    let worldPath;
    let image;
    let imagePath;
    const multi = r.multiHandedness;
    if (multi !== undefined && multi !== null) {
      labels = multi;
      labelPath = P.multiHandedness;
      world = r.multiHandWorldLandmarks;
      worldPath = P.multiHandWorldLandmarks;
      image = r.multiHandLandmarks;
      imagePath = P.multiHandLandmarks;
    } else {
      world = r.worldLandmarks;
      worldPath = P.worldLandmarks;
      image = r.landmarks;
      imagePath = P.landmarks;
      const h = r.handedness;
      if (h !== undefined && h !== null) {
        labels = h;
        labelPath = P.handedness;
      } else {
        const hs = r.handednesses;
        if (hs !== undefined && hs !== null) {
          labels = hs;
          labelPath = P.handednesses;
        }
      }
    }
    const hasWorld = world !== undefined && world !== null;
    const hasImage = image !== undefined && image !== null;
    if (labels === undefined) {
      if (hasWorld || hasImage) {
        fail(
          P.handedness,
          "is missing: a HandLandmarker result needs `handedness` to tell the hands apart" +
            (name === "frame" ? " (a PoseLandmarker result goes in frame.pose)" : ""),
        );
      }
      // Holistic legacy: image landmarks per side. Holistic names the hands by the subject's
      // side, like its pose (`leftHandLandmarks` is the hand at the pose's left wrist); the
      // Hands solutions label them as if the image were mirrored. So `leftHandLandmarks` is the
      // hand Hands would label "Right", and the other way round.
      // tasks-vision's HolisticLandmarker gives the same sides as lists of hands (none or one:
      // `[]` when the hand is not seen), with world landmarks beside them.
      const left = r.leftHandLandmarks;
      const right = r.rightHandLandmarks;
      let n = 0;
      n = packHolisticHand(input, n, 1, left, r.leftHandWorldLandmarks, P.leftHandLandmarks, P.leftHandWorldLandmarks);
      n = packHolisticHand(input, n, 0, right, r.rightHandWorldLandmarks, P.rightHandLandmarks, P.rightHandWorldLandmarks);
      if (n === 0 && left === undefined && right === undefined) return -1;
      return n;
    }
    if (!Array.isArray(labels)) fail(labelPath, `must be an array, got ${describe(labels)}`);
    const n = labels.length;
    if (!(n <= MAX_HANDS)) fail(labelPath, `at most ${MAX_HANDS} hands per frame, got ${n}`);
    checkPerHandList(world, worldPath, n, labelPath);
    checkPerHandList(image, imagePath, n, labelPath);
    for (let i = 0; i < n; i++) {
      at(labelPath, i, "");
      const scoreAt = LI.hands + i * LI.handStride + LI.hand.score;
      const label = readHandedness(labels[i], labelPath, i, "", input, scoreAt);
      if (label & 2) checkScore(input[scoreAt], labelPath, i, ".score");
      else input[scoreAt] = 1;
      packHand(input, i, label & 1, hasWorld ? world[i] : null, hasImage ? image[i] : null, i, worldPath, "", imagePath, "");
    }
    return n;
  }

  // One side of a Holistic result into hand slot `n` (as the label `label` of MediaPipe Hands
  // would give it): legacy Holistic's image landmarks (21 points), or tasks-vision's lists of
  // hands (`[]` or one list) with world landmarks. Returns the next free slot.
  function packHolisticHand(input, n, label, image, world, imagePath, worldPath) {
    if (image === undefined || image === null) return n;
    let fi = -1;
    if (Array.isArray(image) && (image.length === 0 || isListOfLists(image))) {
      if (image.length === 0) return n;
      if (image.length > 1) fail(imagePath, `has ${image.length} hands: a Holistic result has one hand per side`);
      image = image[0];
      fi = 0;
      if (world !== undefined && world !== null) {
        if (!Array.isArray(world) || world.length !== 1) {
          fail(worldPath, `must be a list of one hand like ${imagePath}, got ${describe(world)}`);
        }
        world = world[0];
      }
    } else world = null;
    input[LI.hands + n * LI.handStride + LI.hand.score] = 1;
    packHand(input, n, label, world, image, fi, worldPath, "", imagePath, "");
    return n + 1;
  }

  const NOT_A_FRAME = ["Date", "Map", "Set", "WeakMap", "WeakSet", "RegExp", "Promise", "ArrayBuffer", "Function", "Error"];

  // Frames that are certainly not one frame: say what they look like.
  function checkFrameObject(frame) {
    if (!isObject(frame)) {
      fail("frame", `must be an object { timeMs, hands?, pose?, wrists? }, got ${describe(frame)}`);
    }
    if (Array.isArray(frame)) {
      const first = frame.length > 0 ? frame[0] : undefined;
      const recording = isObject(first) && ("hands" in first || "timeMs" in first || "pose" in first);
      fail(
        "frame",
        `must be one frame object { timeMs, hands?, pose?, wrists? }, got an array of ${frame.length}` +
          (recording ? " (a whole recording? solve its frames one at a time)" : ""),
      );
    }
    const proto = Object.getPrototypeOf(frame);
    if (proto === Object.prototype || proto === null) return;
    const t = tag(frame);
    if (ArrayBuffer.isView(frame) || NOT_A_FRAME.includes(t)) {
      fail("frame", `must be a frame object { timeMs, hands?, pose?, wrists? }, got a ${t}`);
    }
  }

  // Whether `h` (given as frame.hands) is one hand rather than a list or a result: a single
  // handedness and one list of points.
  function looksLikeOneHand(h) {
    const hd = h.handedness;
    const w = h.worldLandmarks;
    const pts = w !== undefined ? w : h.landmarks;
    const oneLabel = typeof hd === "string" || (isObject(hd) && !Array.isArray(hd)) ||
      (Array.isArray(hd) && hd.length > 0 && isObject(hd[0]) && !Array.isArray(hd[0]));
    return oneLabel && (ArrayBuffer.isView(pts) || (Array.isArray(pts) && pts.length > 0 && !isListOfLists(pts)));
  }

  const KNOWN_FRAME_KEYS = [
    "timeMs", "hands", "pose", "wrists", "torso", "body", "face", "imageAspect", "landmarks", "worldLandmarks", "handedness",
    "handednesses", "multiHandLandmarks", "multiHandWorldLandmarks", "multiHandedness",
    "leftHandLandmarks", "rightHandLandmarks", "poseWorldLandmarks", "poseLandmarks",
    "faceLandmarks", "image", "segmentationMask",
    "leftHandWorldLandmarks", "rightHandWorldLandmarks", "faceBlendshapes", "poseSegmentationMasks",
  ];

  function packPose(frame, input) {
    at("frame.pose", -1, "");
    const pose = frame.pose;
    let list;
    let name;
    let image;
    let imageName;
    if (pose !== undefined && pose !== null) {
      if (Array.isArray(pose) || ArrayBuffer.isView(pose)) {
        list = pose;
        name = "frame.pose";
      } else if (isObject(pose)) {
        list = pose.worldLandmarks;
        name = "frame.pose.worldLandmarks";
        if (list === undefined || list === null) {
          list = pose.poseWorldLandmarks;
          name = "frame.pose.poseWorldLandmarks";
        }
        if (list === undefined || list === null) {
          fail("frame.pose.worldLandmarks", "is missing (33 world landmarks, meters)");
        }
        image = pose.landmarks;
        imageName = "frame.pose.landmarks";
      } else {
        fail("frame.pose", `must be { worldLandmarks } or a PoseLandmarker result, got ${describe(pose)}`);
      }
    } else {
      list = frame.poseWorldLandmarks;
      name = "frame.poseWorldLandmarks";
      image = frame.poseLandmarks;
      imageName = "frame.poseLandmarks";
      if ((list === undefined || list === null) && image !== undefined && image !== null) {
        list = legacyHolisticPoseWorld(frame);
        name = list === frame.za ? "frame.za" : "frame.ea";
      }
      if (list === undefined || list === null) return false;
    }
    // The pose's image landmarks (optional): with the hands' they check handedness.
    if (image !== undefined && image !== null) {
      let person = -1;
      if (isListOfLists(image)) {
        image = image[0];
        person = 0;
      }
      if (!(Array.isArray(image) && image.length === 0)) {
        at(imageName, person, "");
        packPoints(image, input, LI.poseImage, POSE_POINTS, 3, imageName, person, "", true);
        input[LI.poseHasImage] = 1;
      }
    }
    // PoseLandmarker: one list per person; the first person drives the avatar.
    let person = -1;
    if (isListOfLists(list)) {
      list = list[0];
      person = 0;
    }
    if (Array.isArray(list) && list.length === 0) return true; // nobody detected
    at(name, person, "");
    packPoints(list, input, LI.pose, POSE_POINTS, LI.poseStride, name, person, "");
    input[LI.posePresent] = 1;
    return true;
  }

  // A legacy @mediapipe/holistic result passed as it comes: its 0.5 build exports the world
  // landmarks under a minified name (`za`; `ea` in earlier builds), taken when it is a list of
  // 33 points.
  function legacyHolisticPoseWorld(frame) {
    return minifiedPoseWorld(frame.za) ?? minifiedPoseWorld(frame.ea);
  }

  // `v` if it looks like 33 world landmarks ({x, y, z} objects), else undefined.
  function minifiedPoseWorld(v) {
    if (!Array.isArray(v) || v.length !== POSE_POINTS) return undefined;
    const p = v[0];
    return isObject(p) && typeof p.x === "number" ? v : undefined;
  }

  const WRIST_FIELDS = SIDES.map((side) => ({
    side: `frame.wrists.${side}`,
    position: `frame.wrists.${side}.position`,
    rotation: `frame.wrists.${side}.rotation`,
  }));

  function packWrists(wrists, input) {
    at("frame.wrists", -1, "");
    if (!isObject(wrists) || Array.isArray(wrists)) {
      fail("frame.wrists", `must be { left?: { position, rotation? }, right?: ... }, got ${describe(wrists)}`);
    }
    for (let s = 0; s < 2; s++) {
      const F = WRIST_FIELDS[s];
      at(F.side, -1, "");
      const w = wrists[SIDES[s]];
      if (w === undefined || w === null) {
        if (w === undefined && wrists[WRIST_MISNAMED[s]] !== undefined) {
          fail(`frame.wrists.${WRIST_MISNAMED[s]}`, `unknown field: did you mean frame.wrists.${SIDES[s]}?`);
        }
        continue;
      }
      const o = LI.wrists + s * LI.wristStride;
      if (!isObject(w)) fail(F.side, `must be { position: [x, y, z], rotation?: [x, y, z, w] }, got ${describe(w)}`);
      const position = w.position;
      if (position === undefined || position === null) fail(F.position, "is missing (expected [x, y, z])");
      readVec3(position, F.position, input, o + LI.wrist.position, COORDINATE_LIMIT);
      const rotation = w.rotation;
      const hasRotation = rotation !== undefined && rotation !== null;
      if (hasRotation) readQuat(rotation, F.rotation, input, o + LI.wrist.rotation);
      input[o + LI.wrist.hasRotation] = hasRotation ? 1 : 0;
      input[o + LI.wrist.present] = 1;
    }
  }

  // frame.torso: { hips?, spine?, chest?, upperChest?, neck?, head?, leftShoulder?,
  // rightShoulder? }, each a local rotation [x, y, z, w] or { x, y, z, w } (model frame).
  // Keys are walked with for..in (no key array per frame); each value is read once.
  function packTorso(torso, input) {
    at("frame.torso", -1, "");
    if (!isObject(torso) || Array.isArray(torso) || ArrayBuffer.isView(torso)) {
      fail("frame.torso", `must be { ${TORSO_BONES.join("?, ")}? } of local rotations [x, y, z, w], got ${describe(torso)}`);
    }
    for (const key in torso) {
      const slot = TORSO_INDEX.get(key);
      if (slot === undefined) {
        fail(`frame.torso.${key}`, `unknown torso bone (expected one of ${TORSO_BONES.join(", ")})`);
      }
      const field = TORSO_FIELDS[slot];
      at(field, -1, "");
      const q = torso[key];
      if (q === undefined || q === null) continue;
      const o = LI.torso + slot * LI.torsoStride;
      readQuat(q, field, input, o + LI.torsoBone.rotation);
      input[o + LI.torsoBone.present] = 1;
    }
  }

  // frame.body: body-tracker joints { hips?, leftUpperLeg?, ... }, each [x, y, z],
  // [x, y, z, confidence] or { x, y, z, confidence? } (model frame; confidence default 1).
  function packBody(body, input) {
    at("frame.body", -1, "");
    if (!isObject(body) || Array.isArray(body) || ArrayBuffer.isView(body)) {
      fail("frame.body", `must be { ${BODY_JOINTS.join("?, ")}? } of joints [x, y, z] or [x, y, z, confidence], got ${describe(body)}`);
    }
    for (let j = 0; j < BODY_JOINTS.length; j++) input[LI.body + j * LI.bodyStride + 3] = 0;
    for (const key in body) {
      const j = BODY_INDEX.get(key);
      if (j === undefined) {
        fail(`frame.body.${key}`, `unknown body joint (expected one of ${BODY_JOINTS.join(", ")})`);
      }
      const F = BODY_FIELDS[j];
      at(F.joint, -1, "");
      const v = body[key];
      if (v === undefined || v === null) continue;
      const o = LI.body + j * LI.bodyStride;
      let confidence = 1;
      let confidenceField = F.confidence;
      if (Array.isArray(v) || ArrayBuffer.isView(v)) {
        const m = v.length;
        if (m !== 3 && m !== 4) fail(F.joint, `must be [x, y, z] or [x, y, z, confidence], got ${m} numbers`);
        for (let c = 0; c < 3; c++) {
          const x = v[c];
          if (!within(x, COORDINATE_LIMIT)) outOfBounds(x, COORDINATE_LIMIT, `${F.joint}[${c}]`);
          input[o + c] = x;
        }
        if (m === 4) {
          confidence = v[3];
          confidenceField = F.confidenceAt;
        }
      } else if (isObject(v)) {
        readVec3(v, F.joint, input, o, COORDINATE_LIMIT);
        const c = v.confidence;
        if (c !== undefined && c !== null) confidence = c;
      } else {
        fail(F.joint, `must be [x, y, z], [x, y, z, confidence] or { x, y, z, confidence? }, got ${describe(v)}`);
      }
      if (!isFiniteNumber(confidence)) notFinite(confidence, confidenceField);
      if (confidence < 0 || confidence > 1) fail(confidenceField, `must be in 0..1, got ${confidence}`);
      input[o + 3] = confidence;
    }
    input[LI.bodyPresent] = 1;
  }

  // Face points from the body tracker that gives `wrists` (the model's own frame), for
  // self-contact: `frame.face = { nose?, leftEye?, rightEye?, leftEar?, rightEar?, mouth? }`.
  const FACE_POINTS = ["nose", "leftEye", "rightEye", "leftEar", "rightEar", "mouth"];
  const FACE_FIELDS = FACE_POINTS.map((n) => `frame.face.${n}`);

  function packFace(face, input) {
    at("frame.face", -1, "");
    if (!isObject(face) || Array.isArray(face)) {
      fail("frame.face", `must be { nose?, leftEye?, rightEye?, leftEar?, rightEar?, mouth? } of [x, y, z], got ${describe(face)}`);
    }
    for (const key of Object.keys(face)) {
      if (!FACE_POINTS.includes(key)) {
        fail("frame.face", `unknown point ${JSON.stringify(key)} (expected ${FACE_POINTS.join(", ")})`);
      }
    }
    for (let k = 0; k < FACE_POINTS.length; k++) {
      at(FACE_FIELDS[k], -1, "");
      const p = face[FACE_POINTS[k]];
      if (p === undefined || p === null) continue;
      const o = LI.face + k * LI.faceStride;
      readVec3(p, FACE_FIELDS[k], input, o + LI.facePoint.position, COORDINATE_LIMIT);
      input[o + LI.facePoint.present] = 1;
    }
  }

  // Fields a frame may carry by mistake for one handrig reads under another name: silently
  // ignored, they would leave the frame without its time or its hands. Looked up only when the
  // right name is absent.
  // (No one-letter names: legacy MediaPipe results carry minified fields such as `za`.)
  const TIME_ALIASES = ["timestamp", "timeStamp", "time", "timestampMs"];
  const HAND_ALIASES = ["hand", "Hands", "handLandmarks", "multiHands"];
  const WRIST_ALIASES = ["wrist", "Wrists"];
  const POSE_ALIASES = ["poses", "Pose"];
  const WRIST_MISNAMED = ["Left", "Right"];
  // Fields misnamed where the right one is absent (see the lists above).
  function checkMisnamed(frame, noTime, noHands, noWrists, noPose) {
    if (noTime) misnamed(frame, TIME_ALIASES, "handrig reads the time from frame.timeMs (milliseconds)");
    if (noHands) misnamed(frame, HAND_ALIASES, "did you mean frame.hands (an array of hands)?");
    if (noWrists) misnamed(frame, WRIST_ALIASES, "did you mean frame.wrists ({ left?, right? })?");
    if (noPose) misnamed(frame, POSE_ALIASES, "did you mean frame.pose ({ worldLandmarks, landmarks? })?");
  }

  function misnamed(frame, aliases, hint) {
    for (let k = 0; k < aliases.length; k++) {
      const v = frame[aliases[k]];
      if (v !== undefined && v !== null) fail(`frame.${aliases[k]}`, `unknown field: ${hint}`);
    }
  }

  // The frame's timestamp, kept in a typed array rather than returned (a returned double is
  // boxed: an allocation per frame).
  const TIME = new Float64Array(1);

  // Packs one frame into `input` and its timestamp (ms) into TIME[0]. Throws a FieldError
  // naming the field on bad input (the input is then partly written; the rig is not called).
  function packFrame(frame, input, lookAround) {
    at("frame", -1, "");
    checkFrameObject(frame);
    input[LI.handCount] = 0;
    input[LI.posePresent] = 0;
    input[LI.poseHasImage] = 0;
    for (let s = 0; s < 2; s++) input[LI.wrists + s * LI.wristStride + LI.wrist.present] = 0;
    for (let b = 0; b < TORSO_BONES.length; b++) input[LI.torso + b * LI.torsoStride + LI.torsoBone.present] = 0;
    input[LI.bodyPresent] = 0;
    for (let k = 0; k < FACE_POINTS.length; k++) input[LI.face + k * LI.faceStride + LI.facePoint.present] = 0;

    const t = frame.timeMs;
    if (t === undefined || t === null) TIME[0] = 0;
    else {
      if (!isFiniteNumber(t)) notFinite(t, "frame.timeMs");
      TIME[0] = t;
    }
    const aspect = frame.imageAspect;
    if (aspect === undefined || aspect === null) input[LI.imageAspect] = 0;
    else {
      finite(aspect, "frame.imageAspect");
      if (aspect <= 0) fail("frame.imageAspect", "must be positive (width / height)");
      input[LI.imageAspect] = aspect;
    }

    let found = t !== undefined;
    const hands = frame.hands;
    let handCount = 0;
    if (hands !== undefined && hands !== null) {
      found = true;
      if (Array.isArray(hands)) handCount = packHandList(hands, input);
      else if (isObject(hands) && !ArrayBuffer.isView(hands)) {
        if (looksLikeOneHand(hands)) {
          fail("frame.hands", "must be an array of hands, got a single hand object: wrap it in [ ]");
        }
        handCount = packResultShape(hands, input, "frame.hands");
        if (handCount < 0) {
          fail("frame.hands", "must be an array of hands or a HandLandmarker / legacy Hands result, got an object with none of their fields");
        }
      } else {
        fail("frame.hands", `must be an array of hands or a HandLandmarker result, got ${describe(hands)}`);
      }
    } else {
      // A MediaPipe result passed as the frame itself.
      handCount = packResultShape(frame, input, "frame");
      if (handCount < 0) handCount = 0;
      else found = true;
    }
    input[LI.handCount] = handCount;

    if (packPose(frame, input)) found = true;

    const wrists = frame.wrists;
    if (wrists !== undefined && wrists !== null) {
      found = true;
      packWrists(wrists, input);
    }
    // Misnamed fields: looked for in a rig's first frames (an app's frames all have one shape:
    // a misnamed field is in the first) and in a frame without its time or with no hand to
    // solve; looking up absent names on every frame showed up as ~60 bytes of garbage a frame
    // in V8 (soak.test.mjs).
    const noTime = t === undefined;
    if (lookAround || noTime || handCount === 0) {
      checkMisnamed(frame, noTime, hands === undefined, wrists === undefined, frame.pose === undefined);
    }

    const torso = frame.torso;
    if (torso !== undefined && torso !== null) {
      found = true;
      packTorso(torso, input);
    }

    const body = frame.body;
    if (body !== undefined && body !== null) {
      found = true;
      packBody(body, input);
    }

    const face = frame.face;
    if (face !== undefined && face !== null) {
      found = true;
      packFace(face, input);
    }

    if (!found) {
      const keys = Object.keys(frame);
      if (keys.length > 0 && !keys.some((k) => KNOWN_FRAME_KEYS.includes(k))) {
        fail("frame", `has none of timeMs, hands, pose, wrists (nor a MediaPipe result's fields); got keys ${keys.slice(0, 8).join(", ")}`);
      }
    }
  }

  // A user getter or Proxy threw while the frame was read: name the part being read.
  function readError(e) {
    return userError(e, path(where.a, where.i, where.b));
  }

  // What a user getter threw while `part` was read, as an Error naming it (our own FieldErrors
  // pass through).
  function userError(e, part) {
    if (e instanceof FieldError) return e;
    const err = new Error(`${part}: reading it threw: ${thrownMessage(e)}`);
    err.cause = e;
    return err;
  }

  // What a user getter threw, as text (whatever it threw: a value whose toString throws too).
  function thrownMessage(e) {
    try {
      return e !== null && typeof e === "object" && typeof e.message === "string" ? e.message : String(e);
    } catch {
      return "a value that cannot be shown";
    }
  }

  // The part of the options, a rest pose or a ChainSolver argument being read (setup-time
  // reads; frames have `where`), to name it when a user getter or Proxy throws.
  let reading = "";

  // Runs `read` (which reads user objects and reports bad values with `fail`), turning what a
  // user getter throws into an Error naming the part being read.
  function readUser(what, read) {
    reading = what;
    try {
      return read();
    } catch (e) {
      throw userError(e, reading);
    }
  }

  // ---------------------------------------------------------------------------------------
  // Results: built from the output view into a reused object.

  function vec(out, at, dst) {
    dst[0] = out[at];
    dst[1] = out[at + 1];
    dst[2] = out[at + 2];
    return dst;
  }

  function quat(out, at, dst) {
    dst[0] = out[at];
    dst[1] = out[at + 1];
    dst[2] = out[at + 2];
    dst[3] = out[at + 3];
    return dst;
  }

  const STATUS = [undefined, "solved", "held", "skipped"];

  // Fills `result` (any object; its parts are created on first use and reused after) from the
  // output view. `driven`/`present` are the rig's bone indices.
  function fillResult(result, out, input, driven, present) {
    result.timeMs = TIME[0];
    // The per-bone arrays, found by name once per result object and then updated by index:
    // a property store by a varying key is a slow (megamorphic) lookup every time.
    const arrays = boneArrays(result, driven, present);
    const rotations = arrays.rotations;
    for (let k = 0; k < driven.length; k++) quat(out, LO.boneRotations + 4 * driven[k], rotations[k]);
    const positions = arrays.positions;
    for (let k = 0; k < present.length; k++) vec(out, LO.bonePositions + 3 * present[k], positions[k]);
    let targets = result.ikTargets;
    if (!isObject(targets)) targets = result.ikTargets = {};
    let alignment = result.alignment;
    if (!isObject(alignment)) alignment = result.alignment = {};
    let hands = result.hands;
    if (!isObject(hands)) hands = result.hands = {};
    const S = LO.side;
    for (let s = 0; s < 2; s++) {
      const side = SIDES[s];
      const at = LO.sides + s * LO.sideStride;
      const cache = sideCache(result, s);
      if (out[at + S.targetPresent] === 1) {
        const t = cache.target;
        vec(out, at + S.targetPosition, t.position);
        quat(out, at + S.targetRotation, t.rotation);
        targets[side] = t;
      } else if (side in targets) delete targets[side];
      if (out[at + S.alignmentPresent] === 1) {
        const a = cache.alignment;
        vec(out, at + S.targetDip, a.targetDip);
        vec(out, at + S.ikWrist, a.ikWrist);
        vec(out, at + S.poseWrist, a.poseWrist);
        const err = out[at + S.alignmentError];
        a.error = Number.isNaN(err) ? null : err;
        a.reachable = out[at + S.reachable] === 1;
        a.aligned = out[at + S.aligned] === 1;
        if (out[at + S.contactPresent] === 1) {
          const c = cache.contact;
          c.anchor = FACE_ANCHORS[out[at + S.contactAnchor]] ?? null;
          c.weight = out[at + S.contactWeight];
          const d = out[at + S.contactDistance];
          c.distance = Number.isNaN(d) ? null : d;
          c.handWeight = out[at + S.contactHandWeight];
          c.push = out[at + S.contactPush];
          a.contact = c;
        } else a.contact = null;
        alignment[side] = a;
      } else if (side in alignment) delete alignment[side];
      const status = STATUS[out[at + S.handStatus]];
      if (status !== undefined) {
        const h = cache.hand;
        h.status = status;
        h.score = out[at + S.handScore];
        h.index = out[at + S.handIndex];
        h.reassigned = out[at + S.handReassigned] === 1;
        hands[side] = h;
      } else if (side in hands) delete hands[side];
    }
    let tips = result.fingertips;
    if (!isObject(tips)) tips = result.fingertips = {};
    let retarget = result.retarget;
    if (!isObject(retarget)) retarget = result.retarget = {};
    for (let s = 0; s < 2; s++) {
      const side = SIDES[s];
      const at = LO.sides + s * LO.sideStride;
      const cache = sideCache(result, s);
      if (fingers(out, at + S.fingertips, cache.tips)) tips[side] = cache.tips;
      else if (side in tips) delete tips[side];
      if (out[at + S.retargetPresent] === 1) {
        const r = cache.retarget;
        fingers(out, at + S.retargetTargets, r.targets);
        r.scale = out[at + S.retargetScale];
        r.iterations = out[at + S.retargetIterations];
        r.residual = out[at + S.retargetResidual];
        retarget[side] = r;
      } else if (side in retarget) delete retarget[side];
    }
    let use = result.handUse;
    if (!Array.isArray(use)) use = result.handUse = [];
    const count = input[LI.handCount];
    use.length = count;
    for (let k = 0; k < count; k++) use[k] = HAND_USE[out[LO.handUse + k]];
    return result;
  }

  const HAND_USE = [null, "left", "right", "lowScore", "duplicate", "contradicted"];
  const FACE_ANCHORS = ["nose", "chin", "mouth", "leftCheek", "rightCheek", "leftEar", "rightEar", "forehead"];
  const FINGERS = ["thumb", "index", "middle", "ring", "little"];

  // Five points (NaN for a finger the avatar lacks) into `dst.thumb` ... `dst.little`
  // (undefined where missing). Returns whether any finger is there.
  function fingers(out, at, dst) {
    let any = false;
    for (let f = 0; f < 5; f++) {
      const o = at + 3 * f;
      const name = FINGERS[f];
      if (Number.isNaN(out[o])) {
        dst[name] = undefined;
        continue;
      }
      const p = dst.points[f];
      vec(out, o, p);
      dst[name] = p;
      any = true;
    }
    return any;
  }

  // { thumb, index, middle, ring, little } with the five reused arrays kept non-enumerable.
  function fingerSet() {
    const o = { thumb: undefined, index: undefined, middle: undefined, ring: undefined, little: undefined };
    Object.defineProperty(o, "points", { value: FINGERS.map(() => [0, 0, 0]), enumerable: false });
    return o;
  }

  // The arrays of `result.bones` and `result.worldPositions`, in the rig's driven / present
  // order, kept on a hidden property of the result (re-found if the caller swapped an object).
  const BONE_ARRAYS = typeof Symbol === "function" ? Symbol("handrig.bones") : "__handrigBones";
  function boneArrays(result, driven, present) {
    let c = result[BONE_ARRAYS];
    if (c !== undefined && c.bones === result.bones && c.world === result.worldPositions && c.driven === driven) return c;
    let bones = result.bones;
    if (!isObject(bones)) bones = result.bones = {};
    let world = result.worldPositions;
    if (!isObject(world)) world = result.worldPositions = {};
    const take = (o, name, n) => {
      const a = o[name];
      if (Array.isArray(a) && a.length === n) return a;
      return (o[name] = n === 4 ? [0, 0, 0, 1] : [0, 0, 0]);
    };
    c = {
      bones,
      world,
      driven,
      rotations: driven.map((i) => take(bones, BONES[i], 4)),
      positions: present.map((i) => take(world, BONES[i], 3)),
    };
    Object.defineProperty(result, BONE_ARRAYS, { value: c, enumerable: false, configurable: true, writable: true });
    return c;
  }

  // Per-side sub-objects, kept on a hidden property of the result so a reused result reuses
  // them (and a fresh `{}` gets its own).
  const SIDE_CACHE = typeof Symbol === "function" ? Symbol("handrig.sides") : "__handrigSides";
  function sideCache(result, s) {
    let c = result[SIDE_CACHE];
    if (c === undefined) {
      const make = () => ({
        target: { position: [0, 0, 0], rotation: [0, 0, 0, 1] },
        alignment: {
          targetDip: [0, 0, 0],
          ikWrist: [0, 0, 0],
          poseWrist: [0, 0, 0],
          error: null,
          reachable: false,
          aligned: false,
          contact: null,
        },
        contact: { anchor: null, weight: 0, distance: null, handWeight: 0, push: 0 },
        hand: { status: "solved", score: 0, index: 0, reassigned: false },
        tips: fingerSet(),
        retarget: { targets: fingerSet(), scale: 0, iterations: 0, residual: 0 },
      });
      c = [make(), make()];
      Object.defineProperty(result, SIDE_CACHE, { value: c, enumerable: false });
    }
    return c[s];
  }

  // ---------------------------------------------------------------------------------------
  // Options: nested objects or dotted paths (as optionDescriptions() spells them), checked
  // against the descriptions, normalized into a plain nested object for the Rust side.

  // The shortest decimal that is the same f32 as `v`. Option ranges and defaults are f32 in
  // Rust, so 0.05 reaches JavaScript as 0.05000000074505806: compared as it arrives, the
  // documented bound 0.05 itself would be out of range. Any decimal between the two rounds to
  // the same f32, so the range accepted here is the one Rust checks.
  function f32Decimal(v) {
    if (typeof v !== "number" || !Number.isFinite(v)) return v;
    const f = Math.fround(v);
    for (let digits = 1; digits < 9; digits++) {
      const d = Number(f.toPrecision(digits));
      if (Math.fround(d) === f) return d;
    }
    return f;
  }

  // The raw descriptions with their numbers as f32Decimal spells them (a fresh array each call:
  // a caller may change what it gets).
  function cleanDescriptions() {
    return RawHandRig.optionDescriptions().map((d) =>
      d.type === "number"
        ? { ...d, min: f32Decimal(d.min), max: f32Decimal(d.max), step: f32Decimal(d.step), default: f32Decimal(d.default) }
        : d,
    );
  }

  let descriptionsCache;
  function descriptions() {
    if (descriptionsCache === undefined) {
      descriptionsCache = new Map(cleanDescriptions().map((d) => [d.path, d]));
    }
    return descriptionsCache;
  }

  function checkOptionValue(d, value, field) {
    switch (d.type) {
      case "boolean":
        if (typeof value !== "boolean") fail(field, `must be true or false, got ${describe(value)}`);
        return value;
      case "enum":
        if (typeof value !== "string" || !d.values.includes(value)) {
          fail(field, `must be one of ${d.values.map((v) => JSON.stringify(v)).join(", ")}, got ${describe(value)}`);
        }
        return value;
      case "points": {
        // { name: [x, y, z] | {x, y, z} } with names from d.names, normalized to arrays;
        // null: none given (the default).
        if (value === null) return null;
        if (!isObject(value) || Array.isArray(value)) {
          fail(field, `must be an object { ${d.names.join(", ")} } of [x, y, z] (meters), got ${describe(value)}`);
        }
        const out = {};
        for (const key of Object.keys(value)) {
          if (!d.names.includes(key)) {
            fail(`${field}.${key}`, `unknown point (expected one of ${d.names.join(", ")})`);
          }
          const p = value[key];
          if (p === undefined || p === null) continue;
          out[key] = point3(p, `${field}.${key}`);
        }
        return out;
      }
      case "numbers": {
        // A fixed-length array of numbers, copied.
        if (!Array.isArray(value) || value.length !== d.length) {
          fail(field, `must be an array of ${d.length} numbers in ${d.min}..${d.max}, got ${describe(value)}`);
        }
        return value.map((x, i) => {
          if (typeof x !== "number" || !Number.isFinite(x) || x < d.min || x > d.max) {
            fail(`${field}[${i}]`, `must be a number in ${d.min}..${d.max}, got ${describe(x)}`);
          }
          return x;
        });
      }
      case "number":
        if (value === null && d.default === null) return null;
        if (typeof value !== "number" || !Number.isFinite(value)) {
          fail(field, `must be a number in ${d.min}..${d.max}, got ${describe(value)}`);
        }
        if (value < d.min || value > d.max) fail(field, `must be in ${d.min}..${d.max}, got ${value}`);
        if (d.integer && !Number.isInteger(value)) fail(field, `must be a whole number in ${d.min}..${d.max}, got ${value}`);
        return value;
      default:
        return value;
    }
  }

  function normalizeOptions(options) {
    if (options === undefined || options === null) return undefined;
    if (!isObject(options) || Array.isArray(options)) {
      fail("options", `must be an object, got ${describe(options)}`);
    }
    const known = descriptions();
    const out = {};
    const seen = new Set();
    const walk = (obj, prefix) => {
      reading = prefix === "" ? "options" : `options.${prefix}`;
      for (const key of Object.keys(obj)) {
        const path = prefix === "" ? key : `${prefix}.${key}`;
        const field = `options.${path}`;
        reading = field;
        const value = obj[key];
        if (value === undefined) continue;
        const d = known.get(path);
        if (d !== undefined) {
          if (seen.has(path)) fail(field, "given twice (as a nested object and as a dotted path)");
          seen.add(path);
          const parts = path.split(".");
          let o = out;
          for (let i = 0; i < parts.length - 1; i++) {
            if (!isObject(o[parts[i]])) o[parts[i]] = {};
            o = o[parts[i]];
          }
          o[parts[parts.length - 1]] = checkOptionValue(d, value, field);
          continue;
        }
        let group = false;
        for (const p of known.keys()) {
          if (p.startsWith(`${path}.`)) {
            group = true;
            break;
          }
        }
        if (!group) fail(field, `unknown option${optionHint(path, known)}`);
        // `filter: false` is `filter: { enabled: false }` (any group with an `enabled` switch).
        if (typeof value === "boolean" && known.has(`${path}.enabled`)) {
          walk({ enabled: value }, path);
          continue;
        }
        if (!isObject(value) || Array.isArray(value)) {
          fail(field, `must be an object of ${path}.* options, got ${describe(value)}`);
        }
        walk(value, path);
      }
    };
    walk(options, "");
    return out;
  }

  // Names users bring from MediaPipe and other rigs for handrig's options.
  const OPTION_ALIASES = { selfieMode: "inputMirrored", mirrored: "mirror", flipHorizontal: "inputMirrored" };

  // " (did you mean X?)" for an unknown option path: a known alias, or the option or group
  // path nearest in spelling (at most 2 edits, or the same name in another case).
  function optionHint(path, known) {
    const alias = OPTION_ALIASES[path];
    if (alias !== undefined) return ` (did you mean ${alias}?)`;
    const names = new Set();
    for (const p of known.keys()) {
      const parts = p.split(".");
      for (let i = 1; i <= parts.length; i++) names.add(parts.slice(0, i).join("."));
    }
    let best;
    let bestDistance = 3;
    for (const name of names) {
      const d = name.toLowerCase() === path.toLowerCase() ? 0 : editDistance(name, path);
      if (d < bestDistance) {
        best = name;
        bestDistance = d;
      }
    }
    return best === undefined ? "" : ` (did you mean ${best}?)`;
  }

  // Levenshtein distance (setup-time: option names are short).
  function editDistance(a, b) {
    let prev = Array.from({ length: b.length + 1 }, (_, j) => j);
    for (let i = 1; i <= a.length; i++) {
      const row = [i];
      for (let j = 1; j <= b.length; j++) {
        row[j] = Math.min(prev[j] + 1, row[j - 1] + 1, prev[j - 1] + (a[i - 1] === b[j - 1] ? 0 : 1));
      }
      prev = row;
    }
    return prev[b.length];
  }

  /**
   * Options as the raw constructors take them: a fresh plain object of checked values (no user
   * getters or prototypes reach Rust, which reads it with serde-wasm-bindgen), or undefined for
   * the defaults.
   */
  function optionsValue(options) {
    return readUser("options", () => normalizeOptions(options));
  }

  // ---------------------------------------------------------------------------------------
  // Rest poses.

  function restPoseToFlat(restPose) {
    return readUser("restPose", () => readRestPose(restPose));
  }

  function readRestPose(restPose) {
    if (!isObject(restPose) || Array.isArray(restPose)) {
      fail("restPose", 'must be an object { bones: { [boneName]: [x, y, z] }, vrmVersion?: "0" | "1" }');
    }
    const v = restPose.vrmVersion;
    let version = 1;
    if (v !== undefined && v !== null) {
      if (v === "0" || v === 0) version = 0;
      else if (v !== "1" && v !== 1) fail("restPose.vrmVersion", `must be "0" or "1", got ${describe(v)}`);
    }
    reading = "restPose.bones";
    const bones = restPose.bones;
    if (!isObject(bones) || Array.isArray(bones)) {
      fail("restPose.bones", "must be an object { [boneName]: [x, y, z] }");
    }
    const rest = new Float64Array(4 * BONE_COUNT);
    for (const name of Object.keys(bones)) {
      const i = BONE_INDEX.get(name);
      if (i === undefined) {
        fail("restPose.bones", `unknown bone name ${JSON.stringify(name)} (expected a VRM 1.0 humanoid bone name such as "leftHand")`);
      }
      rest[4 * i] = 1;
      reading = `restPose.bones.${name}`;
      readVec3(bones[name], reading, rest, 4 * i + 1);
    }
    return { rest, version };
  }

  // Accepts what file/fetch/fs APIs hand out; checks by tag so other realms' buffers work.
  function vrmBytes(bytes) {
    if (bytes instanceof Uint8Array) return bytes;
    const t = tag(bytes);
    if (t === "ArrayBuffer" || t === "SharedArrayBuffer") return new Uint8Array(bytes);
    if (ArrayBuffer.isView(bytes)) return new Uint8Array(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    throw new TypeError(
      "bytes: must be the .vrm file's contents as a Uint8Array, ArrayBuffer, Buffer or typed array" +
        (bytes === undefined ? " (got undefined)" : ` (got ${t})`),
    );
  }

  let memory;
  function wasmMemory() {
    if (memory === undefined) memory = RawHandRig.memory();
    return memory;
  }

  // ---------------------------------------------------------------------------------------

  class HandRig {
    #raw;
    #input;
    #output;
    #result;
    #driven;
    #present;
    #framesRead = 0;

    /**
     * `new HandRig(restPose, options?)`: a solver for one avatar. `restPose.bones` maps VRM 1.0
     * humanoid bone names to rest world positions [x, y, z] (meters, the model's own frame,
     * three-vrm's normalized bones); `restPose.vrmVersion` is "0" or "1" (default "1").
     */
    constructor(restPose, options) {
      if (restPose === ADOPT) {
        this.#adopt(options);
        return;
      }
      ensureReady("new HandRig()");
      let r;
      try {
        const { rest, version } = restPoseToFlat(restPose);
        r = new RawHandRig(rest, version, optionsValue(options));
      } catch (e) {
        throw asError(e);
      }
      this.#adopt(r);
    }

    #adopt(r) {
      this.#raw = r;
      const states = r.boneStates();
      const driven = [];
      const present = [];
      for (let i = 0; i < BONE_COUNT; i++) {
        if (states[i] !== 0) present.push(i);
        if (states[i] === 2) driven.push(i);
      }
      this.#driven = driven;
      this.#present = present;
      this.#input = new Float32Array(0);
      this.#output = new Float32Array(0);
    }

    /** A rig for a `.vrm` file (VRM 1.0 or 0.x), read directly from its bytes. */
    static fromVrm(bytes, options) {
      ensureReady("HandRig.fromVrm()");
      let r;
      try {
        r = RawHandRig.fromVrm(vrmBytes(bytes), optionsValue(options));
      } catch (e) {
        throw asError(e);
      }
      return new HandRig(ADOPT, r);
    }

    /**
     * Every option: `{ path, type, default, values?, min?, max?, step?, description }`. Numbers
     * are the shortest decimals of the f32 values Rust holds (0.05, not 0.05000000074505806);
     * `min` and `max` are accepted.
     */
    static optionDescriptions() {
      ensureReady("HandRig.optionDescriptions()");
      return cleanDescriptions();
    }

    /** The flat frame layout (offsets of the input and output arrays); see the README. */
    static get layout() {
      return L;
    }

    #live(method) {
      const r = this.#raw;
      if (r === null) {
        throw new Error(`HandRig.${method}: this rig was freed (free() was called); create a new HandRig`);
      }
      return r;
    }

    // Views into wasm memory, re-created only when the memory grew (its old buffer is then
    // detached and the old views have length 0).
    #views(method) {
      const r = this.#live(method);
      if (this.#input.length === 0) {
        const buffer = wasmMemory().buffer;
        this.#input = new Float32Array(buffer, r.inputPtr(), LI.length);
        this.#output = new Float32Array(buffer, r.outputPtr(), LO.length);
      }
      return r;
    }

    /**
     * The rig's flat input array (a view into wasm memory, `LAYOUT.input`): write a frame here,
     * then call `solveFlat(timeMs)`. Read the getter again after creating other rigs (a view
     * goes stale when wasm memory grows); it returns the same view while it is valid.
     */
    get input() {
      this.#views("input");
      return this.#input;
    }

    /** The rig's flat output array (a view into wasm memory, `LAYOUT.output`). */
    get output() {
      this.#views("output");
      return this.#output;
    }

    /** Solves the frame in `rig.input` into `rig.output`. Allocates nothing. */
    solveFlat(timeMs) {
      const r = this.#views("solveFlat");
      if (typeof timeMs !== "number") throw new TypeError(`timeMs: must be a number, got ${describe(timeMs)}`);
      if (r.solveFlat(timeMs) !== 0) throw new Error(r.takeError());
    }

    /**
     * Copies `input` (a Float32Array of `LAYOUT.input.length`) in, solves, and copies the
     * output into `output` (a Float32Array of `LAYOUT.output.length`). Allocates nothing.
     */
    solveInto(input, output, timeMs) {
      const r = this.#views("solveInto");
      if (!(input instanceof Float32Array) || input.length !== LI.length) {
        throw new TypeError(`input: must be a Float32Array of ${LI.length} (LAYOUT.input.length)`);
      }
      if (!(output instanceof Float32Array) || output.length !== LO.length) {
        throw new TypeError(`output: must be a Float32Array of ${LO.length} (LAYOUT.output.length)`);
      }
      if (typeof timeMs !== "number") throw new TypeError(`timeMs: must be a number, got ${describe(timeMs)}`);
      this.#input.set(input);
      if (r.solveFlat(timeMs) !== 0) throw new Error(r.takeError());
      output.set(this.#output);
      return output;
    }

    /**
     * Solves one frame (see the README for the frame and result shapes). The result is the
     * rig's own object, updated in place by the next call (nothing is allocated per frame);
     * pass `target` (e.g. `{}`) to get the result in an object of your own instead.
     */
    solve(frame, target) {
      const r = this.#views("solve");
      // The target is checked first: a rejected call leaves the rig where it was.
      let result = target;
      if (result === undefined || result === null) {
        if (this.#result === undefined) this.#result = {};
        result = this.#result;
      } else if (!isObject(result) || !Object.isExtensible(result)) {
        throw new TypeError(
          `target: must be an object to fill with the result${isObject(result) ? " (this one is frozen, sealed or not extensible)" : `, got ${describe(result)}`}`,
        );
      }
      try {
        const first = this.#framesRead < 3;
        packFrame(frame, this.#input, first);
        if (first) this.#framesRead++;
      } catch (e) {
        throw readError(e);
      }
      // A getter that freed this rig or grew wasm memory (creating rigs) while the frame was
      // read: the input view is gone, and what was packed with it.
      if (this.#input.length === 0) {
        this.#views("solve");
        throw new Error("frame: reading it changed wasm memory (a getter created or freed rigs); the frame was not solved, solve it again");
      }
      if (r.solveFlat(TIME[0]) !== 0) throw new Error(r.takeError());
      return fillResult(result, this.#output, this.#input, this.#driven, this.#present);
    }

    /**
     * The avatar's self-contact model at rest (meters, the model's own frame): `{ anchors: {
     * nose, chin, mouth, leftCheek, rightCheek, leftEar, rightEar, forehead: [x, y, z] },
     * headBreadth, colliders: { torso?, neck?: { a, b, radius }, head?: { center, radius } } }`
     * (from `contact.faceAnchors` where given, derived from the rig elsewhere). Anchors
     * relative to the head bone are `anchors[name] - restWorldPositions().head`.
     */
    contactModel() {
      const v = this.#live("contactModel").contactModel();
      const p = (k) => [v[k], v[k + 1], v[k + 2]];
      const anchors = {};
      FACE_ANCHORS.forEach((name, i) => (anchors[name] = p(3 * i)));
      const colliders = {};
      let k = 3 * FACE_ANCHORS.length + 1;
      for (const name of ["torso", "neck"]) {
        if (v[k] === 1) colliders[name] = { a: p(k + 1), b: p(k + 4), radius: v[k + 7] };
        k += 8;
      }
      if (v[k] === 1) colliders.head = { center: p(k + 1), radius: v[k + 4] };
      return { anchors, headBreadth: v[3 * FACE_ANCHORS.length], colliders };
    }

    /** `{ [boneName]: [x, y, z] }`: rest world positions, meters, the model's own frame. */
    restWorldPositions() {
      const p = this.#live("restWorldPositions").restPositions();
      const o = {};
      for (const i of this.#present) o[BONES[i]] = [p[3 * i], p[3 * i + 1], p[3 * i + 2]];
      return o;
    }

    /** The bones this avatar has, parent-first, VRM 1.0 names. */
    boneNames() {
      this.#live("boneNames");
      return this.#present.map((i) => BONES[i]);
    }

    /** The bones the rig writes every frame (in `result.bones`), parent-first. */
    drivenBones() {
      this.#live("drivenBones");
      return this.#driven.map((i) => BONES[i]);
    }

    /** `"0"` or `"1"`. */
    get vrmVersion() {
      return this.#live("vrmVersion").vrmVersion;
    }

    /** Body scale in force for pose input (avatar arm / user arm). */
    get bodyScale() {
      return this.#live("bodyScale").bodyScale;
    }

    /** Restarts body-scale calibration. */
    resetCalibration() {
      this.#live("resetCalibration").resetCalibration();
    }

    /** Forgets all history: filters, holds and blends, held hands, elbow swivel, calibration. */
    reset() {
      this.#live("reset").reset();
    }

    /**
     * Calibrates the hand scale of `handStrategy: "retarget"` from the last hand solved on
     * each side, which should be an open, flat hand (call it while the user shows one).
     * Returns `{ left, right }`: the new scale (avatar hand / user hand), or null where
     * nothing changed (no hand yet, fingers not straight).
     */
    calibrateHandScale() {
      const [left, right] = this.#live("calibrateHandScale").calibrateHandScale();
      return { left: Number.isNaN(left) ? null : left, right: Number.isNaN(right) ? null : right };
    }

    /** Releases the wasm memory. Safe to call twice; the rig is unusable afterwards. */
    free() {
      const r = this.#raw;
      if (r) {
        this.#raw = null;
        this.#input = new Float32Array(0);
        this.#output = new Float32Array(0);
        r.free();
      }
    }

    /** True once `free()` was called. */
    get freed() {
      return this.#raw === null;
    }
  }

  // ---------------------------------------------------------------------------------------
  // ChainSolver: FABRIK or CCD on any chain, over the raw class's flat goal and pose buffers.

  const RawChainSolver = raw.RawChainSolver;
  const CHAIN_KEYS = ["method", "joints", "constraints", "iterations", "tolerance", "maxStepAngle"];

  // ChainSolver's joints, targets and poles lie within this of the origin, as Rust checks
  // (chain_solver.rs COORDINATE_LIMIT): any unit of length, but squares must stay finite.
  const CHAIN_LIMIT = 1e9;

  function point3(v, field, limit = Number.MAX_VALUE) {
    reading = field;
    const out = [0, 0, 0];
    readVec3(v, field, out, 0, limit);
    return out;
  }

  // Checks the shape of ChainSolver options in JS (field-named errors, no user code run
  // inside wasm) and returns a plain copy for the Rust side, which checks the geometry.
  function chainOptions(options) {
    if (!isObject(options) || Array.isArray(options)) {
      fail("options", `must be an object { method?, joints, constraints?, iterations?, tolerance? }, got ${describe(options)}`);
    }
    for (const k of Object.keys(options)) {
      if (!CHAIN_KEYS.includes(k)) fail(`options.${k}`, "unknown option");
    }
    const out = {};
    const method = options.method;
    if (method !== undefined) {
      if (method !== "fabrik" && method !== "ccd") fail("options.method", `must be "fabrik" or "ccd", got ${describe(method)}`);
      out.method = method;
    }
    const joints = options.joints;
    if (!Array.isArray(joints)) fail("options.joints", `must be an array of [x, y, z] rest joint positions, root first, got ${describe(joints)}`);
    if (joints.length < 3) fail("options.joints", `needs at least 3 joints (2 bones), got ${joints.length}`);
    out.joints = joints.map((p, i) => point3(p, `options.joints[${i}]`, CHAIN_LIMIT));
    const constraints = options.constraints;
    if (constraints !== undefined && constraints !== null) {
      if (!Array.isArray(constraints)) fail("options.constraints", `must be an array (one entry per bone, or null), got ${describe(constraints)}`);
      out.constraints = constraints.map((c, i) => {
        const field = `options.constraints[${i}]`;
        if (c === null || c === undefined) return null;
        if (!isObject(c)) fail(field, `must be { type: "cone", maxAngle } or { type: "hinge", axis, min, max } or null, got ${describe(c)}`);
        if (c.type === "cone") {
          for (const k of Object.keys(c)) if (k !== "type" && k !== "maxAngle") fail(`${field}.${k}`, "unknown field");
          return { type: "cone", maxAngle: finite(c.maxAngle, `${field}.maxAngle`) };
        }
        if (c.type === "hinge") {
          for (const k of Object.keys(c)) if (!["type", "axis", "min", "max"].includes(k)) fail(`${field}.${k}`, "unknown field");
          return {
            type: "hinge",
            axis: point3(c.axis, `${field}.axis`),
            min: finite(c.min, `${field}.min`),
            max: finite(c.max, `${field}.max`),
          };
        }
        return fail(`${field}.type`, `must be "cone" or "hinge", got ${describe(c.type)}`);
      });
    }
    if (options.iterations !== undefined) {
      const it = options.iterations;
      if (!Number.isInteger(it) || it < 1 || it > 100000) fail("options.iterations", `must be a whole number in 1..100000, got ${describe(it)}`);
      out.iterations = it;
    }
    if (options.tolerance !== undefined) out.tolerance = finite(options.tolerance, "options.tolerance");
    if (options.maxStepAngle !== undefined) out.maxStepAngle = finite(options.maxStepAngle, "options.maxStepAngle");
    return out;
  }

  class ChainSolver {
    #raw;
    #goal;
    #pose;
    #n;
    #result;

    /**
     * `new ChainSolver({ method: "fabrik" | "ccd", joints, constraints?, iterations?,
     * tolerance?, maxStepAngle? })`: `joints` are rest joint positions [x, y, z], root first
     * (at least 3); `constraints` one entry per bone (or null).
     */
    constructor(options) {
      ensureReady("new ChainSolver()");
      let r;
      try {
        r = new RawChainSolver(readUser("options", () => chainOptions(options)));
      } catch (e) {
        const err = asError(e);
        // The Rust side names fields of the options (`joints[1]`, `constraints[0].maxAngle`).
        if (!(err instanceof FieldError) && !/^options/.test(err.message)) err.message = `options.${err.message}`;
        throw err;
      }
      this.#raw = r;
      this.#n = r.jointCount;
      this.#goal = new Float32Array(0);
      this.#pose = new Float32Array(0);
    }

    #views(method) {
      const r = this.#raw;
      if (r === null) throw new Error(`ChainSolver.${method}: this solver was freed (free() was called)`);
      if (this.#goal.length === 0) {
        const buffer = wasmMemory().buffer;
        this.#goal = new Float32Array(buffer, r.goalPtr(), 7);
        this.#pose = new Float32Array(buffer, r.posePtr(), r.poseLength);
      }
      return r;
    }

    #run(method, target, pole) {
      const r = this.#views(method);
      const g = this.#goal;
      // No closure (readUser's) here: a solve allocates nothing.
      reading = "target";
      try {
        readVec3(target, "target", g, 0, CHAIN_LIMIT);
        if (pole === undefined || pole === null) g[3] = 0;
        else {
          reading = "pole";
          readVec3(pole, "pole", g, 4, CHAIN_LIMIT);
          g[3] = 1;
        }
      } catch (e) {
        throw userError(e, reading);
      }
      // A getter that freed this solver or grew wasm memory (creating solvers or rigs) while
      // the goal was read: the goal view is gone and what was read with it.
      if (g.length === 0) {
        this.#views(method);
        throw new Error(`${method}: reading the goal changed wasm memory (a getter created or freed solvers or rigs); nothing was solved, call it again`);
      }
      if (r.solveFlat() !== 0) throw new Error(r.takeError());
      return this.#pose;
    }

    /** Number of joints. */
    get jointCount() {
      return this.#n;
    }

    /**
     * Solves toward `{ target, pole? }`: returns `{ joints, rotations, reached, reachable,
     * error, iterations }` (joints [x, y, z] root first; rotations: each bone's world rotation
     * from its rest direction [x, y, z, w]). The result object is reused by the next call;
     * pass `into` (e.g. `{}`) for one of your own.
     */
    solve(goal, into) {
      if (!isObject(goal)) throw new FieldError(`goal: must be { target: [x, y, z], pole?: [x, y, z] }, got ${describe(goal)}`);
      let target;
      let pole;
      reading = "goal.target";
      try {
        target = goal.target;
        reading = "goal.pole";
        pole = goal.pole;
      } catch (e) {
        throw userError(e, reading);
      }
      const p = this.#run("solve", target, pole);
      const n = this.#n;
      let out = into;
      if (out === undefined || out === null) {
        if (this.#result === undefined) this.#result = {};
        out = this.#result;
      }
      if (!Array.isArray(out.joints)) out.joints = Array.from({ length: n }, () => [0, 0, 0]);
      if (!Array.isArray(out.rotations)) out.rotations = Array.from({ length: n - 1 }, () => [0, 0, 0, 1]);
      for (let k = 0; k < n; k++) vec(p, 3 * k, out.joints[k]);
      const r0 = 3 * n;
      for (let k = 0; k < n - 1; k++) quat(p, r0 + 4 * k, out.rotations[k]);
      const st = r0 + 4 * (n - 1);
      out.reached = p[st] === 1;
      out.reachable = p[st + 1] === 1;
      out.error = p[st + 2];
      out.iterations = p[st + 3];
      return out;
    }

    /**
     * Solves toward `target` (and `pole`) into `out.joints` (a Float32Array of 3 N) and
     * `out.rotations` (4 (N - 1)); sets `out.reached`, `out.reachable`, `out.error`,
     * `out.iterations`. Allocates nothing.
     */
    solveInto(target, out, pole) {
      const n = this.#n;
      if (!isObject(out) || !(out.joints instanceof Float32Array) || out.joints.length !== 3 * n ||
          !(out.rotations instanceof Float32Array) || out.rotations.length !== 4 * (n - 1)) {
        throw new TypeError(`out: must be { joints: Float32Array(${3 * n}), rotations: Float32Array(${4 * (n - 1)}) }`);
      }
      const p = this.#run("solveInto", target, pole);
      out.joints.set(p.subarray(0, 3 * n));
      out.rotations.set(p.subarray(3 * n, 3 * n + 4 * (n - 1)));
      const st = 3 * n + 4 * (n - 1);
      out.reached = p[st] === 1;
      out.reachable = p[st + 1] === 1;
      out.error = p[st + 2];
      out.iterations = p[st + 3];
      return out;
    }

    /** Back to the rest pose. */
    reset() {
      this.#views("reset").reset();
    }

    /** Releases the wasm memory. Safe to call twice. */
    free() {
      const r = this.#raw;
      if (r) {
        this.#raw = null;
        this.#goal = new Float32Array(0);
        this.#pose = new Float32Array(0);
        r.free();
      }
    }

    /** True once `free()` was called. */
    get freed() {
      return this.#raw === null;
    }
  }

  for (const C of [HandRig, ChainSolver]) {
    if (typeof Symbol === "function" && typeof Symbol.dispose === "symbol") {
      Object.defineProperty(C.prototype, Symbol.dispose, { value: C.prototype.free, writable: true, configurable: true });
    }
  }

  /** `"simd128"` or `"baseline"`: which of the package's two WebAssembly builds is running. */
  function wasmBuild() {
    ensureReady("wasmBuild()");
    return raw.wasmBuild();
  }

  return { HandRig, ChainSolver, LAYOUT: L, wasmBuild };
}
