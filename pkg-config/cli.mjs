#!/usr/bin/env node
// The handrig command line (the package's `bin`, copied into the package by build.mjs):
//
//   handrig export RECORDING.json... --avatar AVATAR.vrm|AVATAR.glb (--out OUT.vrma|OUT.bvh | --out-dir DIR)
//
// The avatar is read as the library reads it: a .glb (VRM extension, Mixamo or Unreal names) by
// HandRig.fromGltf, a .vrm (or anything else) by HandRig.fromVrm. The mirroring defaults are the README quick
// start's (mirror: true, inputMirrored: false), so an export moves as the app's avatar does.
//
// Solves recordings in the shared JSON format (tools/record-video.mjs, the demo's recorder) on
// an avatar and writes VRM Animation (.vrma) or BVH files through MotionRecorder. Many
// recordings run on worker_threads, one per core. Progress and errors go to stderr (an error
// names the file and the frame, and does not stop the other files); the summary to stdout.
// Exit status: 0 all written, 1 some recording failed, 2 bad command line or avatar.

import fs from "node:fs";
import { createRequire } from "node:module";
import os from "node:os";
import path from "node:path";
import { parseArgs } from "node:util";
import v8 from "node:v8";
import { Worker, isMainThread, parentPort, workerData } from "node:worker_threads";

// No optimizing compiles on background threads: on Node 20 a busy machine left 1 in 4-15 runs
// hanging at exit after the file was written (the main thread draining the platform's tasks, a
// background TurboFan job waiting for a garbage collection only the main thread can run;
// gdb on the hung process; nodejs/node#54918). A flag set at run time only reaches isolates
// created after it (`node --trace-opt` shows the main thread's compiles still concurrent), so
// every recording is solved on a worker thread, even a single one: the main thread only reads
// the command line, checks the avatar once and waits.
v8.setFlagsFromString("--no-concurrent-recompilation");

const { HandRig, MotionRecorder, version } = createRequire(import.meta.url)("./index.cjs");

const USAGE = `usage: handrig export RECORDING.json|DIR... --avatar AVATAR.vrm|AVATAR.glb (--out OUT.vrma|OUT.bvh | --out-dir DIR) [options]

  --avatar FILE      the avatar the recordings are solved on: a .vrm (VRM 1.0 or 0.x), or any glTF
                     humanoid .glb (VRM extension, Mixamo or Unreal bone names), as HandRig.fromGltf reads it
  --out FILE         the file to write, for one recording: .vrma (VRM Animation) or .bvh
  --out-dir DIR      for any number of recordings: DIR/NAME.vrma (or .bvh with --format bvh)
  --format F         vrma (default) or bvh, with --out-dir
  --mirror           the avatar mirrors the user (options.mirror: true), as in the README's quick start: the default
  --no-mirror        the avatar does not mirror the user (options.mirror: false)
  --input-mirrored   the recording's images were flipped horizontally, selfie view (options.inputMirrored: true;
                     default false, as MediaPipe's recordings of a plain camera image)
  --options JSON     handrig rig options, e.g. '{"torso":"pose"}' (see docs/reference/options.md); mirror and
                     inputMirrored given here are used as given (not with the flags above)
  --tolerance DEG    .vrma key reduction: drop keys interpolation reproduces within DEG degrees (default 0: every frame)
  --fps N            .bvh frame rate (default: the recording's)
  --unit cm|m        .bvh length unit (default cm)
  --jobs N           worker threads (default: one per core)
  --quiet            no progress lines
  --version, --help

A directory stands for the .json files in it. Recordings are the shared format: an array of
frames or { width, height, frames: [{ timeMs, hands, pose }] }; frames with a FaceLandmarkerResult's
fields spread in (faceBlendshapes, ...) add expressions and look-at to the .vrma (docs/guide/export.md).`;

class UsageError extends Error {}

/** The rig for the avatar's bytes: HandRig.fromGltf for a glTF (`gltf`), else HandRig.fromVrm. */
function openAvatar(bytes, gltf, rigOptions) {
  return gltf ? HandRig.fromGltf(bytes, rigOptions) : HandRig.fromVrm(bytes, rigOptions);
}

/** Exports one recording; returns its figures. Throws an Error naming the file (and frame). */
function exportOne(task, avatar) {
  const { file, out, format, rigOptions, tolerance, fps, unit } = task;
  const name = path.basename(file);
  let rec;
  try {
    rec = JSON.parse(readFile(file, "utf8"));
  } catch (e) {
    throw new Error(`${file}: ${e.code === "ENOENT" ? "no such file" : e instanceof SyntaxError ? `not JSON (${e.message})` : e.message}`);
  }
  const frames = Array.isArray(rec) ? rec : rec !== null && typeof rec === "object" ? rec.frames : undefined;
  if (!Array.isArray(frames)) {
    throw new Error(`${file}: not a recording (expected an array of frames or an object with "frames")`);
  }
  if (frames.length === 0) throw new Error(`${file}: the recording has no frames`);
  const aspect = rec.width > 0 && rec.height > 0 ? rec.width / rec.height : undefined;
  const rig = openAvatar(avatar, task.gltf, rigOptions);
  try {
    const recorder = new MotionRecorder(rig);
    const result = {};
    for (let i = 0; i < frames.length; i++) {
      const f = frames[i];
      const where = () => `${file}: frames[${i}]${f && Number.isInteger(f.frame) && f.frame !== i ? ` (frame ${f.frame})` : ""}`;
      if (f === null || typeof f !== "object" || Array.isArray(f)) throw new Error(`${where()}: not a frame object`);
      if (aspect !== undefined && f.imageAspect === undefined) f.imageAspect = aspect;
      try {
        rig.solve(f, result);
        recorder.add(f.timeMs, result);
      } catch (e) {
        throw new Error(`${where()}: ${e.message}`);
      }
    }
    const data = format === "bvh" ? recorder.toBVH({ fps, unit }) : recorder.toVRMA({ tolerance });
    fs.mkdirSync(path.dirname(path.resolve(out)), { recursive: true });
    writeAtomically(out, data);
    return { file: name, out, frames: recorder.frameCount, seconds: recorder.duration / 1000, bytes: fs.statSync(out).size };
  } finally {
    rig.free();
  }
}

/** The longest file read (bytes): a JSON recording is read as one string, whose length V8 bounds. */
const MAX_FILE_BYTES = 2 ** 29 - 24;

/**
 * A file's contents, only when it is a regular file within MAX_FILE_BYTES: a FIFO or a device
 * would block or never end, a larger file cannot become one string (issue 49).
 */
function readFile(file, encoding) {
  const st = fs.statSync(file);
  if (!st.isFile()) throw new Error(st.isDirectory() ? "a directory, not a file" : "not a regular file");
  if (st.size > MAX_FILE_BYTES) throw new Error(`too large (${st.size} bytes; handrig reads files up to ${MAX_FILE_BYTES} bytes)`);
  return fs.readFileSync(file, encoding);
}

/**
 * Writes `out` whole or not at all: the data goes to a temporary file next to it, renamed over
 * `out` once complete, so a failed export leaves no partial file (and an older `out` as it was).
 */
function writeAtomically(out, data) {
  const tmp = path.join(path.dirname(out), `.${path.basename(out)}.${process.pid}.${Math.random().toString(36).slice(2)}.tmp`);
  try {
    fs.writeFileSync(tmp, data);
    fs.renameSync(tmp, out);
  } catch (e) {
    fs.rmSync(tmp, { force: true });
    throw new Error(`${out}: cannot write it (${e.code ?? e.message})`);
  }
}

if (!isMainThread) {
  // A worker: the avatar and options once, then one recording per message.
  const { avatar } = workerData;
  parentPort.on("message", (task) => {
    const t = process.hrtime.bigint();
    try {
      const r = exportOne(task, avatar);
      parentPort.postMessage({ ok: true, ...r, ms: Number(process.hrtime.bigint() - t) / 1e6 });
    } catch (e) {
      parentPort.postMessage({ ok: false, file: task.file, message: e.message });
    }
  });
} else {
  process.exitCode = await main(process.argv.slice(2)).catch((e) => {
    process.stderr.write(`handrig: ${e instanceof UsageError ? e.message : e.stack || e.message}\n`);
    return 2;
  });
}

function parse(argv) {
  let parsed;
  try {
    parsed = parseArgs({
      args: argv,
      allowPositionals: true,
      strict: true,
      options: {
        avatar: { type: "string" },
        out: { type: "string" },
        "out-dir": { type: "string" },
        format: { type: "string" },
        mirror: { type: "boolean" },
        "no-mirror": { type: "boolean" },
        "input-mirrored": { type: "boolean" },
        options: { type: "string" },
        tolerance: { type: "string" },
        fps: { type: "string" },
        unit: { type: "string" },
        jobs: { type: "string" },
        quiet: { type: "boolean" },
        help: { type: "boolean", short: "h" },
        version: { type: "boolean" },
      },
    });
  } catch (e) {
    // Node's message, e.g. "Unknown option '--avatr'. To specify a positional argument ...": its first sentence.
    throw new UsageError(`${String(e.message).split(". ")[0]} (handrig --help lists the options)`);
  }
  return parsed;
}

/**
 * The rig options with the mirroring flags: the quick start's `mirror: true` unless
 * `--no-mirror`, `inputMirrored` from `--input-mirrored`; what `--options` sets is kept (a flag
 * saying otherwise is an error).
 */
function mirroring(v, given) {
  if (v.mirror && v["no-mirror"]) throw new UsageError("--mirror and --no-mirror: give one");
  if (given !== undefined && (given === null || typeof given !== "object" || Array.isArray(given))) return given; // the rig names it
  const options = { ...given };
  const set = (key, value, flag) => {
    if (key in options && options[key] !== value) {
      throw new UsageError(`${flag}: --options sets ${key}: ${JSON.stringify(options[key])}; give it in one place`);
    }
    options[key] = value;
  };
  if (v["no-mirror"]) set("mirror", false, "--no-mirror");
  else if (v.mirror) set("mirror", true, "--mirror");
  else if (!("mirror" in options)) options.mirror = true;
  if (v["input-mirrored"]) set("inputMirrored", true, "--input-mirrored");
  return options;
}

function number(v, flag, ok) {
  if (v === undefined) return undefined;
  const n = Number(v);
  if (!Number.isFinite(n) || !ok(n)) throw new UsageError(`${flag}: not a valid value: ${JSON.stringify(v)}`);
  return n;
}

/** The .json files of the arguments (a directory: its .json files, sorted). */
function recordings(positionals) {
  const files = [];
  for (const p of positionals) {
    let st;
    try {
      st = fs.statSync(p);
    } catch {
      files.push(p); // reported as that file's error, without stopping the others
      continue;
    }
    if (st.isDirectory()) {
      const inDir = fs.readdirSync(p).filter((f) => f.endsWith(".json")).sort();
      if (inDir.length === 0) throw new UsageError(`${p}: no .json recordings in this directory`);
      files.push(...inDir.map((f) => path.join(p, f)));
    } else files.push(p);
  }
  return files;
}

async function main(argv) {
  const { values: v, positionals } = parse(argv);
  if (v.help) {
    process.stdout.write(`${USAGE}\n`);
    return 0;
  }
  if (v.version) {
    process.stdout.write(`handrig ${version}\n`);
    return 0;
  }
  const [command, ...inputs] = positionals;
  if (command !== "export") {
    throw new UsageError(command === undefined ? `no command\n${USAGE}` : `unknown command ${JSON.stringify(command)} (the command is "export")`);
  }
  if (inputs.length === 0) throw new UsageError("export: no recording given");
  if (v.avatar === undefined) throw new UsageError("export: --avatar AVATAR.vrm (or .glb) is required");
  if ((v.out === undefined) === (v["out-dir"] === undefined)) throw new UsageError("export: give --out FILE (one recording) or --out-dir DIR");
  let rigOptions;
  if (v.options !== undefined) {
    try {
      rigOptions = JSON.parse(v.options);
    } catch (e) {
      throw new UsageError(`--options: not JSON (${e.message})`);
    }
  }
  rigOptions = mirroring(v, rigOptions);
  const tolerance = (number(v.tolerance, "--tolerance", (n) => n >= 0 && n < 180) ?? 0) * (Math.PI / 180);
  const fps = number(v.fps, "--fps", (n) => n > 0 && n <= 1000);
  const unit = v.unit ?? "cm";
  if (unit !== "cm" && unit !== "m") throw new UsageError(`--unit: must be cm or m, got ${JSON.stringify(unit)}`);
  const cores = typeof os.availableParallelism === "function" ? os.availableParallelism() : os.cpus().length;
  const jobs = number(v.jobs, "--jobs", (n) => Number.isInteger(n) && n >= 1) ?? cores;

  let avatar;
  try {
    avatar = new Uint8Array(readFile(v.avatar));
  } catch (e) {
    throw new UsageError(`--avatar ${v.avatar}: ${e.code === "ENOENT" ? "no such file" : e.message}`);
  }
  // The avatar and the options, checked once here: the rig's Error names the bad field.
  const gltf = /^\.(glb|gltf)$/i.test(path.extname(v.avatar));
  try {
    openAvatar(avatar, gltf, rigOptions).free();
  } catch (e) {
    throw new UsageError(`${/^(vrm|gltf):/.test(e.message) ? `--avatar ${v.avatar}` : "--options"}: ${e.message}`);
  }

  const files = recordings(inputs);
  let tasks;
  if (v.out !== undefined) {
    if (files.length !== 1) throw new UsageError(`--out takes one recording (got ${files.length}); use --out-dir DIR for many`);
    const ext = path.extname(v.out).toLowerCase();
    if (ext !== ".vrma" && ext !== ".bvh") throw new UsageError(`--out ${v.out}: must end in .vrma or .bvh`);
    if (v.format !== undefined) throw new UsageError("--format goes with --out-dir (with --out the extension says it)");
    tasks = [{ file: files[0], out: v.out, format: ext.slice(1) }];
  } else {
    const format = v.format ?? "vrma";
    if (format !== "vrma" && format !== "bvh") throw new UsageError(`--format: must be vrma or bvh, got ${JSON.stringify(format)}`);
    const seen = new Map();
    tasks = files.map((file) => {
      const out = path.join(v["out-dir"], `${path.basename(file).replace(/\.json$/i, "")}.${format}`);
      if (seen.has(out)) throw new UsageError(`--out-dir: ${seen.get(out)} and ${file} would both write ${out}`);
      seen.set(out, file);
      return { file, out, format };
    });
  }
  for (const t of tasks) Object.assign(t, { rigOptions, tolerance, fps, unit, gltf });

  const t0 = process.hrtime.bigint();
  const workers = Math.max(1, Math.min(jobs, tasks.length));
  const done = [];
  const failed = [];
  const report = (r) => {
    if (r.ok) done.push(r);
    else failed.push(r);
    if (!r.ok) process.stderr.write(`handrig: ${r.message}\n`);
    else if (!v.quiet) {
      process.stderr.write(
        `[${done.length + failed.length}/${tasks.length}] ${r.file} -> ${r.out}: ${r.frames} frames, ${r.seconds.toFixed(2)} s, ${r.bytes} bytes (${(r.ms / 1000).toFixed(2)} s)\n`,
      );
    }
  };
  await new Promise((resolve, reject) => {
    let next = 0;
    let running = workers;
    for (let w = 0; w < workers; w++) {
      const worker = new Worker(new URL(import.meta.url), { workerData: { avatar } });
      const feed = () => {
        if (next < tasks.length) worker.postMessage(tasks[next++]);
        else {
          worker.terminate();
          if (--running === 0) resolve();
        }
      };
      worker.on("message", (r) => {
        report(r);
        feed();
      });
      worker.on("error", reject);
      feed();
    }
  });
  const wall = Number(process.hrtime.bigint() - t0) / 1e9;
  const sum = (k) => done.reduce((s, r) => s + r[k], 0);
  process.stdout.write(
    `handrig export: ${done.length} of ${tasks.length} written: ${sum("frames")} frames, ${sum("seconds").toFixed(2)} s of motion, ` +
      `${sum("bytes")} bytes, ${wall.toFixed(2)} s wall time on ${workers} worker thread${workers > 1 ? "s" : ""} (${cores} cores)` +
      `${failed.length ? `; ${failed.length} failed` : ""}\n`,
  );
  return failed.length ? 1 : 0;
}
