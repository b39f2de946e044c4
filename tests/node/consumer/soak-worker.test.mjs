// Issue 49's soak: (1) an hour of 30 fps frames through a rig in a worker thread
// (handrig/worker's createRigWorker and serveRig, the way a page runs it) with recording on
// (MotionRecorder.add of every result); (2) many rigs in one process, each solving its own
// stream. Memory must stay flat after the warm-up (within 1 MB: the JS heaps of both threads,
// the main thread's with its ArrayBuffers minus the recording's own storage, which grows with
// frames by design; the wasm memories) and
// the time per frame must not grow.
//
// Short by default (make test); HANDRIG_SOAK=long (make soak) runs the full lengths: 108,000
// frames (one hour at 30 fps) through the worker, 100 rigs for 10 minutes of frames (18,000
// each). The figures go to stdout (`# soak ...` lines) and to docs/measurements/2026-12-06-robustness.md.

import assert from "node:assert/strict";
import path from "node:path";
import { describe, it } from "node:test";
import v8 from "node:v8";
import vm from "node:vm";
import { MessageChannel, Worker } from "node:worker_threads";
import { fileURLToPath } from "node:url";

import { HandRig, MotionRecorder } from "handrig";
import { createRigWorker, readRotation } from "handrig/worker";
import { avatars, readBytes, readRecording } from "./support.mjs";

v8.setFlagsFromString("--expose-gc");
const gc = vm.runInNewContext("gc");

const LONG = process.env.HANDRIG_SOAK === "long";
const FRAMES = LONG ? 108_000 : 15_000;
const RIGS = LONG ? 100 : 10;
const RIG_FRAMES = LONG ? 18_000 : 1_500;
const MB = 1 << 20;
const robot = readBytes(avatars.robot);
const recording = readRecording();
const here = path.dirname(fileURLToPath(import.meta.url));

const mb = (b) => `${(b / MB).toFixed(2)} MB`;

/** A node:worker_threads Worker as handrig/worker's WorkerLike (a DOM Worker's shape). */
function workerLike(w) {
  const like = {
    onmessage: null,
    onerror: null,
    postMessage: (m, transfer) => w.postMessage(m, transfer),
    terminate: () => w.terminate(),
  };
  w.on("message", (data) => like.onmessage?.({ data }));
  w.on("error", (e) => like.onerror?.({ message: e.message }));
  return like;
}

/** The recording's storage (bytes) after `n` frames: capacities double from 64. */
function recorderBytes(n, driven) {
  let cap = 64;
  while (cap < n) cap *= 2;
  return cap * (8 + 16 * driven + 12);
}

describe(`soak (${LONG ? "long" : "short"}: HANDRIG_SOAK=long for an hour of frames)`, () => {
  it(`${FRAMES.toLocaleString("en")} frames through a rig in a worker thread, recording every result`, async () => {
    const { port1: stats, port2 } = new MessageChannel();
    const thread = new Worker(path.join(here, "soak-worker.child.mjs"), {
      workerData: { stats: port2, avatar: robot },
      transferList: [port2],
    });
    const ask = () => new Promise((resolve) => {
      stats.once("message", resolve);
      stats.postMessage(0);
    });
    const rig = await createRigWorker(workerLike(thread), { avatar: robot.slice() });
    // The recorder, fed from the flat output (readRotation into one reused result object).
    const local = HandRig.fromVrm(robot);
    const recorder = new MotionRecorder(local);
    const driven = recorder.bones;
    local.free();
    const result = { bones: Object.fromEntries(driven.map((b) => [b, [0, 0, 0, 1]])) };
    let next;
    rig.onResult = ({ output, timeMs }) => {
      for (const b of driven) readRotation(output, b, result.bones[b]);
      recorder.add(timeMs, result);
      next();
    };
    rig.onError = (m) => assert.fail(m);
    const frame = (i) => {
      const f = recording[i % recording.length];
      return { ...f, timeMs: i * (1000 / 30) };
    };
    // Prebuilt frames (the recording's, with an hour of times): the loop allocates only what
    // the worker protocol does.
    const solveOne = (i) => new Promise((resolve) => {
      next = resolve;
      rig.solve(frame(i));
    });
    const memory = async () => {
      gc();
      const w = await ask();
      // The recording's typed arrays are ArrayBuffer memory, outside the JS heap proper.
      const m = process.memoryUsage();
      return {
        main: m.heapUsed + m.arrayBuffers - recorderBytes(recorder.frameCount, driven.length),
        worker: w.heap,
        wasm: w.wasm,
        rss: process.memoryUsage().rss,
      };
    };
    const WINDOW = 1000;
    const timeWindow = async (from) => {
      const t = performance.now();
      for (let i = from; i < from + WINDOW; i++) await solveOne(i);
      return ((performance.now() - t) / WINDOW) * 1000; // us per frame
    };
    const start = await memory();
    const warm = Math.min(5000, FRAMES / 3);
    for (let i = 0; i < warm; i++) await solveOne(i);
    const warmed = await memory();
    const firstUs = await timeWindow(warm);
    for (let i = warm + WINDOW; i < FRAMES - WINDOW; i++) await solveOne(i);
    const lastUs = await timeWindow(FRAMES - WINDOW);
    const end = await memory();
    await thread.terminate();
    stats.close();
    assert.equal(recorder.frameCount, FRAMES);
    assert.equal(rig.stats.failed, 0);
    assert.equal(rig.stats.solved, FRAMES);
    const line = (k) => `${mb(start[k])} at start, ${mb(warmed[k])} after warm-up, ${mb(end[k])} at the end`;
    console.log(`# soak worker: ${FRAMES} frames (${(FRAMES / 30 / 60).toFixed(1)} min at 30 fps), recording on (${recorder.frameCount} frames, ${mb(recorderBytes(FRAMES, driven.length))} of storage)`);
    console.log(`# soak worker: main JS heap and ArrayBuffers, minus the recording: ${line("main")}`);
    console.log(`# soak worker: worker JS heap: ${line("worker")}`);
    console.log(`# soak worker: worker wasm memory: ${line("wasm")}`);
    console.log(`# soak worker: process RSS: ${line("rss")}`);
    console.log(`# soak worker: round trip per frame: ${firstUs.toFixed(1)} us after warm-up, ${lastUs.toFixed(1)} us at the end`);
    assert.ok(end.main - warmed.main < MB, `main heap grew ${end.main - warmed.main} bytes`);
    assert.ok(end.worker - warmed.worker < MB, `worker heap grew ${end.worker - warmed.worker} bytes`);
    assert.ok(end.wasm - warmed.wasm <= MB, `worker wasm memory grew ${end.wasm - warmed.wasm} bytes`);
    assert.ok(lastUs < 1.5 * firstUs + 50, `slower at the end: ${firstUs.toFixed(1)} -> ${lastUs.toFixed(1)} us`);
  });

  it(`${RIGS} rigs in one process, ${RIG_FRAMES.toLocaleString("en")} frames each`, () => {
    const rigs = Array.from({ length: RIGS }, () => HandRig.fromVrm(robot));
    const results = rigs.map(() => ({}));
    // Each rig its own stream: the recording from its own offset (its frames' times are
    // rewritten in place: no object per frame; this is the file's last test).
    const step = (f) => {
      for (let r = 0; r < RIGS; r++) {
        const src = recording[(f + 97 * r) % recording.length];
        src.timeMs = f * (1000 / 30);
        rigs[r].solve(src, results[r]);
      }
    };
    const memory = () => {
      gc();
      return { heap: process.memoryUsage().heapUsed, wasm: rigs[0].input.buffer.byteLength };
    };
    const start = memory();
    const warm = Math.min(1000, RIG_FRAMES / 3);
    for (let f = 0; f < warm; f++) step(f);
    const warmed = memory();
    const WINDOW = Math.min(500, RIG_FRAMES / 6);
    const window = (from) => {
      const t = performance.now();
      for (let f = from; f < from + WINDOW; f++) step(f);
      return ((performance.now() - t) / (WINDOW * RIGS)) * 1000;
    };
    const firstUs = window(warm);
    for (let f = warm + WINDOW; f < RIG_FRAMES - WINDOW; f++) step(f);
    const lastUs = window(RIG_FRAMES - WINDOW);
    const end = memory();
    for (const r of rigs) r.free();
    const line = (k) => `${mb(start[k])} at start, ${mb(warmed[k])} after warm-up, ${mb(end[k])} at the end`;
    console.log(`# soak rigs: ${RIGS} rigs x ${RIG_FRAMES} frames (${(RIG_FRAMES / 30 / 60).toFixed(1)} min at 30 fps each)`);
    console.log(`# soak rigs: JS heap: ${line("heap")}`);
    console.log(`# soak rigs: wasm memory: ${line("wasm")}`);
    console.log(`# soak rigs: solve per rig-frame: ${firstUs.toFixed(1)} us after warm-up, ${lastUs.toFixed(1)} us at the end`);
    assert.ok(end.heap - warmed.heap < MB, `heap grew ${end.heap - warmed.heap} bytes`);
    assert.ok(end.wasm - warmed.wasm <= MB, `wasm memory grew ${end.wasm - warmed.wasm} bytes`);
    assert.ok(lastUs < 1.5 * firstUs + 20, `slower at the end: ${firstUs.toFixed(1)} -> ${lastUs.toFixed(1)} us`);
  });
});
