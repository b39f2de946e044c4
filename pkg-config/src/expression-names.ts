// The face's weights onto an avatar's own expression or morph-target names (issue 50), for
// `handrig/three-vrm` and `handrig/three`: the 52 ARKit names in their case and prefix variants
// ("eyeBlinkLeft", "EyeBlinkLeft", "BlendShape.eyeBlinkLeft", "eyeBlink_L") for perfect sync,
// and the VRM presets under their VRM 1.0, VRM 0.x and VRChat viseme names. Bound once per
// avatar (setup), read by index every frame.

import { LAYOUT, LO } from "./layout.js";

/** Lower case, without a prefix up to the last "." and without "_", "-" and spaces. */
export function normalizeExpressionName(name: string): string {
  return name
    .slice(name.lastIndexOf(".") + 1)
    .toLowerCase()
    .replace(/[_\-\s]/g, "");
}

const ARKIT_KEYS = new Map<string, number>(LAYOUT.arkit.map((n, i) => [n.toLowerCase(), i]));

/** Each preset's accepted names, normalized (VRM 1.0, VRM 0.x, VRChat visemes). */
const PRESET_ALIASES: { [preset: string]: string[] } = {
  happy: ["happy", "joy"],
  angry: ["angry"],
  sad: ["sad", "sorrow"],
  relaxed: ["relaxed", "fun"],
  surprised: ["surprised"],
  aa: ["aa", "a", "vaa"],
  ih: ["ih", "i", "vih"],
  ou: ["ou", "u", "vou"],
  ee: ["ee", "e", "ve"],
  oh: ["oh", "o", "voh"],
  blink: ["blink"],
  blinkLeft: ["blinkleft", "blinkl"],
  blinkRight: ["blinkright", "blinkr"],
  lookUp: ["lookup"],
  lookDown: ["lookdown"],
  lookLeft: ["lookleft"],
  lookRight: ["lookright"],
};

/** The ARKit index a name stands for, if any ("eyeBlink_L" -> eyeBlinkLeft). */
function arkitIndex(name: string): number | undefined {
  const n = normalizeExpressionName(name);
  const exact = ARKIT_KEYS.get(n);
  if (exact !== undefined) return exact;
  const last = n[n.length - 1];
  if (last === "l") return ARKIT_KEYS.get(`${n.slice(0, -1)}left`);
  if (last === "r") return ARKIT_KEYS.get(`${n.slice(0, -1)}right`);
  return undefined;
}

/** Which of an avatar's names each face weight goes to. */
export interface FaceBinding {
  /** Per ARKit weight (`LAYOUT.arkit` order), the avatar's name or null. */
  arkit: (string | null)[];
  /** Per preset (`LAYOUT.expressions` order), the avatar's name or null. */
  presets: (string | null)[];
  /** The avatar carries the ARKit shapes (at least half of them): perfect sync drives them, and the presets are left alone. */
  perfectSync: boolean;
}

/** Binds an avatar's expression or morph-target names. */
export function bindFace(names: Iterable<string>): FaceBinding {
  const arkit: (string | null)[] = LAYOUT.arkit.map(() => null);
  const byNormal = new Map<string, string>();
  for (const name of names) {
    const k = arkitIndex(name);
    if (k !== undefined && arkit[k] === null) arkit[k] = name;
    const n = normalizeExpressionName(name);
    if (!byNormal.has(n)) byNormal.set(n, name);
  }
  const presets = LAYOUT.expressions.map((p) => {
    for (const alias of PRESET_ALIASES[p] ?? [p.toLowerCase()]) {
      const name = byNormal.get(alias);
      if (name !== undefined) return name;
    }
    return null;
  });
  const found = arkit.filter((n) => n !== null).length;
  return { arkit, presets, perfectSync: found >= LAYOUT.arkit.length / 2 };
}

/** This frame's face, copied from a result or a flat output (no allocation). */
export const FACE = {
  /** 0 none, 1 tracked, 2 lost and easing out. */
  state: 0,
  presets: new Float32Array(LAYOUT.expressions.length),
  arkit: new Float32Array(LAYOUT.arkit.length),
  yaw: 0,
  pitch: 0,
};

const STATES: { [s: string]: number } = { tracked: 1, lost: 2 };

/**
 * Reads the face of a `solve` result or a flat output into FACE; false when the result has no
 * face fields (a result of a handrig before the face).
 */
export function readFace(result: unknown): boolean {
  if (result instanceof Float32Array) {
    if (result.length !== LO.length) return false;
    FACE.state = result[LO.faceState]!;
    for (let k = 0; k < FACE.presets.length; k++) FACE.presets[k] = result[LO.expressions + k]!;
    for (let k = 0; k < FACE.arkit.length; k++) FACE.arkit[k] = result[LO.arkit + k]!;
    FACE.yaw = result[LO.lookAt]!;
    FACE.pitch = result[LO.lookAt + 1]!;
    return true;
  }
  const r = result as { face?: unknown; expressions?: { [k: string]: number }; arkit?: ArrayLike<number>; lookAt?: { yaw: number; pitch: number } };
  if (r === null || typeof r !== "object" || !("face" in r) || !r.expressions || !r.arkit || !r.lookAt) return false;
  FACE.state = typeof r.face === "string" ? (STATES[r.face] ?? 0) : 0;
  const names = LAYOUT.expressions;
  for (let k = 0; k < names.length; k++) FACE.presets[k] = r.expressions[names[k]!] ?? 0;
  for (let k = 0; k < FACE.arkit.length; k++) FACE.arkit[k] = r.arkit[k] ?? 0;
  FACE.yaw = r.lookAt.yaw;
  FACE.pitch = r.lookAt.pitch;
  return true;
}
