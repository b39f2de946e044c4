#!/usr/bin/env node
// Records the shared videos with tools/record-video.mjs and compares each recording with the
// shared one made from the same video by another MediaPipe build (tools/compare-recordings.mjs):
//   data/video/right-hand.mp4  hands mode     vs data/hands/right-hand-video-mediapipe.json
//                                              (@mediapipe/hands 0.4.1675469240 in Chromium)
//   data/asl/<clip>.mp4        holistic mode  vs data/asl/<clip>.json (MediaPipe 0.10.14 Python
//                              hands mode        Pose + Hands)
// Recordings and a summary (summary.json, summary.md) go to artifacts/recordings/.
//
//   node tools/check-shared-recordings.mjs [--only NAME]   (make record-check)

import { execFileSync } from "node:child_process";
import { existsSync, mkdirSync, writeFileSync } from "node:fs";
import { dirname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import { bestOffset, printReport, report } from "./compare-recordings.mjs";

const REPO = resolve(dirname(fileURLToPath(import.meta.url)), "..");
const SHARED = process.env.HANDRIG_SHARED ?? resolve(REPO, "..", "shared");
const OUT = join(REPO, "artifacts", "recordings");

const JOBS = [
  { name: "right-hand", video: "data/video/right-hand.mp4", ref: "data/hands/right-hand-video-mediapipe.json", modes: ["hands"] },
  ...["eat", "thanks", "brother", "sister"].map((c) => ({
    name: c,
    video: `data/asl/${c}.mp4`,
    ref: `data/asl/${c}.json`,
    modes: ["holistic", "hands"],
  })),
];

const only = process.argv.includes("--only") ? process.argv[process.argv.indexOf("--only") + 1] : null;
const reuse = process.argv.includes("--reuse"); // compare the recordings already in artifacts/recordings
if (!existsSync(SHARED)) {
  console.error(`check-shared-recordings: ${SHARED} not found (set HANDRIG_SHARED)`);
  process.exit(2);
}
mkdirSync(OUT, { recursive: true });
const results = [];
for (const job of JOBS) {
  if (only && job.name !== only) continue;
  for (const mode of job.modes) {
    const out = join(OUT, `${job.name}-${mode}.json`);
    const t0 = Date.now();
    const line = reuse && existsSync(out) ? `${out} (reused)` : execFileSync(process.execPath, [join(REPO, "tools/record-video.mjs"), join(SHARED, job.video), "--mode", mode, "--out", out, "--quiet"], {
      encoding: "utf8",
      stdio: ["ignore", "pipe", "inherit"],
    });
    const seconds = (Date.now() - t0) / 1000;
    const r = report(out, join(SHARED, job.ref));
    console.log(`\n== ${job.name}, ${mode} mode (${seconds.toFixed(0)} s)\n${line.trim()}\n${printReport(r)}`);
    results.push({ name: job.name, mode, seconds, ...r });
    // Frames that line up better one frame off: say so, and compare them there too.
    const best = bestOffset(r);
    if (best !== 0) {
      const rb = report(out, join(SHARED, job.ref), best);
      console.log(`-- the frames line up at reference offset ${best}:\n${printReport(rb)}`);
      results.push({ name: `${job.name} (ref frame = frame ${best > 0 ? "+" : "-"} ${Math.abs(best)})`, mode, seconds, ...rb });
    }
  }
}

const f = (s, k = 1, d = 2) => (s ? `${(s.median * k).toFixed(d)} / ${(s.p95 * k).toFixed(d)}` : "–");
const md = [
  "| video | mode | frames | hands: frames mine / shared | hands paired (same label) | hand image px | hand world mm | pose image px (upper body) | pose world mm (upper body) | alignment px at the row's offset -1 / 0 / +1 |",
  "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |",
  ...results.map(
    (r) =>
      `| ${r.name} | ${r.mode} | ${r.mine.frames} | ${r.mine.framesWithHands} / ${r.reference.framesWithHands} | ${r.pairedHands} (${r.sameLabel}) | ` +
      `${f(r.stats.handImage)} | ${f(r.stats.handWorld, 1000, 1)} | ${f(r.stats.poseImageUpper)} | ${f(r.stats.poseWorldUpper, 1000, 1)} | ` +
      `${[r.offset - 1, r.offset, r.offset + 1].map((o) => r.offsets[o]?.toFixed(2) ?? "–").join(" / ")} |`,
  ),
].join("\n");
writeFileSync(join(OUT, "summary.json"), JSON.stringify(results, null, 2));
writeFileSync(join(OUT, "summary.md"), `${md}\n\nmedian / p95 per landmark; see tools/README.md\n`);
console.log(`\n${md}\n\n${join(OUT, "summary.md")}`);
