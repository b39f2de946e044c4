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
// - the third table, the face, the legs and contact on the skin against what a user would pick
//   instead (Kalidokit's Face.solve and Pose.solve with legs; contact off): node eval/face.mjs
//   --json (the FaceLandmarker recordings of make eval-face), node eval/bench/score-legs.mjs
//   --json (the bench's leg recordings of make eval-bench-legs), and target/skin-contact.json as
//   the last `node eval/skin-contact.mjs --json` left it (15 minutes: not run here; its date is
//   printed). A source whose recordings are missing is left out with the command that makes them.

import { execFileSync } from "node:child_process";
import { existsSync, mkdtempSync, readFileSync, statSync } from "node:fs";
import { tmpdir } from "node:os";
import { dirname, join, resolve } from "node:path";
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
const untouched = /; (\d+(?:\.\d+)?) deg on the same frames without the dropout/.exec(liveOut);
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
  ["dropout easing (issue 13)", `largest step of a hand bone over a 1 s loss, deg (the fingers blend in; a hand bone back with its fingertip aligned shows its solve at once; ${untouched?.[1] ?? "–"} on the same frames without the loss)`, dropout?.[2] ?? "–", `${dropout?.[1] ?? "–"} (snapping)`, "eval_live"],
  ["handedness from the pose (issue 13)", "ASL hands driven to the pose's side, labels all swapped", driven("all swapped", "reassign") ?? "–", `${driven("all swapped", "trust") ?? "–"} (labels trusted)`, "eval_live"],
  ["wrist limits (issue 15)", "ASL hand-frames beyond the wrist's range, robot", wristRow(true)?.["beyond the range"] ?? "–", `${wristRow(false)?.["beyond the range"] ?? "–"} (limits off)`, "eval_wrist"],
];
console.log("\n| capability | measure | handrig | without it | eval |");
console.log("| --- | --- | ---: | ---: | --- |");
for (const [name, measure, on, off, example] of capabilities) console.log(`| ${name} | ${measure} | ${on} | ${off} | \`${example}\` |`);

// The face, the legs and contact on the skin: each against what a user would pick instead.
const third = [];
const missing = [];
const tmp = mkdtempSync(join(tmpdir(), "handrig-table-"));
const pct = (x) => (Number.isFinite(x) ? `${(100 * x).toFixed(0)}%` : "–");
const faceClips = ["again", "eat", "please", "thanks", "brother", "hungry", "sister", "carphone"];
if (faceClips.every((c) => existsSync(join(root, "eval", "face", `${c}.json`)))) {
  run("node", ["eval/face.mjs", "--json", join(tmp, "face.json")]);
  const face = JSON.parse(readFileSync(join(tmp, "face.json"), "utf8"));
  const both = (fn) => [fn(face["test/handrig"], face["talking/handrig"]), fn(face["test/kalidokit"], face["talking/kalidokit"])];
  const where = "real faces, FaceLandmarker: the ASL test half (202 frames) and the talking face (120)";
  third.push(["face: blink recall / false blinks", where, ...both((t, k) => `${pct(t.blinkRecall)}, ${pct(k.blinkRecall)} / ${pct(t.falseBlinks)}, ${pct(k.falseBlinks)}`), "`face.mjs`"]);
  third.push(["face: `aa` >= 0.3 on open mouths / <= 0.1 on closed", "the talking face (23 open, 10 closed frames)", ...both((_, k) => `${pct(k.aaOpenAtLeast03)} / ${pct(k.aaShutAtMost01)}`), "`face.mjs`"]);
  third.push(["face: head yaw against the matrix, deg (mean / max)", where, ...both((t, k) => `${f(t.yawErrMean)}, ${f(k.yawErrMean)} / ${f(Math.max(t.yawErrMax, k.yawErrMax))}`), "`face.mjs`"]);
} else {
  missing.push("the face: `make eval-face` (records the ASL clips and the talking face with FaceLandmarker)");
}
const legClips = ["woman", "man", "child", "primitive"].flatMap((a) => ["walk", "sidestep", "squat", "oneleg"].map((c) => `${a}-${c}`));
if (legClips.every((c) => existsSync(join(root, "eval", "bench", "clips", `${c}-tasks.json`)))) {
  run("node", ["eval/bench/score-legs.mjs", "--json", join(tmp, "legs.json")]);
  const legs = JSON.parse(readFileSync(join(tmp, "legs.json"), "utf8")).report;
  const where = "the bench's report avatars (man, child, figure of primitives): walk, sidestep, squat, one leg";
  const m = (k, stat) => [legs.handrig, legs.kalidokit].map((x) => f(x?.[k]?.[stat]));
  third.push(["legs: knee / ankle from the hip, mm (median)", where, `${m("knee", "median")[0]} / ${m("ankle", "median")[0]}`, `${m("knee", "median")[1]} / ${m("ankle", "median")[1]}`, "`bench/score-legs.mjs`"]);
  third.push(["legs: foot sliding, mm per stance frame (mean)", where, m("slide", "mean")[0], m("slide", "mean")[1], "`bench/score-legs.mjs`"]);
  third.push(["legs: frames with a sole > 2 cm under the floor", where, `${legs.handrig.under} of ${legs.handrig.frames}`, `${legs.kalidokit?.under ?? "–"} of ${legs.kalidokit?.frames ?? "–"}`, "`bench/score-legs.mjs`"]);
} else {
  missing.push("the legs: `node eval/bench/tasks.mjs --legs` (tracks the bench's leg clips, 13 min), or `make eval-bench-legs`");
}
const skinFile = join(root, "target", "skin-contact.json");
if (existsSync(skinFile)) {
  const skin = JSON.parse(readFileSync(skinFile, "utf8")).rows.filter((r) => r.group === "half:report");
  const on = skin.find((r) => r.contact);
  const off = skin.find((r) => !r.contact);
  const day = statSync(skinFile).mtime.toISOString().slice(0, 10);
  const where = `the report half (report clips x report avatars; \`skin-contact.mjs --json\` of ${day})`;
  const lands = (r) => `${f(r?.face.cleanPct, 0)}% / ${f(r?.chest.cleanPct, 0)}% / ${f(r?.hand.cleanPct, 0)}%`;
  if (on && off) {
    third.push(["contact: face / chest / other-hand touches that land", where, lands(on), `${lands(off)} (contact off)`, "`skin-contact.mjs`"]);
    third.push(["contact: false touches / frames > 1 cm inside / deepest, mm", where, `${f(on.falseTouch.pct)}% / ${f(on.deep.pct, 2)}% / ${f(on.deep.maxMm)}`, `${f(off.falseTouch.pct)}% / ${f(off.deep.pct, 2)}% / ${f(off.deep.maxMm)} (contact off)`, "`skin-contact.mjs`"]);
  }
} else {
  missing.push("contact on the skin: `node eval/skin-contact.mjs --json` (15 min; writes target/skin-contact.json)");
}
console.log("\n| what | on | handrig | Kalidokit 1.1.5, or without it | eval |");
console.log("| --- | --- | ---: | ---: | --- |");
for (const [what, where, h, k, e] of third) console.log(`| ${what} | ${where} | ${h} | ${k} | ${e} |`);
for (const m of missing) console.log(`\nLeft out, its recordings missing: ${m}.`);

