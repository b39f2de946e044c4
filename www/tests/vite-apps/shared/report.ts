// What both apps report: per frame, how far some bones turned from rest (degrees), drawn on a
// canvas and put on window.__result for the test.

/** The bones plotted and reported. */
export const WATCHED = [
  "rightUpperArm",
  "rightLowerArm",
  "rightHand",
  "rightIndexProximal",
  "rightThumbProximal",
  "leftUpperArm",
  "leftLowerArm",
  "leftIndexProximal",
] as const;
export type Watched = (typeof WATCHED)[number];

/** The angle of a unit quaternion [x, y, z, w] from identity, in degrees; null stays null. */
export function angleDeg(q: ArrayLike<number> | null | undefined): number | null {
  if (!q) return null;
  const w = Math.min(1, Math.abs(q[3] ?? 1));
  return (2 * Math.acos(w) * 180) / Math.PI;
}

export interface Report {
  app: string;
  frames: number;
  /** rotations[frame][k]: WATCHED[k]'s local rotation [x, y, z, w], or null when not driven. */
  rotations: (number[] | null)[][];
  /** angles[frame][k]: WATCHED[k]'s angle from rest (degrees), or null when not driven. */
  angles: (number | null)[][];
  /** Largest angle of each watched bone over the clip. */
  largest: Record<Watched, number>;
  extra?: unknown;
  error?: string;
}

declare global {
  interface Window {
    __result?: Report;
  }
}

const COLORS = ["#e6194b", "#f58231", "#ffe119", "#3cb44b", "#42d4f4", "#4363d8", "#911eb4", "#f032e6"];

/** A copy of a rotation (the sources reuse theirs). */
export function copy(q: ArrayLike<number> | null | undefined): number[] | null {
  return q ? [q[0]!, q[1]!, q[2]!, q[3]!] : null;
}

/** Draws the bones' angles from rest and publishes the report. */
export function publish(app: string, rotations: (number[] | null)[][], extra?: unknown): void {
  const angles = rotations.map((row) => row.map(angleDeg));
  const largest = Object.fromEntries(WATCHED.map((b) => [b, 0])) as Record<Watched, number>;
  for (const row of angles) {
    row.forEach((a, k) => {
      const b = WATCHED[k]!;
      if (a !== null && a > largest[b]) largest[b] = a;
    });
  }
  const canvas = document.querySelector("canvas")!;
  const g = canvas.getContext("2d")!;
  const { width: w, height: h } = canvas;
  g.fillStyle = "#111";
  g.fillRect(0, 0, w, h);
  g.font = "16px sans-serif";
  g.fillStyle = "#eee";
  g.fillText(`${app}: eat.json, ${angles.length} frames, bone angle from rest (0-180°)`, 12, 22);
  const x = (i: number) => 40 + ((w - 60) * i) / Math.max(1, angles.length - 1);
  const y = (deg: number) => h - 30 - ((h - 80) * deg) / 180;
  WATCHED.forEach((bone, k) => {
    g.strokeStyle = COLORS[k]!;
    g.lineWidth = 2;
    g.beginPath();
    let pen = false;
    angles.forEach((row, i) => {
      const a = row[k];
      if (a === null || a === undefined) return void (pen = false);
      if (pen) g.lineTo(x(i), y(a));
      else g.moveTo(x(i), y(a));
      pen = true;
    });
    g.stroke();
    g.fillStyle = COLORS[k]!;
    g.fillText(`${bone} (max ${largest[bone].toFixed(0)}°)`, w - 300, 50 + 20 * k);
  });
  window.__result = { app, frames: angles.length, rotations, angles, largest, extra };
}

export function publishError(app: string, e: unknown): void {
  window.__result = { app, frames: 0, rotations: [], angles: [], largest: {} as Record<Watched, number>, error: String((e as Error)?.message ?? e) };
}

/** The clip's shape (MediaPipe Holistic per frame: pose and hands). */
export interface Clip {
  frames: { timeMs: number }[];
}

export async function loadInputs(): Promise<{ avatar: ArrayBuffer; clip: Clip }> {
  const [avatar, clip] = await Promise.all([
    fetch("./avatar.vrm").then((r) => r.arrayBuffer()),
    fetch("./eat.json").then((r) => r.json() as Promise<Clip>),
  ]);
  return { avatar, clip };
}
