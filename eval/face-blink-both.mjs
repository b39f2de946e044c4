#!/usr/bin/env node
// The face's both-eyes blink and wink (issue 50, seventh session) by a replica of src/face's
// blink arithmetic over the FaceLandmarker recordings (eval/face-bench/*.json: the face bench;
// eval/face/*.json: the ASL clips), without building the package. Per eye, the corrected blink
// b = cal(eyeBlink) - LOOK_DOWN_BLINK x cal(eyeLookDown) (cal: over the neutral face, the mean
// of the first 2 s without frames NEUTRAL_OUTLIER above it); each eye shows the largest of
//   - its own ramp, BLINK_OPEN..BLINK_CLOSED (main's blink);
//   - both eyes': min(bL, bR) over BOTH_OPEN..the user's closed level (the mean of the frames
//     it reads as closed, starting at BOTH_CLOSED weighted as BOTH_PRIOR_FRAMES frames, at
//     least BOTH_CLOSED_FLOOR; or fixed at BOTH_CLOSED);
//   - a wink's: b - b_other over WINK_OPEN..WINK_CLOSED;
// an eye shown at least half closed the frame before reading BLINK_HOLD higher in all three
// (eighth session; rows with hold: h, or a margin m at both ends of the shown weight, were the
// candidates); then the opening limited to 0.1 s. It follows src/face/mod.rs by hand: check a setting
// against the package (node eval/face-bench.mjs, node eval/face.mjs) before trusting it.
//
// Prints, on the tuning half (the bench's woman; ASL again, eat, please, thanks) or with
// --report on the report half (the bench's man and child; ASL brother, hungry, sister):
//   1. the corrected blinks' ranges: both eyes closed (the smaller eye), a wink's closed eye and
//      the other, open frames (the larger eye, the smaller, the difference);
//   2. the variants: both-eyes closed frames caught (per avatar, their mean blink), wink frames
//      caught, false blinks, the largest move on still stretches; the ASL clips' labelled blink,
//      false blinks and the largest blink on other frames;
//   3. --grid: the wink's ramp;
//   4. --noise: how far the readings move per frame on held frames (open, both closed);
//   5. --squint: both eyes held at a squint's reading for 1-30 s before every clip: the user's
//      closed level after it, the both-eyes ramp's largest on the ASL clips' other frames, and
//      the same with the level learned only from closures that ended within 0.5 s;
//   6. --still: a fall smaller than K smoothed (still13): the variants' rows and, on the bench,
//      how many frames after the truth's closing (>= 0.8) each eye shows closed (>= 0.5) and
//      after its opening (under 0.8) shows open (under 0.5): mean / max;
//   7. --trace AVATAR/CLIP:FROM-TO (a bench clip, e.g. child/face-wink:16-32): each frame's
//      eyeBlink and eyeLookDown (left, right) as read and their neutral, the corrected blinks,
//      the user's closed level, the three ramps' largest per eye and what each eye shows
//      before and after BLINK_STILL (still13);
//   --calibration SECONDS: the neutral face over the clips' first seconds (2 by default).
//
//   node eval/face-blink-both.mjs [--report] [--grid] [--noise] [--squint] [--still] [--trace A/C:F-T] [--calibration S]

import { readFileSync } from "node:fs";
import { join } from "node:path";
import { parseArgs } from "node:util";
import { REPO } from "./bench/common.mjs";
import { FACE_CLIPS, faceFrame } from "./bench/face-motions.mjs";

const { values: o } = parseArgs({ options: { report: { type: "boolean" }, grid: { type: "boolean" }, noise: { type: "boolean" }, squint: { type: "boolean" }, still: { type: "boolean" }, trace: { type: "string" }, calibration: { type: "string" } } });
const BENCH = o.report ? ["man", "child"] : ["woman"];
const ASL = o.report ? ["brother", "hungry", "sister"] : ["again", "eat", "please", "thanks"];
const labels = JSON.parse(readFileSync(join(REPO, "eval", "labels", "face.json"), "utf8"));
const clamp01 = (x) => Math.min(1, Math.max(0, x));
/** src/filter/one_euro.rs's alpha: a low-pass at `cutoff` Hz over `ms` milliseconds. */
const alphaAt = (ms, cutoff) => 1 / (1 + 1 / (2 * Math.PI * cutoff) / (ms / 1000));
const BLINK = 8;
const LOOK_DOWN = 10;
// src/face/mod.rs
const LOOK_DOWN_BLINK = 0.25;
const NEUTRAL_OUTLIER = 0.35;
const CALIBRATION_MS = o.calibration ? Number(o.calibration) * 1000 : 2000; // --calibration SECONDS: the neutral face over the clips' first seconds

/** Each face frame's corrected blinks [left, right] (the avatar's sides: un-mirrored input), or null. */
function series(frames) {
  let start = null;
  let sum = null;
  let n = null;
  return frames.map((f) => {
    if (!f.blendshapes) return null;
    const raw = f.blendshapes.slice(1).map(([, x]) => clamp01(x));
    start ??= f.timeMs;
    if (f.timeMs - start <= CALIBRATION_MS || !sum) {
      if (!sum) {
        sum = raw.slice();
        n = raw.map(() => 1);
      } else {
        for (let k = 0; k < raw.length; k++) {
          if (raw[k] <= sum[k] / n[k] + NEUTRAL_OUTLIER) {
            sum[k] += raw[k];
            n[k]++;
          }
        }
      }
    }
    const cal = (k) => {
      const neutral = Math.min(0.5, sum[k] / n[k]);
      return clamp01((raw[k] - neutral) / (1 - neutral));
    };
    const ks = [BLINK, BLINK + 1, LOOK_DOWN, LOOK_DOWN + 1];
    return {
      t: f.timeMs,
      b: [0, 1].map((e) => cal(BLINK + e) - LOOK_DOWN_BLINK * cal(LOOK_DOWN + e)),
      raw: ks.map((k) => raw[k]),
      neutral: ks.map((k) => Math.min(0.5, sum[k] / n[k])),
    };
  });
}

const bench = BENCH.flatMap((avatar) =>
  FACE_CLIPS.map((clip) => {
    const rec = JSON.parse(readFileSync(join(REPO, "eval", "face-bench", `${avatar}-${clip.id}.json`), "utf8"));
    const truth = rec.frames.map((_, i) => {
      const t = faceFrame(clip, i).expressions;
      return [Math.max(t.blink ?? 0, t.blinkLeft ?? 0), Math.max(t.blink ?? 0, t.blinkRight ?? 0)];
    });
    return { avatar, clip: clip.id, s: series(rec.frames), truth };
  }),
);
const asl = ASL.map((c) => ({
  clip: c,
  s: series(JSON.parse(readFileSync(join(REPO, "eval", "face", `${c}.json`), "utf8")).frames),
  closed: new Set(labels[c].eyesClosed),
}));

/** Each frame's shown blink per eye under variant v (null without a face). */
function solve(s0, v) {
  // v.squint: { r, seconds } both eyes held at the reading r for that long (then 10 open frames)
  // before the clip, whose outputs alone are returned.
  const first = s0.find(Boolean);
  const dt = 1000 / 30;
  const n = v.squint && first ? Math.round(v.squint.seconds * 30) : 0;
  const pre = Array.from({ length: n ? n + 10 : 0 }, (_, i) => ({ t: first.t - (n + 10 - i) * dt, b: i < n ? [v.squint.r, v.squint.r] : [0, 0] }));
  const s = pre.concat(s0);
  let prev = [0, 0];
  let last = null;
  let sum = 0;
  let count = 0;
  // v.both.maxRun (ms): a closure's readings count toward the user's level only once it has
  // ended within that long (a blink's length), not while it lasts.
  let runSum = 0;
  let runCount = 0;
  let runMs = 0;
  return s.map((x) => {
    if (!x) {
      last = null;
      return null;
    }
    const step = last === null ? null : (x.t - last) / 100;
    last = x.t;
    // Hysteresis: an eye shown at least half closed reads v.hold higher (and, with v.sym, one
    // shown less than half closed v.hold lower).
    const hold = [0, 1].map((e) => (!v.hold || step === null ? 0 : prev[e] >= 0.5 ? v.hold : v.sym ? -v.hold : 0));
    let y = [0, 1].map((e) => clamp01((x.b[e] + hold[e] - 0.2) / 0.4));
    if (v.both) {
      const m0 = Math.min(...x.b);
      const level = v.both.adapt ? Math.max(v.both.floor, (v.both.closed * v.both.prior + sum) / (v.both.prior + count)) : v.both.closed;
      const ramp = (m) => clamp01((m - v.both.open) / (level - v.both.open));
      if (v.both.adapt && !v.both.maxRun && ramp(m0) >= 0.5) {
        sum += m0;
        count++;
      }
      if (v.both.adapt && v.both.maxRun) {
        if (ramp(m0) >= 0.5) {
          runSum += m0;
          runCount++;
          runMs += step === null ? 0 : step * 100;
        } else {
          if (runCount && runMs <= v.both.maxRun) {
            sum += runSum;
            count += runCount;
          }
          runSum = runCount = runMs = 0;
        }
      }
      y = y.map((z, e) => Math.max(z, ramp(m0 + hold[e])));
      if (v.trace) {
        v.trace.level = level;
        v.trace.together = ramp(m0);
      }
    }
    if (v.wink) y = y.map((z, e) => Math.max(z, clamp01((x.b[e] + hold[e] - x.b[1 - e] - v.wink.open) / (v.wink.closed - v.wink.open))));
    if (v.margin) y = y.map((z) => clamp01((z - v.margin) / (1 - 2 * v.margin)));
    if (v.trace) v.trace.target = y.slice();
    // v.still: a fall of the shown weight smaller than this, to a target above 0 (jitter, not an
    // opening), is smoothed at the face's cutoff at rest (face.minCutoff, 2 Hz: alpha); a rise
    // and a larger fall as before (still13).
    const a = step === null ? 1 : alphaAt(step * 100, 2);
    // v.soft: every move but a closing (to at least half closed from under it) and an opening
    // to 0 has its first K (either way) smoothed, the rest passed; then the opening's limit.
    if (v.soft && step !== null) {
      prev = y.map((z, e) => {
        const p = prev[e];
        if (z === 0 || (p < 0.5 && (v.closedOnly || z >= 0.5))) return z < p ? Math.max(z, p - step) : z;
        // v.fallAtOnce: a fall of K or more opens as before (limited), a smaller one is smoothed.
        if (v.fallAtOnce && z < p) return p - z < v.soft ? p - a * (p - z) : Math.max(z, p - step);
        return Math.max(z - (1 - a) * Math.min(v.soft, Math.max(-v.soft, z - p)), p - step);
      });
      return v.trace ? Object.assign(prev.slice(), { together: v.trace.together, level: v.trace.level, target: v.trace.target }) : prev;
    }
    // v.both2: a rise smaller than K smoothed too.
    prev = y.map((z, e) =>
      v.still && v.both2 && step !== null && z > 0 && Math.abs(prev[e] - z) < v.still
        ? prev[e] + a * (z - prev[e])
        : step !== null && z < prev[e]
          ? v.still && z > 0 && prev[e] - z < v.still
            ? prev[e] - a * (prev[e] - z)
            : Math.max(z, prev[e] - step)
          : z,
    );
    return v.trace ? Object.assign(prev.slice(), { together: v.trace.together, level: v.trace.level, target: v.trace.target }) : prev;
  }).slice(pre.length);
}

const range = (xs) => (xs.length ? `${Math.min(...xs).toFixed(2)}..${Math.max(...xs).toFixed(2)}` : "n/a");
const near = (truth, k) => truth.slice(Math.max(0, k - 2), k + 3).some(([l, r]) => l > 0 || r > 0);

function readings() {
  console.log("| | both closed: smaller eye | wink: closed eye / other | open: larger eye / smaller / difference |\n| --- | --- | --- | --- |");
  for (const avatar of BENCH) {
    const both = [], wink = [], other = [], big = [], small = [], diff = [];
    for (const c of bench.filter((c) => c.avatar === avatar)) {
      c.s.forEach((x, k) => {
        if (!x) return;
        const [l, r] = c.truth[k];
        if (l >= 0.8 && r >= 0.8) both.push(Math.min(...x.b));
        for (const [e, te, to] of [[0, l, r], [1, r, l]]) {
          if (te >= 0.8 && to === 0) {
            wink.push(x.b[e]);
            other.push(x.b[1 - e]);
          }
        }
        if (!near(c.truth, k)) {
          big.push(Math.max(...x.b));
          small.push(Math.min(...x.b));
          diff.push(Math.abs(x.b[0] - x.b[1]));
        }
      });
    }
    console.log(`| bench ${avatar} | ${range(both)} | ${range(wink)} / ${range(other)} | ${range(big)} / ${range(small)} / ${range(diff)} |`);
  }
  for (const c of asl) {
    const big = [], small = [], diff = [], closed = [];
    c.s.forEach((x, k) => {
      if (!x) return;
      if (c.closed.has(k)) closed.push(x.b.map((b) => b.toFixed(2)).join(" / "));
      else if (!c.closed.has(k - 1) && !c.closed.has(k + 1)) {
        big.push(Math.max(...x.b));
        small.push(Math.min(...x.b));
        diff.push(Math.abs(x.b[0] - x.b[1]));
      }
    });
    console.log(`| ASL ${c.clip}${closed.length ? ` (labelled blink: ${closed.join(", ")})` : ""} | | | ${range(big)} / ${range(small)} / ${range(diff)} |`);
  }
}

/** How far the readings move per frame where the truth is held: open eyes (6 frames unchanged), both eyes closed (closed the frame before too). */
function noise() {
  const pct = (xs, p) => xs.slice().sort((a, b) => a - b)[Math.min(xs.length - 1, Math.floor(p * xs.length))];
  console.log("\n| the readings' move per frame: open (held 6 frames), both closed (closed the frame before) | n | p50 | p95 | max |\n| --- | ---: | ---: | ---: | ---: |");
  for (const avatar of BENCH) {
    const open = [], closed = [];
    for (const c of bench.filter((c) => c.avatar === avatar)) {
      c.s.forEach((x, k) => {
        if (!x || !c.s[k - 1]) return;
        const [l, r] = c.truth[k];
        if (l >= 0.8 && r >= 0.8 && Math.min(...c.truth[k - 1]) >= 0.8) closed.push(Math.abs(Math.min(...x.b) - Math.min(...c.s[k - 1].b)));
        let held = k >= 6;
        for (let j = k - 6; held && j < k; j++) if (c.truth[j][0] !== c.truth[k][0] || c.truth[j][1] !== c.truth[k][1]) held = false;
        if (!held) return;
        if (l === 0 && r === 0) for (const e of [0, 1]) open.push(Math.abs(x.b[e] - c.s[k - 1].b[e]));
      });
    }
    for (const [n, xs] of [["open, each eye", open], ["both closed, the smaller eye", closed]]) if (xs.length) console.log(`| ${avatar}: ${n} | ${xs.length} | ${pct(xs, 0.5).toFixed(3)} | ${pct(xs, 0.95).toFixed(3)} | ${Math.max(...xs).toFixed(3)} |`);
  }
}

function row(label, v) {
  const per = {};
  let wink = 0, winkN = 0, fb = 0, open = 0;
  const still = [];
  for (const c of bench) {
    const out = solve(c.s, v);
    const p = (per[c.avatar] ??= { hit: 0, n: 0, sum: 0 });
    out.forEach((y, k) => {
      if (!y) return;
      const [l, r] = c.truth[k];
      for (const [e, te, to] of [[0, l, r], [1, r, l]]) {
        if (te >= 0.8 && to >= 0.8) {
          p.n++;
          p.sum += y[e];
          if (y[e] >= 0.5) p.hit++;
        }
        if (te >= 0.8 && to === 0) {
          winkN++;
          if (y[e] >= 0.5) wink++;
        }
      }
      if (!near(c.truth, k)) {
        open++;
        if (Math.max(...y) >= 0.5) fb++;
      }
      let held = k >= 6;
      for (let j = k - 6; held && j < k; j++) if (c.truth[j][0] !== c.truth[k][0] || c.truth[j][1] !== c.truth[k][1]) held = false;
      if (held && out[k - 1]) still.push(Math.max(Math.abs(y[0] - out[k - 1][0]), Math.abs(y[1] - out[k - 1][1])));
    });
  }
  const a = { hit: 0, n: 0, other: 0, fb: 0, largest: 0 };
  for (const c of asl) {
    solve(c.s, v).forEach((y, k) => {
      if (!y) return;
      const b = Math.max(...y);
      if (c.closed.has(k)) {
        a.n++;
        if (b >= 0.5) a.hit++;
      } else if (!c.closed.has(k - 1) && !c.closed.has(k + 1)) {
        a.other++;
        a.largest = Math.max(a.largest, b);
        if (b >= 0.5) a.fb++;
      }
    });
  }
  const both = Object.entries(per).map(([av, p]) => `${av} ${p.hit} / ${p.n} (${(p.sum / p.n).toFixed(2)})`).join(", ");
  return `| ${label} | ${both} | ${wink} / ${winkN} | ${fb} / ${open} | ${Math.max(...still).toFixed(3)} | ${a.n ? `${a.hit} / ${a.n}` : "n/a"} | ${a.fb} / ${a.other} | ${a.largest.toFixed(2)} |`;
}
const HEAD = "| bench: both eyes closed, frames caught (mean blink) | bench: wink frames caught | bench: false blinks | bench: still stretches' largest move | ASL: labelled blink caught | ASL: false blinks | ASL: largest blink on other frames |";

const MERGED = { both: { open: 0.15, closed: 0.45, prior: 10, floor: 0.35, adapt: true }, wink: { open: 0.25, closed: 0.55 } };
console.log(`${o.report ? "report" : "tune"} half: bench ${BENCH.join(", ")}; ASL ${ASL.join(", ")}\n`);
readings();
if (o.noise) noise();
console.log(`\n| variant ${HEAD}\n| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |`);
const variants = [
  ["main: each eye's ramp 0.2..0.6", {}],
  ["+ both eyes, fixed 0.1..0.5", { both: { open: 0.1, closed: 0.5 } }],
  ["+ both eyes, fixed 0.15..0.45", { both: { open: 0.15, closed: 0.45 } }],
  ["+ both eyes, 0.15..the user's level (prior 0.45, 10 frames, floor 0.35)", { both: MERGED.both }],
  ["+ both eyes, 0.1..the user's level (prior 0.5, 10 frames, floor 0.35)", { both: { ...MERGED.both, open: 0.1, closed: 0.5 } }],
  ["+ both eyes, prior 5 frames", { both: { ...MERGED.both, prior: 5 } }],
  ["+ both eyes, floor 0.3", { both: { ...MERGED.both, floor: 0.3 } }],
  ["+ a wink 0.25..0.55 alone", { wink: MERGED.wink }],
  ["**the user's level and the wink (merged)**", MERGED],
  ...[0.05, 0.1, 0.15].map((m) => [`merged + a margin ${m} at both ends`, { ...MERGED, margin: m }]),
  ...[0.02, 0.03, 0.035, 0.04, 0.05, 0.08].map((h) => [`merged + hysteresis ${h} when closed${h === 0.035 ? " (kept: BLINK_HOLD)" : ""}`, { ...MERGED, hold: h }]),
  ...[0.02, 0.03, 0.04, 0.05, 0.08].map((h) => [`merged + hysteresis ${h} both ways`, { ...MERGED, hold: h, sym: true }]),
];
for (const [label, v] of variants) console.log(row(label, v));
const HELD = { ...MERGED, hold: 0.035 };
/** After a squint: the user's level at the clips' first frame; ASL: both eyes' ramp's largest on other frames, frames it shows at least half closed. */
function squintRow(label, v) {
  let level = 0, both = 0, fb = 0, n = 0;
  for (const c of asl) {
    const out = solve(c.s, { ...v, trace: {} });
    level = out.find(Boolean).level;
    out.forEach((y, k) => {
      if (!y || c.closed.has(k) || c.closed.has(k - 1) || c.closed.has(k + 1)) return;
      n++;
      both = Math.max(both, y.together);
      if (y.together >= 0.5) fb++;
    });
  }
  return `${row(label, v)} ${level.toFixed(3)} | ${both.toFixed(2)} | ${fb} / ${n} |`;
}
if (o.squint) {
  console.log(`\n| both eyes held at a squint reading before the clips (then 10 open frames) ${HEAD} the user's level after | ASL: both eyes' ramp, largest on other frames | ASL: both eyes' ramp >= 0.5 |\n| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |`);
  for (const [label, b] of [["merged (+ BLINK_HOLD)", HELD.both], ["learning from closures that ended within 0.5 s", { ...HELD.both, maxRun: 500 }]]) {
    console.log(squintRow(`${label}, no squint`, { ...HELD, both: b }));
    for (const r of [0.25, 0.3, 0.35]) for (const seconds of [1, 5, 30]) console.log(squintRow(`${label}, ${seconds} s at ${r}`, { ...HELD, both: b, squint: { r, seconds } }));
  }
}
if (o.grid) {
  console.log(`\n| wink ramp (with both eyes as merged) ${HEAD}\n| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |`);
  for (const open of [0.15, 0.2, 0.25, 0.3]) {
    for (const closed of [0.4, 0.45, 0.5, 0.55, 0.6, 0.7]) if (closed > open + 0.1) console.log(row(`${open}..${closed}`, { ...MERGED, wink: { open, closed } }));
  }
}

/** The bench: frames from the truth's closing (an eye >= 0.8) to the eye shown closed (>= 0.5), and from its opening (under 0.8) to shown open. */
function lags(v) {
  const close = [], open = [];
  for (const c of bench) {
    const out = solve(c.s, v);
    for (const e of [0, 1]) {
      for (let k = 1; k < c.truth.length; k++) {
        const was = c.truth[k - 1][e] >= 0.8, is = c.truth[k][e] >= 0.8;
        if (was === is) continue;
        let j = k;
        while (j < out.length && out[j] && (out[j][e] >= 0.5) !== is) j++;
        (is ? close : open).push(j - k);
      }
    }
  }
  const m = (xs) => `${(xs.reduce((a, b) => a + b, 0) / xs.length).toFixed(2)} / ${Math.max(...xs)}`;
  return `${m(close)} (${close.length}) | ${m(open)} (${open.length}) |`;
}
if (o.still) {
  const NOW = { ...MERGED, both: { ...MERGED.both, maxRun: 500 }, hold: 0.035 };
  console.log(`\n| a fall under K smoothed ${HEAD} bench: frames to shown closed, mean / max | bench: frames to shown open, mean / max |\n| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |`);
  console.log(`${row("main (BLINK_HOLD, BLINK_LEARN_MS)", NOW)} ${lags(NOW)}`);
  for (const k of (process.env.STILL_K ?? "0.03,0.04,0.05,0.0667,0.08,0.1,0.117,0.15").split(",").map(Number)) {
    const v = { ...NOW, soft: k };
    console.log(`${row(`every move but a closing and an opening to 0: its first K ${k} smoothed`, v)} ${lags(v)}`);
    const w = { ...NOW, soft: k, closedOnly: true };
    console.log(`${row(`the same, only from an eye shown at least half closed: K ${k}`, w)} ${lags(w)}`);
    const x = { ...NOW, soft: k, fallAtOnce: true };
    console.log(`${row(`a rise but a closing: its first K ${k} smoothed; a fall under K smoothed, a larger one limited${k === 0.0667 ? " (kept: BLINK_STILL)" : ""}`, x)} ${lags(x)}`);
  }
  for (const both2 of [false, true]) {
    for (const k of (process.env.STILL_K ?? "0.03,0.04,0.05,0.0667,0.08,0.1,0.117,0.15").split(",").map(Number)) {
      const v = { ...NOW, still: k, both2 };
      console.log(`${row(`${both2 ? "a rise or a fall" : "a fall"} under K ${k}`, v)} ${lags(v)}`);
    }
  }
}

if (o.trace) {
  const [, avatar, clip, from, to] = o.trace.match(/^(\w+)\/([\w-]+):(\d+)-(\d+)$/);
  const c = bench.find((x) => x.avatar === avatar && x.clip === clip) ?? (() => { throw new Error(`${o.trace}: not on this half (--report for man, child)`); })();
  const NOW = { ...MERGED, both: { ...MERGED.both, maxRun: 500 }, hold: 0.035 };
  const before = solve(c.s, { ...NOW, trace: {} });
  const after = solve(c.s, { ...NOW, soft: 0.02 / 0.3, fallAtOnce: true, trace: {} }); // BLINK_STILL
  const f = (x) => x.toFixed(3);
  console.log(`\n${avatar} ${clip}: frame | truth L / R | eyeBlink L / R (neutral) | eyeLookDown L / R (neutral) | corrected L / R | level | target L / R (largest ramp) | shown before L / R | shown after L / R |\n| ---: | --- | --- | --- | --- | ---: | --- | --- | --- |`);
  for (let k = Number(from); k <= Number(to); k++) {
    const x = c.s[k];
    if (!x) continue;
    const [bl, br, dl, dr] = x.raw;
    const [nbl, nbr, ndl, ndr] = x.neutral;
    console.log(`| ${k} | ${c.truth[k].map((t) => t.toFixed(2)).join(" / ")} | ${f(bl)} / ${f(br)} (${f(nbl)} / ${f(nbr)}) | ${f(dl)} / ${f(dr)} (${f(ndl)} / ${f(ndr)}) | ${x.b.map(f).join(" / ")} | ${f(before[k].level)} | ${before[k].target.map(f).join(" / ")} | ${before[k].slice(0, 2).map(f).join(" / ")} | ${after[k].slice(0, 2).map(f).join(" / ")} |`);
  }
}
