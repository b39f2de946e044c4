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
  // A C shape (hungry's curved hand): every finger bent at each joint, the thumb across from them.
  curved: shape({ index: [35, 45, 25, 0], middle: [38, 48, 25, 0], ring: [40, 50, 25, -2], little: [42, 52, 28, -5], thumb: [5, 35, 15, 15] }),
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

/**
 * Puts the truth `q` (a clipPose / legClipPose bone map) on a three-vrm VRM's normalized bones:
 * the bones `q` names turned, every other one at rest (identity). The caller updates the VRM.
 */
export function setNormalizedPose(vrm, q) {
  for (const name of Object.keys(vrm.humanoid.humanBones)) {
    const node = vrm.humanoid.getNormalizedBoneNode(name);
    if (!node) continue;
    const r = q[name];
    if (r) node.quaternion.set(r[0], r[1], r[2], r[3]);
    else node.quaternion.identity();
  }
}

export const CLIPS = CLIPS_DEF;
export const clipById = (id) => {
  const c = CLIPS.find((x) => x.id === id);
  if (!c) throw new Error(`no clip "${id}" (have ${CLIPS.map((x) => x.id).join(", ")})`);
  return c;
};

// ---- leg clips (issue 51) -----------------------------------------------------------------------
// Whole-body motion: the hips' room position and both feet, keyframed in units of the avatar's
// leg length L (the rest hip joint's height above the floor), turned into rotations of the hips'
// children by two-bone IK on the avatar's own rest skeleton (so a planted foot stays exactly
// where it was put down, on every avatar). Per key and side: `lift` (the ankle's rise above its
// rest height), `x` (outwards: + is the avatar's left for the left foot and its right for the
// right foot), `z` (forwards), `pitch` (the foot's toes-down turn, degrees); for the hips `x`
// (+ = the avatar's left), `z` (forwards) and `drop` (down). The hips stay upright (identity);
// the standing legs' hips come down only as far as the feet need to reach (at most 99.9% of the
// leg's length), the knee bends forwards (its pole), the feet stay level but for `pitch`; the
// arms hang at the arm clips' rest posture. The floor is y = 0 (VRM avatars stand on it).
//
//   legClipPose(clip, i, rest) -> { bones: { leftUpperLeg: [x, y, z, w], ... }, hipsOffset: [x, y, z] }
//
// `rest`: world positions at rest of the normalized hips, upper legs, lower legs, feet and toes
// ({ hips: [x, y, z], leftUpperLeg: ..., ... }, restOfLegs below reads them from three-vrm).

/** Leg ranges (degrees) the truth keeps inside (the leg page's limits, docs/how-it-works/legs.md). */
export const LEG_RANGES = { kneeFlex: [0, 150], hipFlex: [-30, 120], ankleDorsi: [-50, 40] };

const FOOT = { lift: 0, x: 0, z: 0, pitch: 0 };
const HIPS = { x: 0, z: 0, drop: 0 };
const LEG_CLIPS_DEF = [
  {
    // Walking in place: each foot up 0.22 L and 0.06 L forward with its toes down, the weight
    // shifted over the standing foot; a step a side every 15 frames (a stride of 1 s).
    id: "walk", kind: "legs", frames: 120,
    keys: (() => {
      const k = [[0, {}], [8, {}]];
      for (let c = 0; c < 3; c++) {
        const t = 8 + 30 * c;
        k.push([t + 7, { hips: { x: -0.04 }, left: { lift: 0.22, z: 0.06, pitch: 15 } }]);
        k.push([t + 15, { hips: { x: 0 } }]);
        k.push([t + 22, { hips: { x: 0.04 }, right: { lift: 0.22, z: 0.06, pitch: 15 } }]);
        k.push([t + 30, {}]);
      }
      k.push([119, {}]);
      return k;
    })(),
  },
  {
    // A step sideways to the avatar's left and back: the left foot out 0.3 L, the hips over
    // it, the right foot after; then the right foot back, the hips, the left foot.
    id: "sidestep", kind: "legs", frames: 120,
    keys: [
      [0, {}], [10, {}],
      [20, { hips: { x: 0.04 }, left: { lift: 0.1, x: 0.15 } }],
      [30, { hips: { x: 0.08 }, left: { x: 0.3 } }],
      [45, { hips: { x: 0.26 }, left: { x: 0.3 } }],
      [53, { hips: { x: 0.3 }, left: { x: 0.3 }, right: { lift: 0.1, x: -0.15 } }],
      [62, { hips: { x: 0.3 }, left: { x: 0.3 }, right: { x: -0.3 } }],
      [72, { hips: { x: 0.3 }, left: { x: 0.3 }, right: { x: -0.3 } }],
      [80, { hips: { x: 0.26 }, left: { x: 0.3 }, right: { lift: 0.1, x: -0.15 } }],
      [90, { hips: { x: 0.2 }, left: { x: 0.3 } }],
      [102, { hips: { x: 0.04 }, left: { x: 0.3 } }],
      [108, { hips: { x: 0 }, left: { lift: 0.1, x: 0.15 } }],
      [116, {}], [119, {}],
    ],
  },
  {
    // Two squats, feet planted: down 0.35 L sitting back 0.12 L in 1 s, held, up in 1 s;
    // then a shallower one (0.25 L).
    id: "squat", kind: "legs", frames: 120,
    keys: [
      [0, {}], [8, {}],
      [38, { hips: { drop: 0.35, z: -0.12 } }],
      [46, { hips: { drop: 0.35, z: -0.12 } }],
      [74, {}],
      [96, { hips: { drop: 0.25, z: -0.08 } }],
      [119, {}],
    ],
  },
  {
    // Standing on the right leg: the weight over it, the left foot up 0.35 L and 0.1 L forward
    // (toes down 20 degrees), held 1.3 s, and down again.
    id: "oneleg", kind: "legs", frames: 120,
    keys: [
      [0, {}], [8, {}],
      [22, { hips: { x: -0.07 } }],
      [40, { hips: { x: -0.08 }, left: { lift: 0.35, z: 0.1, pitch: 20 } }],
      [80, { hips: { x: -0.08 }, left: { lift: 0.35, z: 0.1, pitch: 20 } }],
      [96, { hips: { x: -0.07 } }],
      [110, {}], [119, {}],
    ],
  },
];

/** The keyframed channels of a leg clip at frame `i` (smoothstep between keys, as the arm clips). */
export function legChannels(clip, i) {
  const flat = (pose) => {
    const out = {};
    for (const [part, def] of [["hips", HIPS], ["left", FOOT], ["right", FOOT]]) {
      for (const [k, v] of Object.entries(def)) out[`${part}.${k}`] = pose[part]?.[k] ?? v;
    }
    return out;
  };
  const keys = clip.keys;
  let k = 0;
  while (k < keys.length - 2 && i > keys[k + 1][0]) k++;
  const [t0, pa] = keys[k];
  const [t1, pb] = keys[Math.min(k + 1, keys.length - 1)];
  const a = flat(pa);
  const b = flat(pb);
  const u = t1 > t0 ? Math.min(1, Math.max(0, (i - t0) / (t1 - t0))) : 0;
  const e = u * u * (3 - 2 * u);
  const out = {};
  for (const key of Object.keys(a)) out[key] = a[key] + (b[key] - a[key]) * e;
  return out;
}

const v3 = {
  sub: (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]],
  add: (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]],
  scale: (a, s) => [a[0] * s, a[1] * s, a[2] * s],
  dot: (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2],
  cross: (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]],
  len: (a) => Math.hypot(a[0], a[1], a[2]),
};
v3.norm = (a) => v3.scale(a, 1 / v3.len(a));
/** Rotation matrix (columns d, x', d x x') of a direction and an axis made perpendicular to it. */
function frameOf(d, x) {
  const dn = v3.norm(d);
  const xn = v3.norm(v3.sub(x, v3.scale(dn, v3.dot(x, dn))));
  return [dn, xn, v3.cross(dn, xn)];
}
/** Quaternion of the rotation taking frame A onto frame B (both column triples). */
function quatBetweenFrames(A, B) {
  // R = B * A^T
  const m = [[0, 0, 0], [0, 0, 0], [0, 0, 0]];
  for (let r = 0; r < 3; r++) for (let c = 0; c < 3; c++) for (let k = 0; k < 3; k++) m[r][c] += B[k][r] * A[k][c];
  return quatFromMatrix(m);
}
function quatFromMatrix(m) {
  const tr = m[0][0] + m[1][1] + m[2][2];
  let q;
  if (tr > 0) {
    const s = Math.sqrt(tr + 1) * 2;
    q = [(m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, s / 4];
  } else if (m[0][0] > m[1][1] && m[0][0] > m[2][2]) {
    const s = Math.sqrt(1 + m[0][0] - m[1][1] - m[2][2]) * 2;
    q = [s / 4, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s, (m[2][1] - m[1][2]) / s];
  } else if (m[1][1] > m[2][2]) {
    const s = Math.sqrt(1 + m[1][1] - m[0][0] - m[2][2]) * 2;
    q = [(m[0][1] + m[1][0]) / s, s / 4, (m[1][2] + m[2][1]) / s, (m[0][2] - m[2][0]) / s];
  } else {
    const s = Math.sqrt(1 + m[2][2] - m[0][0] - m[1][1]) * 2;
    q = [(m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, s / 4, (m[1][0] - m[0][1]) / s];
  }
  const l = Math.hypot(...q);
  return q.map((x) => x / l);
}
const qConj = (q) => [-q[0], -q[1], -q[2], q[3]];

/** The arms' rest posture of the arm clips (REST_ARM), as bone rotations. */
function restArms() {
  const out = {};
  for (const side of ["right", "left"]) {
    const m = side === "right" ? (q) => q : mirror;
    out[`${side}UpperArm`] = m(upperArm(REST_ARM.upperArm));
    out[`${side}LowerArm`] = m(lowerArm(REST_ARM.lowerArm));
    out[`${side}Hand`] = m(hand({}));
    Object.assign(out, handShapeBones(side, (() => {
      const s = SHAPES[REST_ARM.shape];
      return { index: s.index, middle: s.middle, ring: s.ring, little: s.little, thumb: s.thumb };
    })()));
  }
  return out;
}

/**
 * The truth of a leg clip at frame `i` on an avatar whose rest skeleton is `rest`: normalized
 * bone rotations (legs, feet, toes at identity, the arms' rest posture) and the hips' offset from
 * their rest position (meters). Also the knees' and ankles' room positions it solved for.
 */
export function legClipPose(clip, i, rest) {
  const c = legChannels(clip, i);
  const L = rest.leftUpperLeg[1];
  const sides = ["left", "right"];
  const cap = (s) => s[0].toUpperCase() + s.slice(1);
  const leg = {};
  for (const s of sides) {
    const hip = rest[`${s}UpperLeg`];
    const knee = rest[`${s}LowerLeg`];
    const ankle = rest[`${s}Foot`];
    const out = s === "left" ? 1 : -1; // +X is the avatar's left
    leg[s] = {
      hipRel: v3.sub(hip, rest.hips),
      a: v3.len(v3.sub(knee, hip)),
      b: v3.len(v3.sub(ankle, knee)),
      d0: v3.norm(v3.sub(knee, hip)),
      e0: v3.norm(v3.sub(ankle, knee)),
      ankle: [ankle[0] + out * c[`${s}.x`] * L, ankle[1] + c[`${s}.lift`] * L, ankle[2] + c[`${s}.z`] * L],
      pitch: c[`${s}.pitch`],
    };
  }
  // The hips: keyed x, z and drop; no lower than needed for both feet to reach.
  const off = [c["hips.x"] * L, -c["hips.drop"] * L, c["hips.z"] * L];
  for (const s of sides) {
    const l = leg[s];
    const reach = 0.999 * (l.a + l.b);
    const h = v3.add(v3.add(rest.hips, off), l.hipRel);
    const dx = l.ankle[0] - h[0];
    const dz = l.ankle[2] - h[2];
    const maxY = l.ankle[1] + Math.sqrt(Math.max(0, reach * reach - dx * dx - dz * dz));
    if (h[1] > maxY) off[1] -= h[1] - maxY;
  }
  const bones = restArms();
  const points = {};
  const X = [1, 0, 0];
  const FWD = [0, 0, 1];
  for (const s of sides) {
    const l = leg[s];
    const H = v3.add(v3.add(rest.hips, off), l.hipRel);
    const toA = v3.sub(l.ankle, H);
    const d = Math.min(Math.max(v3.len(toA), Math.abs(l.a - l.b) + 1e-6), (l.a + l.b) * 0.999999);
    const u = v3.norm(toA);
    const v = v3.norm(v3.sub(FWD, v3.scale(u, v3.dot(FWD, u)))); // the knee's pole: forwards
    const cosA = (l.a * l.a + d * d - l.b * l.b) / (2 * l.a * d);
    const sinA = Math.sqrt(Math.max(0, 1 - cosA * cosA));
    const K = v3.add(H, v3.add(v3.scale(u, l.a * cosA), v3.scale(v, l.a * sinA)));
    const A = v3.add(H, v3.scale(u, d));
    const d1 = v3.norm(v3.sub(K, H));
    const e1 = v3.norm(v3.sub(A, K));
    // The knee's hinge axis: the bend plane's normal (+X for a knee bent forwards).
    let n = v3.cross(d1, e1);
    n = v3.len(n) > 1e-6 ? v3.norm(n) : v3.norm(v3.cross(FWD, d1));
    const thigh = quatBetweenFrames(frameOf(l.d0, X), frameOf(d1, n));
    const shinWorld = quatBetweenFrames(frameOf(l.e0, X), frameOf(e1, n));
    const footWorld = qAxis("x", l.pitch);
    bones[`${s}UpperLeg`] = thigh;
    bones[`${s}LowerLeg`] = qMul(qConj(thigh), shinWorld);
    bones[`${s}Foot`] = qMul(qConj(shinWorld), footWorld);
    bones[`${s}Toes`] = [0, 0, 0, 1];
    points[`${s}Knee`] = K;
    points[`${s}Ankle`] = A;
    points[`${s}Hip`] = H;
  }
  bones.hips = [0, 0, 0, 1];
  return { bones, hipsOffset: off, points };
}

/** World positions at rest of the bones legClipPose needs, from a three-vrm VRM (normalized bones at identity). */
export const LEG_REST_BONES = ["hips", "leftUpperLeg", "rightUpperLeg", "leftLowerLeg", "rightLowerLeg", "leftFoot", "rightFoot", "leftToes", "rightToes"];

export const LEG_CLIPS = LEG_CLIPS_DEF;

/**
 * The leg clips seen by a camera that looks down (issue 51, the camera's pitch): the same
 * motion, the camera at the same distance from the same point but raised so that it looks
 * `pitch` degrees down at it (a camera above the person, as the real walking video's). Not
 * among LEG_CLIPS: the bench's figures stay those of the level camera; `--pitched` renders,
 * tracks and scores these.
 */
export const PITCHED_LEG_CLIPS = LEG_CLIPS_DEF.map((c) => ({ ...c, id: `${c.id}-down30`, pitch: 30 }));

// ---- contact clips (issue 52) ---------------------------------------------------------------------
// The right hand brought onto the chest and held, then taken 18 cm straight out before it and
// held, in four hand shapes: a flat palm, a curved (C) hand and a fist on the middle of the chest,
// and the curved hand at the collar (`hungry`'s first frames). One clip per avatar (`avatar`:
// rendered on that one only), its angles found for that avatar's body by a search over the arm's
// angles against its skin (three-vrm, CPU skinning): the palm turned to the body (its normal at
// least 0.9 of the way into it: the back of the hand to the camera), the hand's skin 3 mm off the
// chest with nothing inside, at 57% of the way from the upper chest bone up to the shoulder joints (the
// collar: at the shoulder joints' height), a little to the body's right of its middle; the hand
// before the chest at the same height and side, 180 mm off, the palm still turned to the body,
// in the same shape. The truth's own skin gap is measured per frame by eval/bench/chest-cue.mjs. What it
// is for: the chest cue's readings (src/contact/chest.rs) against a hand known to touch or not,
// whatever its shape.
const C = ([down, flex, hadd, rot, elbow, pro, wrist, dev], shape) => ({
  right: { upperArm: { down, flex, hadd, rot }, lowerArm: { flex: elbow, pro }, hand: { flex: wrist, dev }, shape },
});
const TOUCH_POSES = {
  woman: {
    onFlat: [81, 7, 33, -8, 107, -8, 29, 20], offFlat: [73, 39, 25, -8, 75, -40, 37, -28],
    onCurved: [77, 7, 33, -8, 107, -10, 28, 20], offCurved: [77, 39, 25, 0, 71, -45, 36, -30],
    onFist: [73, 7, 33, -8, 107, -16, 29, 20], offFist: [65, 44, 33, -8, 66, -58, 29, -30],
    onCollar: [85, 15, 33, -8, 126, -25, 21, -9], offCollar: [71, 43, 21, -8, 85, -58, 26, -23],
  },
  man: {
    onFlat: [73, 7, 41, -8, 107, -4, 29, 14], offFlat: [66, 23, 33, 0, 91, -45, 37, -28],
    onCurved: [65, 7, 41, -8, 107, -15, 39, 16], offCurved: [62, 19, 33, 0, 91, -48, 27, -16],
    onFist: [73, 7, 41, -8, 107, -4, 28, 14], offFist: [59, 31, 34, -16, 74, -50, 28, 8],
    onCollar: [85, 7, 33, -8, 128, -22, 29, -6], offCollar: [77, 32, 26, -8, 87, -58, 29, 2],
  },
  child: {
    onFlat: [79, 3, 33, -8, 111, -4, 29, 20], offFlat: [79, 39, 25, 0, 67, -37, 41, -14],
    onCurved: [79, 3, 33, -8, 111, -10, 29, 20], offCurved: [71, 43, 29, -8, 67, -50, 29, -11],
    onFist: [79, 3, 33, -8, 111, -22, 29, 16], offFist: [71, 42, 25, -9, 63, -47, 37, -13],
    onCollar: [87, 7, 33, -8, 130, -23, 17, 1], offCollar: [85, 44, 9, -8, 79, -58, 30, -19],
  },
};
const touchClip = (avatar) => {
  const p = TOUCH_POSES[avatar];
  const [onF, offF] = [C(p.onFlat, "open"), C(p.offFlat, "open")];
  const [onC, offC] = [C(p.onCurved, "curved"), C(p.offCurved, "curved")];
  const [onX, offX] = [C(p.onFist, "fist"), C(p.offFist, "fist")];
  const [onL, offL] = [C(p.onCollar, "curved"), C(p.offCollar, "curved")];
  return {
    id: `touch-${avatar}`, kind: "body", avatar, frames: 230,
    // [first frame, last frame, on / off, shape] of each hold, for the scoring.
    holds: [[30, 42, "on", "flat"], [57, 62, "off", "flat"], [82, 94, "on", "curved"], [109, 114, "off", "curved"],
      [134, 146, "on", "fist"], [161, 166, "off", "fist"], [186, 198, "on", "collar"], [213, 218, "off", "collar"]],
    keys: [
      [0, {}],
      [15, offF], [30, onF], [42, onF], [57, offF], [62, offF],
      [72, offC], [82, onC], [94, onC], [109, offC], [114, offC],
      [124, offX], [134, onX], [146, onX], [161, offX], [166, offX],
      [176, offL], [186, onL], [198, onL], [213, offL], [218, offL],
      [229, {}],
    ],
  };
};
const CONTACT_CLIPS_DEF = Object.keys(TOUCH_POSES).map(touchClip);
export const CONTACT_CLIPS = CONTACT_CLIPS_DEF;
const ALL_CLIPS = [...CLIPS_DEF, ...LEG_CLIPS_DEF, ...PITCHED_LEG_CLIPS, ...CONTACT_CLIPS_DEF];
/** Any clip: arm, leg or contact. */
export const anyClipById = (id) => {
  const c = ALL_CLIPS.find((x) => x.id === id);
  if (!c) throw new Error(`no clip "${id}" (have ${ALL_CLIPS.map((x) => x.id).join(", ")})`);
  return c;
};
