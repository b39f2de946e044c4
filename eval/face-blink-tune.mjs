#!/usr/bin/env node
// The face's blink constants (issue 50) by a replica of src/face's blink arithmetic over the
// FaceLandmarker recordings (eval/face/*.json: the ASL clips; eval/face-bench/*.json: the face
// bench), without building the package: the neutral face over the first 2 s (its estimator
// varied), `eyeBlink` minus LOOK_DOWN_BLINK x `eyeLookDown` (both calibrated), the ramp
// BLINK_OPEN..BLINK_CLOSED, the opening limited to 0.1 s. It follows src/face/mod.rs by hand: check
// a setting against the package (node eval/face.mjs, node eval/face-bench.mjs) before trusting it.
//
// Prints, on the tuning half (the bench's woman; ASL again, eat, please, thanks) or with
// --report on the report half (the bench's man and child; ASL brother, hungry, sister):
//   1. the neutral face's estimators at the merged ramp: closed frames caught and their mean
//      blink on the bench, false blinks (eyes-down) and the largest blink on the ASL clips'
//      other frames;
//   2. --grid: LOOK_DOWN_BLINK x BLINK_OPEN x BLINK_CLOSED with the merged neutral.
//
//   node eval/face-blink-tune.mjs [--report] [--grid]

import { readFileSync } from "node:fs";
import { join } from "node:path";
import { parseArgs } from "node:util";
import { REPO } from "./bench/common.mjs";
import { FACE_CLIPS, faceFrame } from "./bench/face-motions.mjs";

const { values: o } = parseArgs({ options: { report: { type: "boolean" }, grid: { type: "boolean" } } });
const BENCH = o.report ? ["man", "child"] : ["woman"];
const ASL = o.report ? ["brother", "hungry", "sister"] : ["again", "eat", "please", "thanks"];
const labels = JSON.parse(readFileSync(join(REPO, "eval", "labels", "face.json"), "utf8"));
const BLINK = 8;
const LOOK_DOWN = 10;
const CALIBRATION_MS = 2000;
const MERGED = { open: 0.2, closed: 0.6, lookDown: 0.25, neutral: { outlier: 0.35 } };
const clamp01 = (x) => Math.min(1, Math.max(0, x));

/** The mean of the sorted values between the `lo` and `hi` fractions of them (lo = hi: that quantile). */
function slice(xs, lo, hi) {
  const s = [...xs].sort((a, b) => a - b);
  if (hi <= lo) {
    const p = lo * (s.length - 1);
    const i = Math.floor(p);
    return i + 1 < s.length ? s[i] + (s[i + 1] - s[i]) * (p - i) : s[i];
  }
  const a = lo * s.length;
  const b = hi * s.length;
  let sum = 0;
  for (let k = 0; k < s.length; k++) sum += Math.max(0, Math.min(b, k + 1) - Math.max(a, k)) * s[k];
  return sum / (b - a);
}

/** Each neutral estimator: a function of the calibration frames so far, one weight's values. */
function neutralOf(kind, state, raw) {
  if (kind.outlier !== undefined) {
    // The merged one: the mean, but for frames more than `outlier` above the mean so far.
    if (!state.sum) {
      state.sum = raw.slice();
      state.n = raw.map(() => 1);
    } else {
      for (let k = 0; k < raw.length; k++) {
        if (raw[k] <= state.sum[k] / state.n[k] + kind.outlier) {
          state.sum[k] += raw[k];
          state.n[k]++;
        }
      }
    }
    return state.sum.map((s, k) => s / state.n[k]);
  }
  (state.window ??= []).push(raw);
  return raw.map((_, k) => {
    const xs = state.window.map((r) => r[k]);
    if (kind.mean) return xs.reduce((a, b) => a + b, 0) / xs.length;
    return slice(xs, kind.lo, kind.hi);
  });
}

/** Each frame's blink per eye [left, right] (the avatar's sides: un-mirrored input), or null. */
function solve(frames, v) {
  let start = null;
  let neutral = null;
  const state = {};
  let prev = [0, 0];
  let lastMs = null;
  return frames.map((f) => {
    if (!f.blendshapes) {
      lastMs = null;
      return null;
    }
    // MediaPipe's categories without `_neutral`, in ARKit order.
    const raw = f.blendshapes.slice(1).map(([, x]) => clamp01(x));
    start ??= f.timeMs;
    if (f.timeMs - start <= CALIBRATION_MS || !neutral) neutral = neutralOf(v.neutral, state, raw).map((x) => Math.min(x, 0.5));
    const cal = (k) => clamp01((raw[k] - neutral[k]) / (1 - neutral[k]));
    const step = lastMs === null ? null : (f.timeMs - lastMs) / 1000 / 0.1;
    lastMs = f.timeMs;
    prev = [0, 1].map((e) => {
      const b = cal(BLINK + e) - v.lookDown * cal(LOOK_DOWN + e);
      const x = clamp01((b - v.open) / (v.closed - v.open));
      return step !== null && x < prev[e] ? Math.max(x, prev[e] - step) : x;
    });
    return prev;
  });
}

const cache = new Map();
const load = (file) => {
  if (!cache.has(file)) cache.set(file, JSON.parse(readFileSync(file, "utf8")));
  return cache.get(file);
};

/** The bench: closed-eye frames (truth >= 0.8, per eye) caught (>= 0.5) and their mean; false blinks as eval/face-bench.mjs counts them. */
function bench(v) {
  const acc = { closed: 0, hit: 0, sum: 0, open: 0, falseBlinks: 0 };
  for (const avatar of BENCH) {
    for (const clip of FACE_CLIPS) {
      const rec = load(join(REPO, "eval", "face-bench", `${avatar}-${clip.id}.json`));
      const res = solve(rec.frames, v);
      const truth = rec.frames.map((_, i) => {
        const t = faceFrame(clip, i).expressions;
        return [Math.max(t.blink ?? 0, t.blinkLeft ?? 0), Math.max(t.blink ?? 0, t.blinkRight ?? 0)];
      });
      const near = (k) => truth.slice(Math.max(0, k - 2), k + 3).some(([l, r]) => l > 0 || r > 0);
      res.forEach((r, k) => {
        if (!r) return;
        for (const e of [0, 1]) {
          if (truth[k][e] >= 0.8) {
            acc.closed++;
            acc.sum += r[e];
            if (r[e] >= 0.5) acc.hit++;
          }
        }
        if (!near(k)) {
          acc.open++;
          if (Math.max(...r) >= 0.5) acc.falseBlinks++;
        }
      });
    }
  }
  return acc;
}

/** The ASL clips: labelled closed frames caught; false blinks on other frames (not next to a closed one), on eyes-down ones, the largest. */
function asl(v) {
  const acc = { closed: 0, hit: 0, other: 0, falseBlinks: 0, down: 0, downBlinks: 0, largest: 0 };
  for (const clip of ASL) {
    const res = solve(load(join(REPO, "eval", "face", `${clip}.json`)).frames, v);
    const closed = new Set(labels[clip].eyesClosed);
    const down = new Set(labels[clip].eyesDown);
    res.forEach((r, k) => {
      if (!r) return;
      const b = Math.max(...r);
      if (closed.has(k)) {
        acc.closed++;
        if (b >= 0.5) acc.hit++;
      } else if (!closed.has(k - 1) && !closed.has(k + 1)) {
        acc.other++;
        acc.largest = Math.max(acc.largest, b);
        if (b >= 0.5) acc.falseBlinks++;
        if (down.has(k)) {
          acc.down++;
          if (b >= 0.5) acc.downBlinks++;
        }
      }
    });
  }
  return acc;
}

function row(label, v) {
  const b = bench(v);
  const a = asl(v);
  return `| ${label} | ${(b.sum / b.closed).toFixed(2)} (${b.hit} / ${b.closed}) | ${b.falseBlinks} / ${b.open} | ${a.closed ? `${a.hit} / ${a.closed}` : "n/a"} | ${a.falseBlinks} / ${a.other} (${a.downBlinks} / ${a.down}) | ${a.largest.toFixed(2)} |`;
}

const half = o.report ? "report" : "tune";
console.log(`${half} half: bench ${BENCH.join(", ")}; ASL ${ASL.join(", ")}\n`);
const head = "| bench: closed frames' mean blink (caught) | bench: false blinks | ASL: closed frames caught | ASL: false blinks (eyes-down) | ASL: largest blink on other frames |";
if (o.grid) {
  console.log(`| LOOK_DOWN_BLINK, BLINK_OPEN, BLINK_CLOSED ${head}\n| --- | ---: | ---: | ---: | ---: | ---: |`);
  for (const lookDown of [0.25, 0.2, 0.15, 0.1]) {
    for (const open of [0.2, 0.15, 0.1, 0.05]) {
      for (const closed of [0.6, 0.5, 0.45, 0.4, 0.35, 0.3]) {
        if (closed > open + 0.1) console.log(row(`${lookDown}, ${open}, ${closed}`, { ...MERGED, lookDown, open, closed }));
      }
    }
  }
} else {
  console.log(`| neutral face ${head}\n| --- | ---: | ---: | ---: | ---: | ---: |`);
  const kinds = [
    ["mean", { mean: true }],
    ["median", { lo: 0.5, hi: 0.5 }],
    ["0.3 quantile", { lo: 0.3, hi: 0.3 }],
    ["0.1 quantile", { lo: 0.1, hi: 0.1 }],
    ["interquartile mean", { lo: 0.25, hi: 0.75 }],
    ...[0.5, 0.4, 0.35, 0.3, 0.25, 0.1].map((x) => [`mean without frames ${x} above it`, { outlier: x }]),
  ];
  for (const [label, neutral] of kinds) console.log(row(label, { ...MERGED, neutral }));
}
