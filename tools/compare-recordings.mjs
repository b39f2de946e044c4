#!/usr/bin/env node
// Compares two recordings in the shared JSON format frame by frame (same `frame` numbers):
// how many frames each has hands and pose in, and per-landmark distances where both have them.
//
//   node tools/compare-recordings.mjs MINE.json REFERENCE.json [--offset N] [--json]
//
// Hands are paired by their image wrist (nearest, within 10% of the image), so that label
// flips and duplicate hands do not pair the wrong hands; label agreement is reported. Image
// distances use x and y only (MediaPipe's image z is a relative depth), in pixels of the
// reference's width x height; world distances are 3D, meters (hands: MediaPipe's hand world
// frame, origin near the hand's center; pose: origin between the hips). "upper body" pose is
// landmarks 0-22 (face, shoulders, arms, hands; the hips and legs are mostly out of frame in
// the shared clips). `--offset N` compares mine's frame i with the reference's frame i + N;
// the alignment check compares at N - 1, N, N + 1: the smallest median at N says the frames
// line up.

import { readFileSync } from "node:fs";
import { dirname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";

const REPO = resolve(dirname(fileURLToPath(import.meta.url)), "..");
const { readRecording } = await import(join(REPO, "www/src/recording-format.js"));

const UPPER_BODY = 23;

function load(file) {
  const rec = JSON.parse(readFileSync(file, "utf8"));
  const sum = readRecording(rec);
  const frames = Array.isArray(rec) ? rec : rec.frames;
  const meta = Array.isArray(rec) ? {} : rec;
  return { file, sum, meta, byFrame: new Map(frames.map((f) => [f.frame, f])) };
}

const quantile = (xs, q) => {
  if (!xs.length) return null;
  const s = Float64Array.from(xs).sort();
  return s[Math.min(s.length - 1, Math.floor(q * s.length))];
};

/** Pairs hands of two frames by nearest image wrist (greedy), within `maxDist` (normalized). */
function pairHands(a, b, maxDist = 0.1) {
  const pairs = [];
  const used = new Set();
  const cands = [];
  for (let i = 0; i < a.length; i++) {
    for (let j = 0; j < b.length; j++) {
      const d = Math.hypot(a[i].landmarks[0][0] - b[j].landmarks[0][0], a[i].landmarks[0][1] - b[j].landmarks[0][1]);
      if (d <= maxDist) cands.push([d, i, j]);
    }
  }
  cands.sort((x, y) => x[0] - y[0]);
  const usedA = new Set();
  for (const [, i, j] of cands) {
    if (usedA.has(i) || used.has(j)) continue;
    usedA.add(i);
    used.add(j);
    pairs.push([a[i], b[j]]);
  }
  return pairs;
}

function imageDist(p, q, w, h, out) {
  for (let k = 0; k < p.length; k++) out.push(Math.hypot((p[k][0] - q[k][0]) * w, (p[k][1] - q[k][1]) * h));
}

function worldDist(p, q, out, n = p.length) {
  for (let k = 0; k < n; k++) out.push(Math.hypot(p[k][0] - q[k][0], p[k][1] - q[k][1], p[k][2] - q[k][2]));
}

/** Per-landmark distances between `mine` and `ref` with mine's frame i against ref's i + offset. */
export function compare(mine, ref, offset = 0) {
  const w = ref.meta.width ?? mine.meta.width ?? 1;
  const h = ref.meta.height ?? mine.meta.height ?? 1;
  const d = { handImage: [], handWorld: [], poseImage: [], poseWorld: [], poseImageUpper: [], poseWorldUpper: [] };
  let common = 0;
  let handFramesBoth = 0;
  let pairedHands = 0;
  let sameLabel = 0;
  let handsMine = 0;
  let handsRef = 0;
  for (const [i, f] of mine.byFrame) {
    const g = ref.byFrame.get(i + offset);
    if (!g) continue;
    common++;
    const a = f.hands ?? [];
    const b = g.hands ?? [];
    handsMine += a.length;
    handsRef += b.length;
    if (a.length && b.length) handFramesBoth++;
    for (const [p, q] of pairHands(a, b)) {
      pairedHands++;
      if (p.handedness === q.handedness) sameLabel++;
      imageDist(p.landmarks, q.landmarks, w, h, d.handImage);
      if (p.worldLandmarks && q.worldLandmarks) worldDist(p.worldLandmarks, q.worldLandmarks, d.handWorld);
    }
    if (f.pose && g.pose) {
      if (f.pose.landmarks && g.pose.landmarks) {
        imageDist(f.pose.landmarks, g.pose.landmarks, w, h, d.poseImage);
        imageDist(f.pose.landmarks.slice(0, UPPER_BODY), g.pose.landmarks.slice(0, UPPER_BODY), w, h, d.poseImageUpper);
      }
      if (f.pose.worldLandmarks && g.pose.worldLandmarks) {
        worldDist(f.pose.worldLandmarks, g.pose.worldLandmarks, d.poseWorld);
        worldDist(f.pose.worldLandmarks, g.pose.worldLandmarks, d.poseWorldUpper, UPPER_BODY);
      }
    }
  }
  const stats = {};
  for (const [k, xs] of Object.entries(d)) stats[k] = xs.length ? { n: xs.length, median: quantile(xs, 0.5), p95: quantile(xs, 0.95) } : null;
  return { offset, common, handsMine, handsRef, handFramesBoth, pairedHands, sameLabel, stats };
}

/**
 * The comparison of two recording files at reference frame offset `offset` (mine's frame i
 * against the reference's i + offset), with the alignment check at offset -1, 0, +1 around it.
 */
export function report(mineFile, refFile, offset = 0) {
  const mine = load(mineFile);
  const ref = load(refFile);
  const main = compare(mine, ref, offset);
  const offsets = [offset - 1, offset + 1].map((o) => compare(mine, ref, o));
  return {
    mine: { file: mineFile, mediapipe: mine.meta.mediapipe ?? null, ...without(mine.sum, "meta") },
    reference: { file: refFile, mediapipe: ref.meta.mediapipe ?? null, ...without(ref.sum, "meta") },
    ...main,
    offsets: Object.fromEntries([main, ...offsets].map((c) => [c.offset, c.stats.handImage?.median ?? c.stats.poseImage?.median ?? null])),
  };
}

/** The reference frame offset (-1, 0 or +1) where the median image distance is smallest. */
export function bestOffset(r) {
  let best = r.offset;
  for (const [o, d] of Object.entries(r.offsets)) if (d != null && d < r.offsets[best]) best = Number(o);
  return best;
}

function without(o, key) {
  const { [key]: _, ...rest } = o;
  return rest;
}

const fmt = (s, unit, k = 1) => (s ? `${(s.median * k).toFixed(unit === "mm" ? 1 : 2)} / ${(s.p95 * k).toFixed(unit === "mm" ? 1 : 2)} ${unit}` : "-");

export function printReport(r) {
  const lines = [];
  lines.push(`mine:      ${r.mine.file} (${r.mine.mediapipe ?? "?"}): ${r.mine.frames} frames, hands in ${r.mine.framesWithHands}, pose in ${r.mine.framesWithPose}`);
  lines.push(`reference: ${r.reference.file} (${r.reference.mediapipe ?? "?"}): ${r.reference.frames} frames, hands in ${r.reference.framesWithHands}, pose in ${r.reference.framesWithPose}`);
  lines.push(`frames in both: ${r.common}; hands mine ${r.handsMine} / reference ${r.handsRef}; frames where both have a hand: ${r.handFramesBoth}; hands paired: ${r.pairedHands}, same label: ${r.sameLabel}`);
  lines.push("per-landmark distance, median / p95:");
  lines.push(`  hand image  ${fmt(r.stats.handImage, "px")}`);
  lines.push(`  hand world  ${fmt(r.stats.handWorld, "mm", 1000)}`);
  lines.push(`  pose image  ${fmt(r.stats.poseImage, "px")} (upper body ${fmt(r.stats.poseImageUpper, "px")})`);
  lines.push(`  pose world  ${fmt(r.stats.poseWorld, "mm", 1000)} (upper body ${fmt(r.stats.poseWorldUpper, "mm", 1000)})`);
  const os = [r.offset - 1, r.offset, r.offset + 1];
  lines.push(`frame alignment (median image distance at reference offset ${os.join(" / ")}): ${os.map((o) => r.offsets[o]?.toFixed(2) ?? "-").join(" / ")} px`);
  return lines.join("\n");
}

if (process.argv[1] && resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const args = process.argv.slice(2);
  const json = args.includes("--json");
  const oi = args.indexOf("--offset");
  const offset = oi >= 0 ? Number(args[oi + 1]) : 0;
  const files = args.filter((a, i) => a !== "--json" && i !== oi && i !== oi + 1);
  if (files.length !== 2 || !Number.isInteger(offset)) {
    console.error("usage: node tools/compare-recordings.mjs MINE.json REFERENCE.json [--offset N] [--json]");
    process.exit(2);
  }
  try {
    const r = report(files[0], files[1], offset);
    console.log(json ? JSON.stringify(r, null, 2) : printReport(r));
  } catch (e) {
    console.error(`compare-recordings: ${e.message}`);
    process.exit(1);
  }
}
