// One table of every method on the shared recordings (issue 10): runs the evaluations, reads
// their figures, and prints one Markdown table (with --verbose, each evaluation's own output
// first). `make eval` runs it.
//
//   make pkg && npm ci --prefix eval     # once
//   node eval/table.mjs [--verbose]
//
// Sources (each also runs alone; see docs/measurements/README.md and the method pages they feed):
// - node eval/hands.mjs --json: bone-direction error of handrig's analytic solver and of
//   Kalidokit 1.1.5 (the hand video, 621 frames, robot avatar, frames with no joint limit active)
// - cargo run --release --example eval_retarget -- --json: fingertip and pinch error, joint-limit
//   violations, jitter (mean frame-to-frame change of the finger bones) of "analytic" and
//   "retarget" (the hand video, robot, automatic hand scale)
// - cargo run --release --example eval_alignment: the avatar's index distal against the target
//   DIP (Kinect wrists + the hand video, robot, right hand) per method and arm solver
// - node eval/speed.mjs --json: time per frame in Node (wasm), Kalidokit in the same process
// - cargo run --release --example eval_torso / eval_contact / eval_live / eval_wrist: the
//   second table (the torso, self-contact, live tracking, the wrist limits), each figure with
//   the same rig without the capability

import { execFileSync } from "node:child_process";
import { dirname, resolve } from "node:path";
import { fileURLToPath } from "node:url";

const root = resolve(dirname(fileURLToPath(import.meta.url)), "..");
const verbose = process.argv.includes("--verbose");

function run(cmd, args) {
  const out = execFileSync(cmd, args, { cwd: root, encoding: "utf8", maxBuffer: 64 << 20, stdio: ["ignore", "pipe", "inherit"] });
  if (verbose) console.log(`$ ${cmd} ${args.join(" ")}\n${out}`);
  return out;
}

/** Rows of every Markdown table in `text` whose header includes all `columns`, as objects. */
function tableRows(text, columns) {
  const lines = text.split("\n");
  const rows = [];
  for (let i = 0; i < lines.length - 1; i++) {
    const cells = (l) => l.trim().replace(/^\||\|$/g, "").split("|").map((c) => c.trim());
    if (!lines[i].startsWith("|")) continue;
    const header = cells(lines[i]);
    if (!columns.every((c) => header.includes(c)) || !lines[i + 1].startsWith("| ---")) continue;
    for (let j = i + 2; j < lines.length && lines[j].startsWith("|"); j++) {
      const c = cells(lines[j]);
      rows.push(Object.fromEntries(header.map((h, k) => [h, c[k]])));
    }
  }
  return rows;
}

const mean = (xs) => xs.reduce((a, b) => a + b, 0) / xs.length;
const f = (x, d = 1) => (x === undefined || x === null || Number.isNaN(x) ? "–" : Number(x).toFixed(d));

// Bone-direction error: mean over the five fingers of the per-finger median (degrees).
const hands = JSON.parse(run("node", ["eval/hands.mjs", "--json"]));
const video = hands.results["right-hand-video-mediapipe"];
const fingers = ["thumb", "index", "middle", "ring", "little"];
const boneDir = {
  handrig: mean(fingers.map((k) => video[k].handrig.median)),
  kalidokit: mean(fingers.map((k) => video[k].kalidokit.median)),
};

// Fingertips, pinches, limits, jitter: the hand video on the robot, automatic scale.
const retarget = JSON.parse(run("cargo", ["run", "--release", "--quiet", "--example", "eval_retarget", "--", "--json"]));
const rt = (strategy) => retarget.find((r) => r.recording === "video" && r.avatar === "robot" && r.scale === "auto" && r.strategy === strategy);

// Alignment: index distal vs target DIP, robot, right hand, Kinect wrists + hand video.
const alignment = run("cargo", ["run", "--release", "--quiet", "--example", "eval_alignment"]);
const methodRows = tableRows(alignment, ["avatar", "side", "method", "median mm"]).filter(
  (r) => r.avatar === "debug-robot.vrm" && r.side === "right",
);
const method = (prefix) => Number(methodRows.find((r) => r.method.startsWith(prefix))?.["median mm"]);
const solverRows = tableRows(alignment, ["data", "armSolver", "median mm"]).filter(
  (r) => r.data === "kinect wrists" && r.avatar === "debug-robot.vrm" && r.side === "right",
);
const solver = (name) => Number(solverRows.find((r) => r.armSolver === name)?.["median mm"]);

// Time per frame in Node.
const speed = JSON.parse(run("node", ["eval/speed.mjs", "--json", "--passes", "3"]));
const us = (label) => speed.rows.find((r) => r.label.startsWith(label))?.median;

const rows = [
  ["handrig analytic + twoBone (defaults)", boneDir.handrig, rt("analytic")?.tipMedianMm, rt("analytic")?.pinchMaxMm, rt("analytic")?.limitViolations, method("(a)"), rt("analytic")?.jitterDeg, us("handrig object API: one hand")],
  ["handrig retarget (seed 003) + twoBone", null, rt("retarget")?.tipMedianMm, rt("retarget")?.pinchMaxMm, rt("retarget")?.limitViolations, null, rt("retarget")?.jitterDeg, null],
  ["handrig analytic + FABRIK (seed 002)", boneDir.handrig, null, null, null, solver("fabrik"), null, null],
  ["handrig analytic + CCD (seed 004)", boneDir.handrig, null, null, null, solver("ccd"), null, null],
  ["seed 000 as published (avatar vector one frame late)", null, null, null, null, method("(c)"), null, null],
  ["no alignment (pose wrist as the IK target)", null, null, null, null, method("(b)"), null, null],
  ["Kalidokit 1.1.5 (Hand.solve)", boneDir.kalidokit, null, null, null, null, null, us("Kalidokit Hand.solve")],
];

console.log(`\nOne table, ${new Date().toISOString().slice(0, 10)}, \`make eval\` (node eval/table.mjs): the hand video (621 frames) on the robot; alignment with the Kinect wrists (281 frames), right hand.\n`);
console.log("| method | bone direction error, deg (median, mean over fingers) | fingertip error, mm (median) | pinch error, mm (max) | joint-limit violations | alignment error, mm (median) | jitter, deg per bone per frame | time per frame, µs (Node, one hand) |");
console.log("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
for (const [name, dir, tip, pinch, limits, align, jitter, time] of rows) {
  console.log(`| ${name} | ${f(dir, 2)} | ${f(tip, 1)} | ${f(pinch, 2)} | ${limits ?? "–"} | ${f(align, 4)} | ${f(jitter, 2)} | ${f(time, 1)} |`);
}
console.log(`\nFull frame (ASL clips: pose and up to two hands) in Node: handrig object API ${f(us("handrig object API: full frame"))} µs, flat path ${f(us("handrig flat path: full frame"))} µs, Kalidokit Pose.solve + Hand.solve ${f(us("Kalidokit Pose.solve"))} µs (medians).`);

// The capabilities that change more than the hand: each with and without it, from its own eval.
const torsoOut = run("cargo", ["run", "--release", "--quiet", "--example", "eval_torso"]);
const torsoRow = (avatar, prefix) =>
  tableRows(torsoOut, ["avatar", "method", "median mm"]).find((r) => r.avatar === avatar && r.method.startsWith(prefix));
const contactOut = run("cargo", ["run", "--release", "--quiet", "--example", "eval_contact"]);
const contactRows = tableRows(contactOut, ["data", "avatar", "plain error median / p95 mm", "contact error median / p95 mm"]);
const median = (xs) => [...xs].sort((a, b) => a - b)[xs.length >> 1];
// Median over the ASL clips of each clip's median error (human-proportioned avatar).
const contactMedian = (column) =>
  median(
    contactRows
      .filter((r) => r.avatar === "human-proportions" && /^ASL \w+$/.test(r.data))
      .map((r) => Number(r[`${column} median / p95 mm`].split("/")[0])),
  );
const liveOut = run("cargo", ["run", "--release", "--quiet", "--example", "eval_live"]);
const jitter = tableRows(liveOut, ["data", "bones", "raw", "filtered"]).find((r) => r.data.startsWith("hand video"));
const dropout = /(\d+(?:\.\d+)?) deg snapping[^,]*, (\d+(?:\.\d+)?) deg easing/.exec(liveOut);
const handedness = tableRows(liveOut, ["labels", "handedness", "hands driven to the side the pose gives"]);
const driven = (labels, policy) =>
  handedness.find((r) => r.labels === labels && r.handedness === policy)?.["hands driven to the side the pose gives"];
const wristOut = run("cargo", ["run", "--release", "--quiet", "--example", "eval_wrist"]);
const wristRow = (limits) =>
  tableRows(wristOut, ["data", "avatar", "wristLimits", "contact", "beyond the range"]).find(
    (r) => r.data.startsWith("asl") && r.avatar === "debug-robot" && r.wristLimits === `\`${limits}\`` && r.contact === "`false`",
  );

const mm = (x) => (Number.isFinite(Number(x)) ? `${Number(x).toFixed(Number(x) < 1 ? 4 : 1)} mm` : "–");
const capabilities = [
  ["torso from the app (issue 12)", "index distal to target DIP, median: 12 leaning torsos x 8 frames, robot", mm(torsoRow("debug-robot", "app torso (frame.torso), tracker wrists")?.["median mm"]), `${mm(torsoRow("debug-robot", "same, torso not given")?.["median mm"])} (arms from a rest torso)`, "eval_torso"],
  ["self-contact (issue 14)", "avatar fingertip to the expected face point, median over the ASL clips, human-proportioned", mm(contactMedian("contact error")), `${mm(contactMedian("plain error"))} (contact off)`, "eval_contact"],
  ["One Euro filtering (issue 13)", "finger jitter, hand video, rad/s² (lag in frames)", `${jitter?.filtered} (lag ${jitter?.["lag (frames)"]})`, `${jitter?.raw} (filter off)`, "eval_live"],
  ["dropout easing (issue 13)", "largest step of a hand bone over a 1 s loss, deg", dropout?.[2] ?? "–", `${dropout?.[1] ?? "–"} (snapping)`, "eval_live"],
  ["handedness from the pose (issue 13)", "ASL hands driven to the pose's side, labels all swapped", driven("all swapped", "reassign") ?? "–", `${driven("all swapped", "trust") ?? "–"} (labels trusted)`, "eval_live"],
  ["wrist limits (issue 15)", "ASL hand-frames beyond the wrist's range, robot", wristRow(true)?.["beyond the range"] ?? "–", `${wristRow(false)?.["beyond the range"] ?? "–"} (limits off)`, "eval_wrist"],
];
console.log("\n| capability | measure | handrig | without it | eval |");
console.log("| --- | --- | ---: | ---: | --- |");
for (const [name, measure, on, off, example] of capabilities) console.log(`| ${name} | ${measure} | ${on} | ${off} | \`${example}\` |`);
