// The ground-truth motions of the bench (issue 47): keyframed arm, upper-body and finger
// motion authored for handrig (CC0, our own), as per-frame rotations of the VRM 1.0
// *normalized* humanoid bones (three-vrm's normalized rig: identity rest, world axes; the avatar
// faces +Z, its right hand is at -X, the T-pose palms face -Y).
//
// Plain JavaScript without dependencies: the renderer (render-page.js in Chromium) and the
// scorer (score.mjs in Node) import this one file, so the truth is this code.
//
//   import { CLIPS, clipPose } from "./motions.mjs";
//   clipPose(CLIPS.find((c) => c.id === "wave"), 12)  // -> { rightUpperArm: [x, y, z, w], ... }
//
// Joint angles (degrees) are given per side for the right side and mirrored (x -> -x) for the
// left. Every angle stays inside the usual adult ranges of motion (AAOS / Norkin & White):
// shoulder flexion 0-180, abduction 0-180, horizontal adduction 0-130, rotation -90..+70;
// elbow flexion 0-145; forearm pronation/supination +-80; wrist flexion 80, extension 70,
// radial 20, ulnar 30; finger MCP 0-90 (abduction +-20), PIP 0-100, DIP 0-80; thumb CMC
// flexion 0-15 / palmar abduction 0-70, MCP 0-55, IP 0-80 (-10 hyperextension).

export const FPS = 30;

/**
 * The allowed range (degrees) of every angle of the joint models below, from the ranges of
 * motion above; www/tests/bench-render.test.mjs checks every frame of every clip against it.
 * "down" is 90 - shoulder abduction; finger.N and thumb.N index the hand-shape tuples.
 */
export const RANGES = {
  "upperArm.down": [0, 90], "upperArm.flex": [0, 180], "upperArm.hadd": [0, 130], "upperArm.rot": [-70, 90],
  "lowerArm.flex": [0, 145], "lowerArm.pro": [-80, 80], "hand.flex": [-70, 80], "hand.dev": [-30, 20],
  "shape.finger.0": [-10, 90], "shape.finger.1": [0, 100], "shape.finger.2": [0, 80], "shape.finger.3": [-20, 20],
  "shape.thumb.0": [0, 15], "shape.thumb.1": [-15, 70], "shape.thumb.2": [0, 55], "shape.thumb.3": [-10, 80],
};

const D = Math.PI / 180;
const AXES = { x: [1, 0, 0], y: [0, 1, 0], z: [0, 0, 1] };

export function qAxis(axis, deg) {
  const a = typeof axis === "string" ? AXES[axis] : axis;
  const l = Math.hypot(a[0], a[1], a[2]);
  const s = Math.sin((deg * D) / 2) / l;
  return [a[0] * s, a[1] * s, a[2] * s, Math.cos((deg * D) / 2)];
}
export function qMul(a, b) {
  return [
    a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
    a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
    a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
    a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2],
  ];
}
/** Rotations applied in the order given (first = innermost). */
const compose = (...qs) => qs.reduce((acc, q) => qMul(q, acc), [0, 0, 0, 1]);
/** The right side's rotation mirrored to the left (reflection x -> -x). */
const mirror = (q) => [q[0], -q[1], -q[2], q[3]];

// ---- joint models (right side; normalized frame, T-pose rest) ---------------------------------
// Upper arm: `down` lowers the arm from the T-pose (90 = hanging), `flex` raises it forwards
// (shoulder flexion), `hadd` swings the raised arm across the body, `rot` turns it about its
// own axis (positive = external rotation: the forearm of a bent elbow goes up/out).
const upperArm = ({ down = 0, flex = 0, hadd = 0, rot = 0 }) =>
  compose(qAxis("x", -rot), qAxis("z", down), qAxis("x", -flex), qAxis("y", hadd));
// Elbow flexion (the forearm comes forwards from the hanging arm), then forearm pronation
// (+) / supination (-) about the forearm.
const lowerArm = ({ flex = 0, pro = 0 }) => compose(qAxis("x", pro), qAxis("y", flex));
// Wrist: flexion (+, towards the palm) and radial deviation (+, towards the thumb).
const hand = ({ flex = 0, dev = 0 }) => compose(qAxis("y", dev), qAxis("z", flex));
// Long fingers: flexion about the palm's transverse axis, MCP abduction (+ = towards the thumb).
const finger = (flex, abd = 0) => compose(qAxis("z", flex), qAxis("y", abd));
// Thumb (its rest points forwards-down-outwards from the palm's radial edge): flexion curls it
// towards the palm; at the CMC `opp` swings it across the palm (opposition) about the palm normal.
const THUMB_DIR = [-0.55, -0.55, 0.63];
const THUMB_FLEX_AXIS = [0.63, 0, 0.55]; // THUMB_DIR x palm normal (0, -1, 0)
const thumb = (flex, opp = 0) => compose(qAxis(THUMB_FLEX_AXIS, flex), qAxis("y", -opp));

// A hand shape: per finger [MCP, PIP, DIP] flexion and MCP abduction; thumb [CMC flex,
// CMC opposition, MCP, IP].
const shape = (o) => ({ ...o });
const SHAPES = {
  open: shape({ index: [5, 5, 3, 0], middle: [5, 5, 3, 0], ring: [5, 5, 3, 0], little: [5, 5, 3, 0], thumb: [0, 0, 5, 5] }),
  spread: shape({ index: [0, 0, 0, 15], middle: [0, 0, 0, 2], ring: [0, 0, 0, -10], little: [0, 0, 0, -20], thumb: [0, -10, 0, -5] }),
  fist: shape({ index: [85, 95, 60, 0], middle: [88, 98, 60, 0], ring: [88, 98, 60, 0], little: [85, 95, 60, 0], thumb: [10, 40, 45, 40] }),
  relaxed: shape({ index: [25, 30, 15, 2], middle: [30, 35, 20, 0], ring: [35, 40, 20, -2], little: [40, 45, 25, -5], thumb: [5, 15, 15, 15] }),
  pinch: shape({ index: [45, 55, 20, 0], middle: [20, 15, 10, 0], ring: [15, 10, 5, 0], little: [10, 10, 5, -5], thumb: [10, 50, 30, 20] }),
  point: shape({ index: [0, 0, 0, 0], middle: [85, 95, 55, 0], ring: [88, 98, 55, 0], little: [85, 95, 55, 0], thumb: [10, 45, 40, 35] }),
  vee: shape({ index: [0, 0, 0, 12], middle: [0, 0, 0, -8], ring: [85, 95, 55, 0], little: [85, 95, 55, 0], thumb: [10, 45, 40, 35] }),
  ily: shape({ index: [0, 0, 0, 5], middle: [85, 95, 55, 0], ring: [88, 98, 55, 0], little: [0, 0, 0, -15], thumb: [0, -10, 0, 0] }),
  yShape: shape({ index: [85, 95, 55, 0], middle: [88, 98, 55, 0], ring: [88, 98, 55, 0], little: [0, 0, 0, -15], thumb: [0, -10, 0, 0] }),
  flatO: shape({ index: [55, 40, 20, 0], middle: [55, 40, 20, 0], ring: [55, 40, 20, 0], little: [55, 40, 20, 0], thumb: [10, 45, 25, 20] }),
};

/** Local rotations of the normalized finger bones of one hand for a hand shape. */
function handShapeBones(side, s) {
  const out = {};
  const m = side === "right" ? (q) => q : mirror;
  for (const [f, Cap] of [["index", "Index"], ["middle", "Middle"], ["ring", "Ring"], ["little", "Little"]]) {
    const [mcp, pip, dip, abd] = s[f];
    out[`${side}${Cap}Proximal`] = m(finger(mcp, abd));
    out[`${side}${Cap}Intermediate`] = m(finger(pip));
    out[`${side}${Cap}Distal`] = m(finger(dip));
  }
  const [cmc, opp, mcp, ip] = s.thumb;
  out[`${side}ThumbMetacarpal`] = m(thumb(cmc, opp));
  out[`${side}ThumbProximal`] = m(thumb(mcp));
  out[`${side}ThumbDistal`] = m(thumb(ip));
  return out;
}

// ---- key poses -------------------------------------------------------------------------------
// A key pose: { right: { upperArm, lowerArm, hand, shape }, left: {...}, spine: {...} }; missing
// parts are the rest posture (arms hanging slightly away from the body, elbows a little bent,
// relaxed hands).
const REST_ARM = { upperArm: { down: 75 }, lowerArm: { flex: 12 }, hand: {}, shape: "relaxed" };
// The hand-clip posture: the right hand raised before the shoulder, fingers up, palm to the
// camera (upper arm hanging forwards, elbow bent, forearm pronated, wrist a little extended).
const HAND_UP = { upperArm: { down: 80, flex: 25, hadd: 0, rot: 0 }, lowerArm: { flex: 125, pro: 80 }, hand: { flex: -15 } };

const CLIPS_DEF = [
  // ---- body clips (camera about 2 m before the chest) ----
  {
    id: "reach", kind: "body", frames: 75,
    keys: [
      [0, {}],
      [30, { right: { upperArm: { down: 80, flex: 95, hadd: 10 }, lowerArm: { flex: 5, pro: 20 }, hand: { flex: -10 }, shape: "open" } }],
      [45, { right: { upperArm: { down: 80, flex: 95, hadd: 10 }, lowerArm: { flex: 5, pro: 20 }, hand: { flex: -10 }, shape: "pinch" } }],
      [74, { right: { upperArm: { down: 80, flex: 40, hadd: 0 }, lowerArm: { flex: 60, pro: 0 }, hand: { flex: 10 }, shape: "pinch" } }],
    ],
  },
  {
    id: "wave", kind: "body", frames: 75,
    keys: [
      [0, {}],
      [18, { right: { upperArm: { down: 10, rot: 70 }, lowerArm: { flex: 80, pro: 0 }, hand: {}, shape: "open" } }],
      [30, { right: { upperArm: { down: 10, rot: 70 }, lowerArm: { flex: 110, pro: 0 }, hand: { dev: 10 }, shape: "spread" } }],
      [42, { right: { upperArm: { down: 10, rot: 70 }, lowerArm: { flex: 70, pro: 0 }, hand: { dev: -15 }, shape: "spread" } }],
      [54, { right: { upperArm: { down: 10, rot: 70 }, lowerArm: { flex: 110, pro: 0 }, hand: { dev: 10 }, shape: "spread" } }],
      [74, { right: { upperArm: { down: 15, rot: 60 }, lowerArm: { flex: 80, pro: 0 }, hand: { dev: 0 }, shape: "open" } }],
    ],
  },
  {
    id: "face", kind: "body", frames: 75,
    keys: [
      [0, {}],
      [35, { right: { upperArm: { down: 70, flex: 45, hadd: 25 }, lowerArm: { flex: 140, pro: -20 }, hand: { flex: 10 }, shape: "flatO" } }],
      [50, { right: { upperArm: { down: 70, flex: 45, hadd: 25 }, lowerArm: { flex: 140, pro: -20 }, hand: { flex: 10 }, shape: "flatO" } }],
      [74, { right: { upperArm: { down: 72, flex: 25, hadd: 10 }, lowerArm: { flex: 90, pro: 0 }, hand: {}, shape: "relaxed" } }],
    ],
  },
  {
    id: "chest", kind: "body", frames: 75,
    keys: [
      [0, {}],
      [30, { right: { upperArm: { down: 85, flex: 10, hadd: 20 }, lowerArm: { flex: 100, pro: 30 }, hand: { flex: 0 }, shape: "open" } }],
      [50, { right: { upperArm: { down: 85, flex: 15, hadd: 25 }, lowerArm: { flex: 105, pro: 30 }, hand: { flex: 5 }, shape: "open" } }],
      [74, {}],
    ],
  },
  {
    id: "cross", kind: "body", frames: 75,
    keys: [
      [0, {}],
      [35, {
        right: { upperArm: { down: 80, flex: 70, hadd: 45 }, lowerArm: { flex: 70, pro: 30 }, hand: {}, shape: "relaxed" },
        left: { upperArm: { down: 80, flex: 60, hadd: 40 }, lowerArm: { flex: 85, pro: 30 }, hand: {}, shape: "relaxed" },
      }],
      [50, {
        right: { upperArm: { down: 80, flex: 70, hadd: 45 }, lowerArm: { flex: 70, pro: 30 }, hand: {}, shape: "fist" },
        left: { upperArm: { down: 80, flex: 60, hadd: 40 }, lowerArm: { flex: 85, pro: 30 }, hand: {}, shape: "fist" },
      }],
      [74, {}],
    ],
  },
  // ---- hand clips (camera about 0.5 m before the right hand) ----
  {
    id: "fist", kind: "hand", frames: 75,
    keys: [[0, { right: { ...HAND_UP, shape: "open" } }], [25, { right: { ...HAND_UP, shape: "fist" } }], [40, { right: { ...HAND_UP, shape: "fist" } }], [74, { right: { ...HAND_UP, hand: { flex: 5 }, shape: "relaxed" } }]],
  },
  {
    id: "pinch", kind: "hand", frames: 75,
    keys: [[0, { right: { ...HAND_UP, shape: "open" } }], [20, { right: { ...HAND_UP, shape: "pinch" } }], [35, { right: { ...HAND_UP, shape: "flatO" } }], [55, { right: { ...HAND_UP, hand: { flex: -15, dev: 10 }, shape: "pinch" } }], [74, { right: { ...HAND_UP, shape: "open" } }]],
  },
  {
    id: "point", kind: "hand", frames: 75,
    keys: [[0, { right: { ...HAND_UP, shape: "relaxed" } }], [20, { right: { ...HAND_UP, shape: "point" } }], [40, { right: { ...HAND_UP, hand: { flex: 10 }, shape: "point" } }], [74, { right: { ...HAND_UP, shape: "vee" } }]],
  },
  {
    id: "spread", kind: "hand", frames: 75,
    keys: [[0, { right: { ...HAND_UP, shape: "open" } }], [20, { right: { ...HAND_UP, shape: "spread" } }], [40, { right: { ...HAND_UP, shape: "open" } }], [55, { right: { ...HAND_UP, shape: "spread" } }], [74, { right: { ...HAND_UP, hand: { flex: -30 }, shape: "relaxed" } }]],
  },
  {
    id: "signs", kind: "hand", frames: 90,
    keys: [[0, { right: { ...HAND_UP, shape: "open" } }], [15, { right: { ...HAND_UP, shape: "vee" } }], [30, { right: { ...HAND_UP, shape: "vee" } }], [45, { right: { ...HAND_UP, shape: "ily" } }], [60, { right: { ...HAND_UP, shape: "yShape" } }], [75, { right: { ...HAND_UP, shape: "flatO" } }], [89, { right: { ...HAND_UP, shape: "fist" } }]],
  },
];

// ---- interpolation ---------------------------------------------------------------------------
// Every key pose is flattened to joint angles; angles are interpolated between keys with a
// smoothstep ease (velocity 0 at each key), then turned into rotations.
function flatten(pose) {
  const out = {};
  for (const side of ["right", "left"]) {
    const p = { ...REST_ARM, ...(pose[side] ?? {}) };
    for (const part of ["upperArm", "lowerArm", "hand"]) {
      for (const [k, v] of Object.entries(p[part] ?? {})) out[`${side}.${part}.${k}`] = v;
    }
    const s = SHAPES[p.shape];
    if (!s) throw new Error(`unknown hand shape ${p.shape}`);
    for (const [f, vals] of Object.entries(s)) vals.forEach((v, i) => (out[`${side}.shape.${f}.${i}`] = v));
  }
  return out;
}
const DEFAULTS = {
  "upperArm.down": 0, "upperArm.flex": 0, "upperArm.hadd": 0, "upperArm.rot": 0,
  "lowerArm.flex": 0, "lowerArm.pro": 0, "hand.flex": 0, "hand.dev": 0,
};
const valueOf = (flat, key) => flat[key] ?? DEFAULTS[key.slice(key.indexOf(".") + 1)] ?? 0;

/** Joint angles (degrees) of a clip at frame `i`: { "right.upperArm.down": 75, ... }. */
export function clipAngles(clip, i) {
  const keys = clip.keys.map(([t, pose]) => [t, flatten(pose)]);
  let k = 0;
  while (k < keys.length - 2 && i > keys[k + 1][0]) k++;
  const [t0, a] = keys[k];
  const [t1, b] = keys[Math.min(k + 1, keys.length - 1)];
  const u = t1 > t0 ? Math.min(1, Math.max(0, (i - t0) / (t1 - t0))) : 0;
  const e = u * u * (3 - 2 * u);
  const out = {};
  for (const key of new Set([...Object.keys(a), ...Object.keys(b)])) {
    const va = valueOf(a, key);
    out[key] = va + (valueOf(b, key) - va) * e;
  }
  return out;
}

/** Normalized-bone local rotations ([x, y, z, w]) of a clip at frame `i`: the truth. */
export function clipPose(clip, i) {
  const a = clipAngles(clip, i);
  const out = {};
  for (const side of ["right", "left"]) {
    const g = (k) => a[`${side}.${k}`] ?? DEFAULTS[k] ?? 0;
    const m = side === "right" ? (q) => q : mirror;
    out[`${side}UpperArm`] = m(upperArm({ down: g("upperArm.down"), flex: g("upperArm.flex"), hadd: g("upperArm.hadd"), rot: g("upperArm.rot") }));
    out[`${side}LowerArm`] = m(lowerArm({ flex: g("lowerArm.flex"), pro: g("lowerArm.pro") }));
    out[`${side}Hand`] = m(hand({ flex: g("hand.flex"), dev: g("hand.dev") }));
    const s = {};
    for (const f of ["index", "middle", "ring", "little", "thumb"]) s[f] = [0, 1, 2, 3].map((j) => g(`shape.${f}.${j}`));
    Object.assign(out, handShapeBones(side, s));
  }
  return out;
}

export const CLIPS = CLIPS_DEF;
export const clipById = (id) => {
  const c = CLIPS.find((x) => x.id === id);
  if (!c) throw new Error(`no clip "${id}" (have ${CLIPS.map((x) => x.id).join(", ")})`);
  return c;
};
