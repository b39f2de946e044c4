// The worker thread of soak-worker.test.mjs: handrig/worker's serveRig on the thread's port (a
// rig in a worker, as a page runs it), and a second port answering memory questions: this
// thread's JS heap (after a full GC) and its wasm memory.

import v8 from "node:v8";
import vm from "node:vm";
import { parentPort, workerData } from "node:worker_threads";
import * as handrig from "handrig";
import { serveRig } from "handrig/worker";

v8.setFlagsFromString("--expose-gc");
const gc = vm.runInNewContext("gc");

serveRig(handrig, parentPort);
const stats = workerData.stats;
stats.on("message", () => {
  gc();
  // A probe rig's input is a view of the module's one wasm memory.
  const probe = handrig.HandRig.fromVrm(workerData.avatar);
  const wasm = probe.input.buffer.byteLength;
  probe.free();
  stats.postMessage({ heap: process.memoryUsage().heapUsed, wasm });
});
