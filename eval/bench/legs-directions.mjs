#!/usr/bin/env node
// The bench's leg clips (issue 51): how well each way of reading a thigh's and a shin's
// direction from MediaPipe's pose places the knee and the ankle, the segment alone (no solve,
// no filter, no turn), against the truth (motions.mjs legClipPose), on the committed Tasks API
// recordings (eval/bench/clips/AVATAR-CLIP-tasks.json).
//
//   node eval/bench/legs-directions.mjs      # ~10 s; needs npm ci --prefix tests/node (three, three-vrm)
//
// Per avatar, segment (0 thigh: the knee's error; 1 shin: the ankle's error from the knee) and
// clip, the median and 90th percentile (mm) of |the direction - the truth's| times the avatar's
// segment length, for:
// * world: MediaPipe's world landmarks (x, -y, -z);
// * image + bounded depth (handrig since the third session): across and up from the image
//   landmarks scaled by the torso (world length over image length), MediaPipe's depth bounded
//   by the depth the image leaves, sqrt(length^2 - seen^2);
// * image + foreshortening depth (the second session's rule): as above, but from a quarter of
//   the length deep (the image's foreshortening) toward the image's depth, in full from half, the
//   way the hip's 30 degrees of extension allows (thigh) or MediaPipe's (shin).
// * image + the user's own length (fourth session): across and up as above, the depth
//   sqrt(own^2 - seen^2) from the segment's image length against the user's own, learned per
//   leg and segment as an upper quantile (Q, 0.9) of its image length in torso image lengths
//   (RATE, 0.01 per frame), on MediaPipe's side (the thigh: SIGN=hip, the side the hip's 30
//   degrees of extension allows when only one does);
// * image + mean of both depths: the bounded depth while the own length reads the segment less
//   than RAMP's first value of its length deep, the own length's from its second (RAMP=0.3,0.5),
//   blended between;
// * image + MediaPipe's depth bounded by the user's own length (sixth session; handrig's thigh
//   since then): MediaPipe's depth as in "bounded", but the bound is the depth the image leaves
//   against the user's own segment length in the image (the upper quantile above, learned only
//   on frames where the world landmarks put the segment within GATE degrees of the image
//   plane, 5; before any such frame, the world length); SHIN=thigh gives the shin the thigh's
//   learned length times MediaPipe's shin-to-thigh world length ratio instead of its own;
// and the ratio of each segment's image length to its world length (x1000, median): 1000 when
// the torso's image scale holds for the legs.

import { readFileSync } from "node:fs";
import { join } from "node:path";
import { pathToFileURL } from "node:url";
import { LEG_AVATARS, REPO, avatarFile, recordingFile } from "./common.mjs";
import { LEG_CLIPS, LEG_REST_BONES, legClipPose } from "./motions.mjs";

const { loadVrm } = await import(pathToFileURL(join(REPO, "tests", "node", "consumer", "skin-measure.mjs")).href);
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const sc = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const len = (a) => Math.hypot(...a);
const norm = (a) => sc(a, 1 / len(a));
const pct = (v, p) => [...v].sort((a, b) => a - b)[Math.floor((v.length - 1) * p)];
const MP = { left: [23, 25, 27], right: [24, 26, 28] };
const toAvatar = (v) => [v[0], -v[1], -v[2]];
const METHODS = { world: "world", bounded: "image + bounded depth", foreshortening: "image + foreshortening depth", calibrated: "image + the user's own length", mixed: "image + mean of both depths", ownbound: "image + MediaPipe's depth bounded by the user's own length" };
// The user's own segment length in the image, in torso image lengths, learned causally: an upper
// quantile (QUANTILE) tracked by stochastic approximation, RATE per frame.
const QUANTILE = Number(process.env.Q ?? 0.9);
const RATE = Number(process.env.RATE ?? 0.01);
const [RA, RB] = (process.env.RAMP ?? "0.3,0.5").split(",").map(Number);
const GATE = Number(process.env.GATE ?? 5);
const RAMP = (f) => Math.min(1, Math.max(0, (f - RA) / (RB - RA)));

const res = new Map();
const push = (key, v) => (res.get(key) ?? res.set(key, []).get(key)).push(v);
for (const avatar of LEG_AVATARS) {
  const vrm = await loadVrm(avatarFile(avatar));
  vrm.scene.updateMatrixWorld(true);
  const rest = {};
  for (const b of LEG_REST_BONES) {
    const n = vrm.humanoid.getNormalizedBoneNode(b);
    if (n) {
      const v = n.getWorldPosition(n.position.clone());
      rest[b] = [v.x, v.y, v.z];
    }
  }
  for (const clip of LEG_CLIPS) {
    const learned = {};
    let thighWl = 0;
    const gated = {};
    const rec = JSON.parse(readFileSync(recordingFile(avatar, clip, "tasks"), "utf8"));
    const aspect = rec.width / rec.height;
    rec.frames.forEach((fr, i) => {
      if (!fr.pose?.worldLandmarks) return;
      const t = legClipPose(clip, i, rest);
      const W = fr.pose.worldLandmarks;
      const I = fr.pose.landmarks;
      const mid = (p, a, b) => sc(add(p[a], p[b]), 0.5);
      const chord = (p) => sub(mid(p, 11, 12), mid(p, 23, 24));
      const ci = chord(I);
      const m = len(chord(W)) / Math.hypot(ci[0] * aspect, ci[1]);
      for (const side of ["left", "right"]) {
        const [hi, ki, ai] = MP[side];
        const H = add(rest[`${side}UpperLeg`], t.hipsOffset ?? [0, 0, 0]);
        const K = t.points[`${side}Knee`];
        const A = t.points[`${side}Ankle`];
        const segs = [
          [hi, ki, norm(sub(K, H)), len(sub(rest[`${side}LowerLeg`], rest[`${side}UpperLeg`]))],
          [ki, ai, norm(sub(A, K)), len(sub(rest[`${side}Foot`], rest[`${side}LowerLeg`]))],
        ];
        segs.forEach(([a, b, truth, L], si) => {
          const w = sub(W[b], W[a]);
          const wl = len(w);
          const d = sub(I[b], I[a]);
          const across = [d[0] * aspect * m, d[1] * m];
          const al = Math.hypot(...across);
          const z = Math.sqrt(Math.max(0, wl * wl - al * al));
          const mp = Math.max(-z, Math.min(z, w[2]));
          // The segment's image length in torso image lengths; its learned upper quantile.
          const r = al / (m * Math.hypot(ci[0] * aspect, ci[1]));
          const key = `${side}${si}`;
          const R = (learned[key] ??= r);
          learned[key] = R + RATE * (QUANTILE - (r < R ? 1 : 0));
          // The gated own length: learned only on frames MediaPipe's world landmarks show the
          // segment within GATE degrees of the image plane (a leg never seen straight keeps
          // the torso-scaled bound).
          const flat = Math.abs(w[2]) / wl < Math.sin((GATE * Math.PI) / 180);
          if (flat) {
            const G = (gated[key] ??= r);
            gated[key] = G + RATE * (QUANTILE - (r < G ? 1 : 0));
          }
          const Lc = Math.max(al, R * m * Math.hypot(ci[0] * aspect, ci[1]));
          const zc = Math.sqrt(Math.max(0, Lc * Lc - al * al));
          const szMp = w[2] >= 0 ? 1 : -1;
          const sure = Math.min(1, Math.max(0, (z / wl - 0.25) / 0.25));
          const valid = (zz) => si === 1 || Math.atan2(-zz, across[1]) >= -Math.PI / 6;
          const [away, toward] = [valid(z), valid(-z)];
          const [awayC, towardC] = [valid(zc), valid(-zc)];
          const sz = process.env.SIGN === "hip" ? (awayC && !towardC ? 1 : towardC && !awayC ? -1 : szMp) : szMp;
          const sign = away && !toward ? 1 : toward && !away ? -1 : w[2] >= 0 ? 1 : -1;
          const est = {
            world: w,
            bounded: [across[0], across[1], mp],
            foreshortening: [across[0], across[1], mp + sure * (sign * z - mp)],
            calibrated: [across[0], across[1], (si === 0 ? sz : szMp) * zc],
            mixed: [across[0], across[1], mp + RAMP(zc / Lc) * (sz * zc - mp)],
            // MediaPipe's depth, bounded by the depth the image leaves against the user's own
            // length (the learned quantile) rather than against the torso's image scale.
            ownbound: (() => {
              // SHIN=thigh: the shin's own length is the thigh's learned one times MediaPipe's
              // shin-to-thigh world length ratio (the shin is not learned alone).
              const G = si === 1 && process.env.SHIN === "thigh" ? (gated[`${side}0`] === undefined ? undefined : (gated[`${side}0`] * wl) / thighWl) : gated[key];
              if (si === 0) thighWl = wl;
              const own = G === undefined ? wl : G * m * Math.hypot(ci[0] * aspect, ci[1]);
              const c = Math.min(1, al / own);
              const th = Math.min(Math.abs(Math.asin(Math.max(-1, Math.min(1, w[2] / wl)))), Math.acos(c));
              const u = al > 0 ? [across[0] / al, across[1] / al] : [0, -1];
              return [u[0] * Math.cos(th), u[1] * Math.cos(th), Math.sign(w[2]) * Math.sin(th)];
            })(),
          };
          for (const [k, v] of Object.entries(est)) {
            const e = 1000 * L * len(sub(norm(toAvatar(v)), truth));
            push(`${avatar}|${si}|${k}|all`, e);
            push(`${avatar}|${si}|${k}|${clip.id}`, e);
          }
          push(`${avatar}|${si}|ratio|${clip.id}`, (1000 * al) / wl);
        });
      }
    });
  }
}
const clips = ["all", ...LEG_CLIPS.map((c) => c.id)];
console.log(`| avatar | segment | method | ${clips.join(" | ")} |`);
console.log(`| --- | --- | --- | ${clips.map(() => "---:").join(" | ")} |`);
for (const avatar of LEG_AVATARS) {
  for (const si of [0, 1]) {
    for (const k of [...Object.keys(METHODS), "ratio"]) {
      const cells = clips.map((c) => {
        const v = res.get(`${avatar}|${si}|${k}|${c}`);
        if (!v?.length) return "-";
        return k === "ratio" ? pct(v, 0.5).toFixed(0) : `${pct(v, 0.5).toFixed(1)} / ${pct(v, 0.9).toFixed(1)}`;
      });
      console.log(`| ${avatar} | ${si ? "shin (ankle from the knee)" : "thigh (knee)"} | ${METHODS[k] ?? "image / world length x1000"} | ${cells.join(" | ")} |`);
    }
  }
}
