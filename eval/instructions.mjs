// Per-frame cost as machine instructions, counted by valgrind: handrig and Kalidokit on the same
// frames, with a figure that does not depend on how busy the machine is (eval/speed.mjs times
// them; on a shared machine its figures move by up to 1.6x within minutes). Instructions are
// not time (the two run different kinds of code: wasm floating point, JavaScript objects and
// their garbage), so the ratios here and speed.mjs's differ; this is for before/after of a change
// and for where the work goes, speed.mjs for what a user sees.
//
//   node eval/instructions.mjs [--pkg DIR] [--passes N] [--only CASE,...] [--avatar FILE] [--frames FILE]
//
// --avatar: a .vrm (default ../shared/avatars/debug-robot.vrm; the skinned human
// tests/fixtures/avatars/woman-vrm1.vrm counts self-contact on the skin); --frames: full frames
// from a JSON file ({ frames: [...] }, e.g. eval/frames/hands-near-face.json, both hands near
// each other and near the face) instead of the 250 ASL frames.
//
// Needs valgrind (`apt-get install -y valgrind`) and `npm ci --prefix eval` (Kalidokit 1.1.5).
// Each case runs in its own `node` under `valgrind --tool=callgrind` twice: 30 warm-up passes
// over the 250 ASL full frames (../shared/data/asl, pose and 0-2 hands) and then N more passes
// (default 10, at least 5), and 30 warm-up passes alone; the difference over N x 250 frames is
// the figure.
// Node runs with `--single-threaded --no-liftoff --no-wasm-dynamic-tiering`: the wasm is compiled
// by the optimizing compiler up front and JavaScript is optimized on the main thread, so the
// counted passes run the code a warmed page runs, and repeated runs agree to about 3%.
//
// Cases: `kalidokit` (Pose.solve + Hand.solve per hand, as eval/speed.mjs), `object` (handrig's
// object API, default options), `scope` (the object API with what Kalidokit does not do turned
// off: speed.mjs's "Kalidokit's scope"), `flat` (the flat path, defaults: frames packed once
// beforehand and copied into the input view), `flatScope`, `noContact` (the object API with
// `contact.enabled: false`, all else default).

import { execFileSync } from "node:child_process";
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { dirname, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import { aslFrames, KALIDOKIT_SCOPE, kalidokitFrame, kalidokitSolve } from "./full-frame.mjs";

const here = dirname(fileURLToPath(import.meta.url));
const self = fileURLToPath(import.meta.url);
const shared = process.env.HANDRIG_SHARED ?? resolve(here, "../../shared");
const require = createRequire(import.meta.url);

const arg = (name, dflt) => {
  const i = process.argv.indexOf(name);
  return i > 0 ? process.argv[i + 1] : dflt;
};

const CASES = ["kalidokit", "object", "scope", "flat", "flatScope", "noContact"];
const framesOf = (file) => (file ? JSON.parse(readFileSync(file, "utf8")).frames : aslFrames(shared));
const WARMUP = 30;

if (process.argv.includes("--child")) child();
else driver();

// One case: the warm-up passes, then `--passes` more.
function child() {
  const [kind, passes, pkg] = [arg("--case"), Number(arg("--passes")), arg("--pkg")];
  const frames = framesOf(arg("--frames", null));
  let sink = 0;
  let pass;
  if (kind === "kalidokit") {
    const Kalidokit = require("kalidokit/dist/kalidokit.umd.js");
    const kd = frames.map(kalidokitFrame);
    pass = () => {
      for (const k of kd) sink += kalidokitSolve(Kalidokit, k);
    };
  } else {
    const { HandRig } = require(resolve(pkg));
    const robot = readFileSync(arg("--avatar", `${shared}/avatars/debug-robot.vrm`));
    const options =
      kind === "scope" || kind === "flatScope" ? KALIDOKIT_SCOPE : kind === "noContact" ? { contact: { enabled: false } } : undefined;
    const rig = HandRig.fromVrm(robot, options);
    if (kind === "object" || kind === "scope" || kind === "noContact") {
      pass = () => {
        for (const f of frames) sink += rig.solve(f).timeMs;
      };
    } else {
      const packer = HandRig.fromVrm(robot, options);
      const packed = frames.map((f) => {
        packer.solve(f);
        return Float32Array.from(packer.input);
      });
      const { input, output } = rig;
      pass = () => {
        for (let i = 0; i < frames.length; i++) {
          input.set(packed[i]);
          rig.solveFlat(frames[i].timeMs);
          sink += output[0];
        }
      };
    }
  }
  for (let p = 0; p < WARMUP + passes; p++) pass();
  if (!Number.isFinite(sink)) throw new Error("no result");
}

function refs(kind, passes, pkg, extra) {
  // valgrind writes its summary to stderr: both streams are read.
  const args = [
    "--tool=callgrind",
    "--callgrind-out-file=/dev/null",
    process.execPath,
    "--single-threaded",
    "--no-liftoff",
    "--no-wasm-dynamic-tiering",
    self,
    "--child",
    "--case",
    kind,
    "--passes",
    String(passes),
    "--pkg",
    pkg,
    ...extra,
  ];
  let out;
  try {
    out = execFileSync("sh", ["-c", 'exec "$0" "$@" 2>&1', "valgrind", ...args], { encoding: "utf8", maxBuffer: 1 << 26 });
  } catch (e) {
    if (/not found|ENOENT/.test(String(e.stdout ?? "") + String(e.message))) {
      console.error("valgrind is not installed: apt-get install -y valgrind");
      process.exit(2);
    }
    throw new Error(`${kind}: ${e.stdout ?? e.message}`);
  }
  const m = /I\s+refs:\s+([\d,]+)/.exec(out);
  if (!m) throw new Error(`${kind}: no instruction count in valgrind's output:\n${out.slice(-2000)}`);
  return Number(m[1].replaceAll(",", ""));
}

function driver() {
  const pkg = resolve(arg("--pkg", resolve(here, "../pkg")));
  const passes = Number(arg("--passes", "10"));
  // Fewer counted passes leave the difference to the noise of the process around them
  // (2 passes read 20% low here; 5, 10 and 20 agree to about 3%).
  if (!(Number.isInteger(passes) && passes >= 5)) throw new Error(`--passes: an integer of at least 5, got ${arg("--passes")}`);
  const only = arg("--only", CASES.join(",")).split(",");
  for (const c of only) if (!CASES.includes(c)) throw new Error(`--only: unknown case ${c} (${CASES.join(", ")})`);
  const extra = [];
  const avatar = arg("--avatar", null);
  const framesFile = arg("--frames", null);
  if (avatar) extra.push("--avatar", resolve(avatar));
  if (framesFile) extra.push("--frames", resolve(framesFile));
  const perPass = framesOf(framesFile && resolve(framesFile)).length;
  const frames = perPass * passes;
  const rows = [];
  for (const kind of only) {
    const counted = refs(kind, passes, pkg, extra) - refs(kind, 0, pkg, extra);
    rows.push([kind, counted / frames]);
    console.error(`${kind}: ${Math.round(counted / frames)} instructions per frame`);
  }
  const kd = rows.find(([k]) => k === "kalidokit")?.[1];
  const avatarName = avatar ? avatar.replace(/^.*\//, "") : "robot";
  const framesName = framesFile ? framesFile.replace(/^.*\//, "") : "ASL";
  console.log(`Instructions per full frame (valgrind, ${passes} passes of ${perPass} ${framesName} frames after ${WARMUP}; ${avatarName}; ${pkg})`);
  console.log(`${"case".padEnd(12)} ${"instructions".padStart(12)}   Kalidokit / this`);
  for (const [kind, n] of rows) {
    const ratio = kd === undefined ? "-" : (kd / n).toFixed(2);
    console.log(`${kind.padEnd(12)} ${String(Math.round(n)).padStart(12)}   ${ratio}`);
  }
}
