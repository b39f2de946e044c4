// The generated humans' face (issue 50): procedural morph targets from the base mesh's face
// regions (eyelids, jaw, lips, cheeks, brows, nose), the VRM expressions bound to them, and
// vertex colours (an outfit by body region, hair, the iris and pupil of each eye, the mouth's
// inside). Nothing here moves a rest vertex: the targets are deltas (sparse accessors), the
// colours a COLOR_0 attribute.
//
// Every shape is a smooth field over the rest positions of the body (mesh frame: +Y up, the
// body faces +Z, its left at +X), measured from the body itself so that each body shape gets
// its own: the eyes (helper spheres: centre, radius), the eyelid margins (per azimuth around
// the eye, the edges of the gap in the skin in front of the eyeball), the mouth's slit (between
// two midline lip vertices of the base mesh: the same vertex indices in every body, since the
// body targets only move vertices). Lengths scale with the distance between the eyes.
// "Left" is the avatar's left (+X), as in ARKit and VRM (`blinkLeft` closes the left eye).

import { add, dot, length, normalize, scale, sub } from "./math.mjs";

/** ARKit's 52 blendshape names, in Apple's documentation order (as MediaPipe names them). */
export const ARKIT = [
  "eyeBlinkLeft", "eyeLookDownLeft", "eyeLookInLeft", "eyeLookOutLeft", "eyeLookUpLeft", "eyeSquintLeft", "eyeWideLeft",
  "eyeBlinkRight", "eyeLookDownRight", "eyeLookInRight", "eyeLookOutRight", "eyeLookUpRight", "eyeSquintRight", "eyeWideRight",
  "jawForward", "jawLeft", "jawRight", "jawOpen",
  "mouthClose", "mouthFunnel", "mouthPucker", "mouthLeft", "mouthRight",
  "mouthSmileLeft", "mouthSmileRight", "mouthFrownLeft", "mouthFrownRight", "mouthDimpleLeft", "mouthDimpleRight",
  "mouthStretchLeft", "mouthStretchRight", "mouthRollLower", "mouthRollUpper", "mouthShrugLower", "mouthShrugUpper",
  "mouthPressLeft", "mouthPressRight", "mouthLowerDownLeft", "mouthLowerDownRight", "mouthUpperUpLeft", "mouthUpperUpRight",
  "browDownLeft", "browDownRight", "browInnerUp", "browOuterUpLeft", "browOuterUpRight",
  "cheekPuff", "cheekSquintLeft", "cheekSquintRight", "noseSneerLeft", "noseSneerRight", "tongueOut",
];

/**
 * The VRM 1.0 presets as mixes of the ARKit targets (weights), and their VRM 0.x names. The
 * look-at is of type bone (the eyes turn), so the lookUp/Down/Left/Right presets are absent.
 */
export const PRESETS = [
  { name: "aa", vrm0: "a", mix: { jawOpen: 0.9, mouthLowerDownLeft: 0.3, mouthLowerDownRight: 0.3, mouthStretchLeft: 0.5, mouthStretchRight: 0.5 } },
  { name: "ih", vrm0: "i", mix: { jawOpen: 0.25, mouthStretchLeft: 0.7, mouthStretchRight: 0.7 } },
  { name: "ou", vrm0: "u", mix: { mouthPucker: 1, jawOpen: 0.2 } },
  { name: "ee", vrm0: "e", mix: { jawOpen: 0.3, mouthStretchLeft: 0.5, mouthStretchRight: 0.5, mouthSmileLeft: 0.3, mouthSmileRight: 0.3 } },
  { name: "oh", vrm0: "o", mix: { mouthFunnel: 0.9, jawOpen: 0.5 } },
  { name: "blink", vrm0: "blink", mix: { eyeBlinkLeft: 1, eyeBlinkRight: 1 } },
  { name: "blinkLeft", vrm0: "blink_l", mix: { eyeBlinkLeft: 1 } },
  { name: "blinkRight", vrm0: "blink_r", mix: { eyeBlinkRight: 1 } },
  { name: "happy", vrm0: "joy", mix: { mouthSmileLeft: 1, mouthSmileRight: 1, cheekSquintLeft: 0.7, cheekSquintRight: 0.7, eyeSquintLeft: 0.5, eyeSquintRight: 0.5 } },
  { name: "angry", vrm0: "angry", mix: { browDownLeft: 1, browDownRight: 1, noseSneerLeft: 0.5, noseSneerRight: 0.5, mouthFrownLeft: 0.5, mouthFrownRight: 0.5, eyeSquintLeft: 0.3, eyeSquintRight: 0.3 } },
  { name: "sad", vrm0: "sorrow", mix: { browInnerUp: 1, mouthFrownLeft: 0.8, mouthFrownRight: 0.8, eyeLookDownLeft: 0.4, eyeLookDownRight: 0.4 } },
  { name: "relaxed", vrm0: "fun", mix: { mouthSmileLeft: 0.5, mouthSmileRight: 0.5, eyeBlinkLeft: 0.3, eyeBlinkRight: 0.3 } },
  { name: "surprised", vrm0: null, mix: { eyeWideLeft: 1, eyeWideRight: 1, browInnerUp: 1, browOuterUpLeft: 1, browOuterUpRight: 1, jawOpen: 0.4 } },
];

const clamp01 = (t) => (t < 0 ? 0 : t > 1 ? 1 : t);
/** 0 at or below e0, 1 at or above e1 (e0 > e1 reverses it). */
function smoothstep(e0, e1, x) {
  const t = clamp01((x - e0) / (e1 - e0));
  return t * t * (3 - 2 * t);
}
/** A compact bump: 1 at d = 0, 0 from d = 1 on (no tail: the targets stay sparse). */
const bump = (d2) => (d2 >= 1 ? 0 : (1 - d2) * (1 - d2));
const rotX = (q, a) => [q[0], q[1] * Math.cos(a) - q[2] * Math.sin(a), q[1] * Math.sin(a) + q[2] * Math.cos(a)];
const rotY = (q, a) => [q[0] * Math.cos(a) + q[2] * Math.sin(a), q[1], -q[0] * Math.sin(a) + q[2] * Math.cos(a)];
const mirror = (p) => [-p[0], p[1], p[2]];

// Midline vertices of the base mesh's lips (HM08): the lowest of the upper lip's outside and
// the highest of the lower lip's; the slit is between them.
const UPPER_LIP = 362;
const LOWER_LIP = 455;
// The base mesh's distance between the eye centres: lengths below are for it.
const BASE_EYE_SEP = 0.0616;

/** The face's measures from the body's rest positions (`v(i)`: vertex i, mesh frame). */
function measure(v, groups, tris) {
  const eye = (name) => {
    const ids = [];
    for (const [a, b] of groups[name]) for (let i = a; i <= b; i++) ids.push(i);
    let c = [0, 0, 0];
    for (const i of ids) c = add(c, v(i));
    c = scale(c, 1 / ids.length);
    let r = 0;
    for (const i of ids) r += length(sub(v(i), c)) / ids.length;
    return { ids, c, r };
  };
  const L = eye("helper-l-eye");
  const R = eye("helper-r-eye");
  const s = length(sub(L.c, R.c)) / BASE_EYE_SEP;
  const up = v(UPPER_LIP);
  const lo = v(LOWER_LIP);
  const mouth = [0, (up[1] + lo[1]) / 2, Math.max(up[2], lo[2])];
  const f = {
    s,
    eyeL: L,
    eyeR: R,
    mouth,
    mouthHalf: 0.0245 * s,
    pivot: [0, mouth[1] + 0.02 * s, L.c[2] - 0.075 * s],
  };
  f.lidL = opening(v, tris, L, (p) => p);
  // The right eye's opening measured mirrored, in the left eye's frame (see shapeOf).
  f.lidR = opening(v, tris, { ...R, c: mirror(R.c) }, mirror);
  return f;
}

// The lips' seam: the base mesh's lips are joined by a row of faces across the slit (facing
// forward, from the upper lip's edge to the lower lip's), which stretches over the opening when
// the jaw drops. Its two edges, as vertex indices of the base mesh (the same in every body:
// the body targets only move vertices), from the midline (UPPER_LIP, LOWER_LIP) out to the
// corners, the avatar's left then its right. The lips part along them, not along a height:
// on a body whose lips are pressed together (the man) the lower lip's edge lies partly above
// the upper lip's midline vertex.
const SEAM_UPPER = [[362, 357, 356, 355, 5334, 5363, 5341, 372], [362, 7118, 7117, 7116, 11938, 11965, 11944, 7132]];
const SEAM_LOWER = [[455, 454, 450, 456, 409, 5364, 5340, 374, 376], [455, 7214, 7210, 7215, 7169, 11966, 11943, 7134, 7136]];
// Two of the seam's faces on each side fan out to a vertex of the lip's next row (one above,
// one below): they stretch over the opening too, so they belong to the seam (`isSeamFace`).
const SEAM_FAN = [5346, 5354, 11948, 11956];
const SEAM_EDGES = new Set([...SEAM_UPPER.flat(), ...SEAM_LOWER.flat(), ...SEAM_FAN]);
const SEAM_LOWER_SET = new Set(SEAM_LOWER.flat());
/**
 * Whether a base-mesh face (its vertex indices) is one of the seam's faces across the slit:
 * all its corners on the seam's two edges or its fan, at least one on the lower edge and one
 * not. Those faces get a material of their own (dark: the mouth's inside, `generate.mjs`), so
 * the lips around them keep the skin's colour whether the mouth is open or closed (vertex
 * colours dark enough for the opening darkened the lips next to them, up to the nose).
 */
export function isSeamFace(vs) {
  return vs.every((i) => SEAM_EDGES.has(i)) && vs.some((i) => SEAM_LOWER_SET.has(i)) && vs.some((i) => !SEAM_LOWER_SET.has(i));
}
/**
 * The seam's edges (`f.seam`: vertex index -> 1 on the upper lip's edge, -1 on the lower's) and
 * the slit's height across the mouth (`f.slitY(x)`: halfway between the two edges, each
 * interpolated along |x| and averaged over both sides).
 */
function slit(f, v) {
  f.seam = new Map();
  for (const side of SEAM_UPPER) for (const i of side) f.seam.set(i, 1);
  for (const side of SEAM_LOWER) for (const i of side) f.seam.set(i, -1);
  // Each side's edge interpolated along |x| (its end's height beyond it), the mean of the sides.
  const along = (lines) => {
    const qs = lines.map((line) => line.map((i) => [Math.abs(v(i)[0]), v(i)[1]]));
    const at = (q, x) => {
      for (let k = 1; k < q.length; k++) {
        if (x > q[k][0]) continue;
        const t = Math.max(0, x - q[k - 1][0]) / (q[k][0] - q[k - 1][0] || 1);
        return q[k - 1][1] + t * (q[k][1] - q[k - 1][1]);
      }
      return q[q.length - 1][1];
    };
    return (x) => qs.reduce((sum, q) => sum + at(q, x), 0) / qs.length;
  };
  const up = along(SEAM_UPPER);
  const lo = along(SEAM_LOWER);
  f.slitY = (x) => (up(Math.abs(x)) + lo(Math.abs(x))) / 2;
}

// The eye's opening, as seen from straight ahead: per azimuth theta = atan2(x, z) about the
// eye's centre, the elevations phi = atan2(y, z) of the highest and lowest points of the eyeball
// (the sphere of the eye's mean radius) that a ray straight ahead (+Z) from them leaves without
// crossing the skin: the lid margins, measured on the body's own triangles at every azimuth, so
// that the corners are where this body's opening ends (inner and outer corner at their own
// elevations), not where a model of the opening puts them.
const OPEN_STEP = 0.01; // radians between the measured azimuths (and the elevations first tried)
function opening(v, tris, eye, flip) {
  const { c, r } = eye;
  // The triangles in front of the eye's centre, near it (relative to the centre, mirrored for
  // the right eye), with their extent across.
  const near = [];
  for (const t of tris) {
    const p = t.map((i) => sub(flip(v(i)), c));
    if (p.every((q) => length(q) > 2.6 * r || q[2] < -0.3 * r)) continue;
    const xs = p.map((q) => q[0]);
    const ys = p.map((q) => q[1]);
    near.push({ p, x0: Math.min(...xs), x1: Math.max(...xs), y0: Math.min(...ys), y1: Math.max(...ys) });
  }
  const ball = (th, ph) => {
    const tx = Math.tan(th);
    const ty = Math.tan(ph);
    const z = r / Math.sqrt(1 + tx * tx + ty * ty);
    return [z * tx, z * ty, z];
  };
  // How far ahead (z) the skin lies straight ahead of the ball's point (th, ph), at most: -Infinity
  // where none does.
  const front = (th, ph) => {
    const [x, y] = ball(th, ph);
    let best = -Infinity;
    for (const { p, x0, x1, y0, y1 } of near) {
      if (x < x0 || x > x1 || y < y0 || y > y1) continue;
      const [a, b, d] = p;
      const det = (b[0] - a[0]) * (d[1] - a[1]) - (d[0] - a[0]) * (b[1] - a[1]);
      if (det === 0) continue;
      const u = ((x - a[0]) * (d[1] - a[1]) - (d[0] - a[0]) * (y - a[1])) / det;
      const w = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / det;
      if (u < 0 || w < 0 || u + w > 1) continue;
      best = Math.max(best, a[2] + u * (b[2] - a[2]) + w * (d[2] - a[2]));
    }
    return best;
  };
  const covered = (th, ph) => front(th, ph) > ball(th, ph)[2];
  // The radius (in the eye's) of the skin straight ahead of the ball's point (th, ph).
  const skinRadius = (th, ph) => {
    const [x, y] = ball(th, ph);
    const z = front(th, ph);
    return z > -Infinity ? Math.hypot(x, y, z) / r : 1;
  };
  // The edge between a seen elevation and a covered one, by bisection.
  const edge = (th, seen, hidden) => {
    for (let k = 0; k < 20; k++) {
      const m = (seen + hidden) / 2;
      if (covered(th, m)) hidden = m;
      else seen = m;
    }
    return seen;
  };
  const n = Math.round(3 / OPEN_STEP) + 1;
  const th0 = -1.5;
  const up = new Float64Array(n).fill(NaN);
  const lo = new Float64Array(n).fill(NaN);
  // The lower lid's front just under its margin (radius, in the eye's): a closing upper lid
  // that lands behind it leaves the lower lid's rim showing (lit from above: a pale line).
  const loFront = new Float64Array(n).fill(1);
  for (let k = 0; k < n; k++) {
    const th = th0 + k * OPEN_STEP;
    // The longest run of seen elevations in this column.
    let best = null;
    let run = null;
    for (let ph = -1.2; ph <= 1.2 + 1e-9; ph += OPEN_STEP) {
      if (!covered(th, ph)) {
        run = run ? { ...run, hi: ph, count: run.count + 1 } : { lo: ph, hi: ph, count: 1 };
        if (!best || run.count > best.count) best = run;
      } else run = null;
    }
    if (!best) continue;
    up[k] = edge(th, best.hi, best.hi + OPEN_STEP);
    lo[k] = edge(th, best.lo, best.lo - OPEN_STEP);
    loFront[k] = Math.max(skinRadius(th, lo[k] - 0.05), skinRadius(th, lo[k] - 0.1));
  }
  // The opening is the run of open azimuths around the widest one; beyond its corners the lids
  // meet at the corner's elevation (the gap closes to 0 over one step).
  let widest = -1;
  for (let k = 0; k < n; k++) if (up[k] - lo[k] > (widest < 0 ? 0 : up[widest] - lo[widest])) widest = k;
  if (widest < 0) throw new Error("the eye's opening: no part of the eyeball is seen from the front");
  let k0 = widest;
  let k1 = widest;
  while (k0 > 0 && up[k0 - 1] > lo[k0 - 1]) k0--;
  while (k1 < n - 1 && up[k1 + 1] > lo[k1 + 1]) k1++;
  const gapMax = up[widest] - lo[widest];
  for (let k = 0; k < n; k++) {
    if (k >= k0 && k <= k1) continue;
    const e = k < k0 ? k0 : k1;
    up[k] = lo[k] = (up[e] + lo[e]) / 2;
    loFront[k] = loFront[e];
  }
  return { th0, up, lo, loFront, gapMax, corners: [th0 + (k0 - 1) * OPEN_STEP, th0 + (k1 + 1) * OPEN_STEP] };
}

/** The margins at an azimuth, interpolated; `fade` goes to 0 toward the corners. */
function marginAt(open, theta) {
  const x = Math.min(Math.max((theta - open.th0) / OPEN_STEP, 0), open.up.length - 1);
  const k = Math.min(Math.floor(x), open.up.length - 2);
  const t = x - k;
  const up = open.up[k] + t * (open.up[k + 1] - open.up[k]);
  const lo = open.lo[k] + t * (open.lo[k + 1] - open.lo[k]);
  const gap = up - lo;
  const loFront = open.loFront[k] + t * (open.loFront[k + 1] - open.loFront[k]);
  return { up, lo, gap, loFront, fade: smoothstep(0, 0.5 * open.gapMax, gap) };
}

/**
 * How a lid closes (`lids`): `closeAt`, the closing line's place up the opening (0: the lower
 * lid's margin, 1: the upper's); `over`, how far past it the upper lid goes (a share of the
 * opening); `lidR`, the radius (in eyeball radii) of the sphere the upper lid's skin is brought
 * in to where it lies further out (0: none), over `pull` (radians above the upper margin: all
 * of it below the first, none above the second).
 */
const SQUINT_LID = { closeAt: 0.4, over: 0, lidR: 0, pull: [0, 0] };
// How far (eyeball radii) behind the lower lid's front a closed upper lid's margin may lie.
const LID_CREASE = 0.03;
// The blink's line 20% of the opening below the lower lid's margin (the lower lid moves down to
// it), the upper lid 5% past: chosen on the woman (FaceLandmarker's score of her closed eyes;
// docs/measurements/2026-12-06-face.md, sixth session).
const BLINK_LID = { closeAt: -0.2, over: 0.05, lidR: 1.08, pull: [0.2, 0.35] };

/**
 * The lids of the eye on the avatar's left moved: the upper lid turned about the eye's
 * horizontal axis by `upper` of the way to the closing line (negative: opened by that share of
 * the gap), the lower lid by `lower`; `yaw` turns both lids sideways (radians, +: toward +X).
 * Turning about the eyeball's centre keeps the lids off the eyeball.
 */
function lids(f, p, upper, lower, yaw = 0, how = SQUINT_LID) {
  const { closeAt, over, lidR, pull: lidPull } = how;
  const eye = f.eyeL;
  const q = sub(p, eye.c);
  const rho = length(q);
  if (rho < 0.85 * eye.r || rho > 2.6 * eye.r || q[2] < -0.3 * eye.r) return null;
  const theta = Math.atan2(q[0], q[2]);
  const m = marginAt(f.lidL, theta);
  // Fading out toward the midline: nothing moves on the other half of the face.
  const radial = (1 - smoothstep(1.5 * eye.r, 2.4 * eye.r, rho)) * smoothstep(0.002 * f.s, 0.008 * f.s, p[0]);
  const phi = Math.atan2(q[1], q[2]);
  let turned = q;
  if (m.gap > 0 && radial > 0) {
    const close = m.lo + closeAt * (m.up - m.lo);
    const mid = (m.up + m.lo) / 2;
    let a = 0;
    if (phi >= mid) {
      const target = upper >= 0 ? upper * (close - over * m.gap - m.up) : -upper * m.gap * 0.5;
      a = target * (1 - smoothstep(0, 0.55, phi - m.up)) * radial;
    } else {
      const target = lower >= 0 ? lower * (close - m.lo) : lower * m.gap * 0.3;
      a = target * (1 - smoothstep(0, 0.45, m.lo - phi)) * radial;
    }
    turned = rotX(q, -a);
    // The closing upper lid lies on a sphere over the eyeball (`lidR` of its radius): the skin of
    // the fold above the margin, which sits further out (the socket's rim), comes in over the
    // ball as the lid unfolds, instead of turning down as an overhang (whose underside faced
    // down, dark: read as a squint).
    if (lidR > 0 && upper > 0 && phi >= mid) {
      const pull = upper * (1 - smoothstep(lidPull[0], lidPull[1], phi - m.up)) * radial * m.fade;
      const r = length(turned);
      const R = lidR * eye.r;
      // Nor far behind the lower lid's front, which it comes down onto: where that lies further
      // out than the upper lid's margin (a thick lower lid), the lid's skin comes out to a
      // crease's depth (LID_CREASE) behind it, else the lower lid's rim, facing up, shows along
      // the closed eye as a pale band. The lid's inside (within the eyeball's radius) stays
      // where the turn puts it.
      const out = (m.loFront - LID_CREASE) * eye.r;
      if (r > R && pull > 0) turned = scale(turned, (r - pull * (r - R)) / r);
      else if (r >= eye.r && r < out && pull > 0) turned = scale(turned, (r + pull * (out - r)) / r);
    }
  }
  if (yaw) {
    const w = bump((q[0] * q[0] + q[1] * q[1]) / (2.2 * eye.r) ** 2) * radial;
    turned = rotY(turned, yaw * w);
  }
  const d = sub(turned, q);
  return d[0] || d[1] || d[2] ? d : null;
}

// The lower face (jaw) weight: below the slit, in front of the jaw's pivot, not the neck.
function jawWeight(f, p, i) {
  const [x, y, z] = p;
  const s = f.s;
  const ax = Math.abs(x);
  const band = 0.0008 * s + 0.6 * Math.max(0, ax - f.mouthHalf * 0.9);
  let below = smoothstep(-band, band, f.slitY(x) - y);
  // The lips' edges by side (toward the corners, by height again).
  const edge = f.seam.get(i);
  if (edge) below += (edge < 0 ? 1 - below : -below) * (1 - smoothstep(0.8, 1, ax / f.mouthHalf));
  const front = smoothstep(f.pivot[2] + 0.01 * s, f.pivot[2] + 0.06 * s, z);
  const side = 1 - smoothstep(0.05 * s, 0.075 * s, ax);
  const chin = smoothstep(f.mouth[1] - 0.1 * s, f.mouth[1] - 0.055 * s, y);
  return below * front * side * chin;
}
// The jaw's turn at jawOpen 1 (radians about `pivot`): the lower lip drops about 2.4 cm at the
// midline on the adult bodies (with aa's mouthLowerDown, 2.5 cm between the lips).
const JAW_TURN = 0.24;
// How far (m, for the base mesh) jawOpen takes the lips' edges back into the mouth.
const SEAM_TUCK = 0.004;
function jawTurn(f, p, w, a = JAW_TURN) {
  const q = sub(p, f.pivot);
  return scale(sub(rotX(q, a), q), w);
}

// The lips' edges (the seam's vertices): 1 over the middle of the mouth, fading out toward the
// corners (where the seam's faces are short and fan out onto the lips); 0 elsewhere.
function lipEdge(f, p, i) {
  if (!f.seam.has(i)) return 0;
  return 1 - smoothstep(0.75, 1, Math.abs(p[0]) / f.mouthHalf);
}

// The lips: a band around the slit, out to past the corners, in front.
function lipWeight(f, p) {
  const s = f.s;
  const u = Math.abs(p[0]) / (f.mouthHalf * 1.2);
  const dv = (p[1] - f.mouth[1]) / (0.013 * s);
  const front = smoothstep(f.mouth[2] - 0.035 * s, f.mouth[2] - 0.015 * s, p[2]);
  return (1 - smoothstep(0.75, 1, u)) * (1 - smoothstep(0.55, 1, Math.abs(dv))) * front;
}
// Above the slit (1) or below (0); the lips' edges by side (toward the corners, by height).
function upperSide(f, p, i) {
  const u = smoothstep(-0.0008 * f.s, 0.0008 * f.s, p[1] - f.slitY(p[0]));
  const side = f.seam.get(i);
  return side ? u + ((side > 0 ? 1 : 0) - u) * (1 - smoothstep(0.8, 1, Math.abs(p[0]) / f.mouthHalf)) : u;
}
// The left half of the mouth fading across the midline.
const leftHalf = (f, p) => smoothstep(-0.006 * f.s, 0.006 * f.s, p[0]);
// A bump around a point (x, y) on the face (front of the head only), radius rx, ry.
function faceBump(f, p, cx, cy, rx, ry, zmin) {
  if (p[2] < zmin) return 0;
  const dx = (p[0] - cx) / rx;
  const dy = (p[1] - cy) / ry;
  return bump(dx * dx + dy * dy);
}
function cornerWeight(f, p, r = 0.017) {
  const c = [f.mouthHalf, f.mouth[1], f.mouth[2] - 0.012 * f.s];
  const d = sub(p, c);
  return p[2] < f.mouth[2] - 0.04 * f.s ? 0 : bump(dot(d, d) / (r * f.s) ** 2);
}

/**
 * The shapes of the left side (and the symmetric ones): name -> (f, p) -> delta or null.
 * Right-side shapes are the left ones mirrored (x -> -x).
 */
const LEFT = {
  // A blink: the upper lid comes down over the ball to just below the lower lid's margin (the
  // lower lid moves down a little to meet it), its fold unfolding onto a sphere over the eyeball
  // (see `lids`). Closing 40% up the opening with both lids (the squint's line) read as a
  // squint to FaceLandmarker (docs/measurements/2026-12-06-face.md).
  eyeBlink: (f, p) => lids(f, p, 1, 1, 0, BLINK_LID),
  eyeLookDown: (f, p) => lids(f, p, 0.35, -0.3),
  eyeLookIn: (f, p) => lids(f, p, 0, 0, -0.08),
  eyeLookOut: (f, p) => lids(f, p, 0, 0, 0.08),
  eyeLookUp: (f, p) => lids(f, p, -0.25, -0.15),
  eyeSquint: (f, p) => lids(f, p, 0.15, 0.45),
  eyeWide: (f, p) => lids(f, p, -0.6, -0.2),
  mouthSmile: (f, p) => {
    const w = cornerWeight(f, p, 0.022);
    return w ? scale([0.006, 0.007, -0.004], w * f.s) : null;
  },
  mouthFrown: (f, p) => {
    const w = cornerWeight(f, p, 0.02);
    return w ? scale([0.001, -0.007, 0], w * f.s) : null;
  },
  mouthDimple: (f, p) => {
    const w = cornerWeight(f, p, 0.018);
    return w ? scale([0.004, 0, -0.004], w * f.s) : null;
  },
  mouthStretch: (f, p) => {
    const w = cornerWeight(f, p, 0.022);
    return w ? scale([0.007, -0.003, -0.001], w * f.s) : null;
  },
  mouthPress: (f, p, i) => {
    const w = lipWeight(f, p) * leftHalf(f, p);
    return w ? scale([0, upperSide(f, p, i) > 0.5 ? -0.0015 : 0.0015, -0.0015], w * f.s) : null;
  },
  mouthLowerDown: (f, p, i) => {
    const w = lipWeight(f, p) * (1 - upperSide(f, p, i)) * leftHalf(f, p);
    return w ? scale([0, -0.005, 0.0005], w * f.s) : null;
  },
  mouthUpperUp: (f, p, i) => {
    const w = lipWeight(f, p) * upperSide(f, p, i) * leftHalf(f, p);
    return w ? scale([0, 0.005, 0.0005], w * f.s) : null;
  },
  browDown: (f, p) => {
    const e = f.eyeL;
    const w = faceBump(f, p, e.c[0], e.c[1] + 1.8 * e.r, 1.9 * e.r, 1.1 * e.r, e.c[2]);
    return w ? scale([-0.0015, -0.005, 0.0005], w * f.s) : null;
  },
  browOuterUp: (f, p) => {
    const e = f.eyeL;
    const w = faceBump(f, p, e.c[0] + 0.9 * e.r, e.c[1] + 1.9 * e.r, 1.3 * e.r, 1.2 * e.r, e.c[2] - e.r);
    return w ? scale([0, 0.006, 0], w * f.s) : null;
  },
  cheekSquint: (f, p) => {
    const e = f.eyeL;
    const w = faceBump(f, p, e.c[0] + 0.2 * e.r, e.c[1] - 1.9 * e.r, 1.6 * e.r, 0.9 * e.r, e.c[2] - 0.5 * e.r);
    return w ? scale([0, 0.004, 0.001], w * f.s) : null;
  },
  noseSneer: (f, p) => {
    const w = faceBump(f, p, 0.011 * f.s, f.mouth[1] + 0.032 * f.s, 0.012 * f.s, 0.012 * f.s, f.mouth[2] - 0.02 * f.s);
    return w ? scale([0.0005, 0.003, 0], w * f.s) : null;
  },
};

const SYMMETRIC = {
  // The jaw turned down about its pivot; the lips' edges (the seam) tucked in behind the lips,
  // so that the seam's faces, stretched over the opening, lie inside the mouth.
  jawOpen: (f, p, i) => {
    const w = jawWeight(f, p, i);
    const e = lipEdge(f, p, i);
    if (!w && !e) return null;
    return add(w ? jawTurn(f, p, w) : [0, 0, 0], [0, 0, -SEAM_TUCK * f.s * e]);
  },
  jawForward: (f, p, i) => {
    const w = jawWeight(f, p, i);
    return w ? scale([0, 0, 0.006], w * f.s) : null;
  },
  jawLeft: (f, p, i) => {
    const w = jawWeight(f, p, i);
    return w ? scale([0.008, 0, 0], w * f.s) : null;
  },
  jawRight: (f, p, i) => {
    const w = jawWeight(f, p, i);
    return w ? scale([-0.008, 0, 0], w * f.s) : null;
  },
  // With jawOpen: the lips closed again over the open jaw (ARKit's use).
  mouthClose: (f, p, i) => {
    const w = lipWeight(f, p);
    if (!w) return null;
    const up = upperSide(f, p, i);
    const jaw = jawTurn(f, p, jawWeight(f, p, i));
    const half = scale(jawTurn(f, [p[0], f.mouth[1] - 0.002 * f.s, p[2]], 1), 0.5);
    return scale(up > 0.5 ? half : sub(half, jaw), w);
  },
  mouthFunnel: (f, p, i) => {
    const w = lipWeight(f, p);
    if (!w) return null;
    // The lips part most at the middle (a round opening, not a slot): 5 mm each there, none at
    // the corners, which come in.
    const u = Math.min(1, Math.abs(p[0]) / f.mouthHalf);
    const open = (upperSide(f, p, i) > 0.5 ? 0.005 : -0.005) * (1 - u * u);
    return scale([-0.3 * p[0] / f.s, open, 0.006], w * f.s);
  },
  mouthPucker: (f, p) => {
    const w = lipWeight(f, p);
    return w ? scale([-0.4 * p[0] / f.s, 0, 0.007], w * f.s) : null;
  },
  mouthLeft: (f, p) => {
    const w = lipWeight(f, p);
    return w ? scale([0.007, 0, 0], w * f.s) : null;
  },
  mouthRight: (f, p) => {
    const w = lipWeight(f, p);
    return w ? scale([-0.007, 0, 0], w * f.s) : null;
  },
  mouthRollLower: (f, p, i) => {
    const w = lipWeight(f, p) * (1 - upperSide(f, p, i));
    return w ? scale([0, 0.001, -0.004], w * f.s) : null;
  },
  mouthRollUpper: (f, p, i) => {
    const w = lipWeight(f, p) * upperSide(f, p, i);
    return w ? scale([0, -0.001, -0.004], w * f.s) : null;
  },
  mouthShrugLower: (f, p, i) => {
    const w = lipWeight(f, p) * (1 - upperSide(f, p, i));
    return w ? scale([0, 0.003, 0.002], w * f.s) : null;
  },
  mouthShrugUpper: (f, p, i) => {
    const w = lipWeight(f, p) * upperSide(f, p, i);
    return w ? scale([0, 0.0025, 0.001], w * f.s) : null;
  },
  browInnerUp: (f, p) => {
    const e = f.eyeL;
    const w = faceBump(f, p, 0, e.c[1] + 1.8 * e.r, 1.6 * e.r, 1.2 * e.r, e.c[2] - 0.3 * e.r);
    return w ? scale([0, 0.006, 0], w * f.s) : null;
  },
  cheekPuff: (f, p) => {
    const ax = Math.abs(p[0]);
    const w = faceBump(f, [ax, p[1], p[2]], 0.04 * f.s, f.mouth[1] + 0.012 * f.s, 0.022 * f.s, 0.024 * f.s, f.pivot[2] + 0.02 * f.s);
    return w ? scale([Math.sign(p[0]) * 0.005, 0, 0.004], w * f.s) : null;
  },
  // No tongue in the mesh (the base mesh's tongue helper is dropped): the lower lip drops
  // forward, as it does around a tongue stuck out.
  tongueOut: (f, p, i) => {
    const w = lipWeight(f, p) * (1 - upperSide(f, p, i));
    return w ? scale([0, -0.004, 0.004], w * f.s) : null;
  },
};

function shapeOf(name) {
  if (SYMMETRIC[name]) return SYMMETRIC[name];
  const m = /^(.*)(Left|Right)$/.exec(name);
  const left = LEFT[m[1]];
  if (m[2] === "Left") return left;
  // The right side: the field of the left evaluated on the mirrored point, mirrored back.
  return (f, p, i) => {
    const fm = { ...f, eyeL: { ...f.eyeR, c: mirror(f.eyeR.c) }, lidL: f.lidR };
    const d = left(fm, mirror(p), i);
    return d ? mirror(d) : null;
  };
}

/**
 * The face of one body: `positions` (Float64Array, mesh frame, every base vertex), the base
 * mesh's `groups`, the `kept` vertices in file order. Returns the morph targets (`name`,
 * sparse `indices` into the kept vertices, Float32 `deltas`), in ARKit order.
 */
export function faceTargets(positions, groups, kept, bodyFaces) {
  const v = (i) => [positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]];
  const bodyCount = groups.body[0][1] + 1;
  const tris = [];
  for (const q of bodyFaces) for (let k = 1; k + 1 < q.length; k++) tris.push([q[0], q[k], q[k + 1]]);
  const f = measure(v, groups, tris);
  slit(f, v);
  const targets = [];
  for (const name of ARKIT) {
    const shape = shapeOf(name);
    const indices = [];
    const deltas = [];
    kept.forEach((vi, k) => {
      if (vi >= bodyCount) return; // the eyes turn with their bones, never morph
      const d = shape(f, v(vi), vi);
      if (!d) return;
      const d32 = d.map(Math.fround);
      if (Math.max(Math.abs(d32[0]), Math.abs(d32[1]), Math.abs(d32[2])) < 1e-5) return;
      indices.push(k);
      deltas.push(...d32);
    });
    targets.push({ name, indices: Uint16Array.from(indices), deltas: Float32Array.from(deltas) });
  }
  return { targets, measures: f };
}

// ---------------------------------------------------------------------------------------------
// Colours (linear RGB, as glTF's COLOR_0): the render bench's regions (eval/bench/render-page.js)

export const COLOURS = {
  skin: [0.72, 0.45, 0.33],
  top: [0.08, 0.2, 0.45],
  trousers: [0.09, 0.09, 0.1],
  shoes: [0.25, 0.12, 0.05],
  hair: [0.05, 0.03, 0.02],
  mouth: [0.03, 0.006, 0.006],
  sclera: [0.85, 0.83, 0.8],
  iris: [0.12, 0.22, 0.35],
  pupil: [0.01, 0.01, 0.01],
};
const REGION = {
  pelvis: "trousers", thigh_l: "trousers", thigh_r: "trousers", calf_l: "trousers", calf_r: "trousers",
  foot_l: "shoes", foot_r: "shoes", ball_l: "shoes", ball_r: "shoes",
  spine_01: "top", spine_02: "top", spine_03: "top", clavicle_l: "top", clavicle_r: "top",
  upperarm_l: "top", upperarm_r: "top",
};

/**
 * COLOR_0 of the kept vertices (RGBA, normalized unsigned bytes): the outfit by each vertex's
 * dominant bone (a top over the torso and upper arms, trousers, shoes), hair on the skull above
 * the brows and the back of the head, the mouth's inside, and on the eyes a pupil and iris
 * around each eye's forward axis, the sclera elsewhere.
 */
export function faceColours(positions, groups, kept, weights, skeleton, measures) {
  const v = (i) => [positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]];
  const bodyCount = groups.body[0][1] + 1;
  const f = measures;
  const head = skeleton.find((b) => b.name === "head");
  const eyeY = f.eyeL.c[1];
  const out = new Uint8Array(4 * kept.length);
  const forward = (eye, target) => normalize(sub(target, eye));
  const eyeAxis = {
    l: forward(f.eyeL.c, skeleton.find((b) => b.name === "eye_l").tail),
    r: forward(f.eyeR.c, skeleton.find((b) => b.name === "eye_r").tail),
  };
  // The mouth's inside: skin with skin in front of it (within 3 mm across, 6 mm ahead).
  const near = [];
  for (let i = 0; i < bodyCount; i++) {
    const p = v(i);
    if (Math.abs(p[0]) < f.mouthHalf * 1.2 && Math.abs(p[1] - f.mouth[1]) < 0.04 * f.s && p[2] > f.pivot[2]) near.push(p);
  }
  const occluded = (p) => near.some((o) => Math.abs(o[0] - p[0]) < 0.003 && Math.abs(o[1] - p[1]) < 0.003 && o[2] > p[2] + 0.006);
  kept.forEach((vi, k) => {
    const p = v(vi);
    let region;
    if (vi >= bodyCount) {
      const left = p[0] > 0;
      const e = left ? f.eyeL : f.eyeR;
      const c = dot(normalize(sub(p, e.c)), left ? eyeAxis.l : eyeAxis.r);
      region = c > 0.96 ? "pupil" : c > 0.88 ? "iris" : "sclera";
    } else {
      const bone = skeleton[weights[vi][0][0]].name;
      region = REGION[bone] ?? "skin";
      if (bone === "head" || bone === "neck_01") {
        const s = f.s;
        const inMouth =
          Math.abs(p[0]) < 0.9 * f.mouthHalf &&
          p[1] - f.mouth[1] < 0.015 * s &&
          f.mouth[1] - p[1] < 0.025 * s &&
          p[2] > f.pivot[2] &&
          p[2] < f.mouth[2] - 0.008 * s &&
          occluded(p);
        // The seam's faces, stretched over an opening, are dark by a material of their own
        // (`isSeamFace`), so the lips' edges keep the skin's colour. Only inside vertices
        // behind the lips' front: 8 mm in front of a crease, the upper lip's skin under the
        // philtrum read as occluded (a red patch above the lip).
        if (inMouth) region = "mouth";
        else if (bone === "head" && (p[1] > eyeY + 0.045 * s || (p[2] < head.head[2] - 0.026 * s && p[1] > eyeY - 0.06 * s))) region = "hair";
      }
    }
    const c = COLOURS[region];
    for (let j = 0; j < 3; j++) out[4 * k + j] = Math.round(255 * c[j]);
    out[4 * k + 3] = 255;
  });
  return out;
}
