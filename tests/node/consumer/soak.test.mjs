// Memory over long runs (issues 10 and 13): the per-frame paths create no garbage, wasm memory
// does not grow with frames, and creating and freeing rigs returns their memory.

import assert from "node:assert/strict";
import inspector from "node:inspector";
import { describe, it } from "node:test";
import v8 from "node:v8";
import vm from "node:vm";

import { HandRig } from "handrig";
import { avatars, readBytes, readRecording } from "./support.mjs";

v8.setFlagsFromString("--expose-gc");
const gc = vm.runInNewContext("gc");

const robotBytes = readBytes(avatars.robot);
const frames = readRecording();

const session = new inspector.Session();
session.connect();
const post = (method, params) =>
  new Promise((resolve, reject) => session.post(method, params, (e, r) => (e ? reject(e) : resolve(r))));

/**
 * Bytes allocated per call of `frame(i)` over `n` calls after a warm-up, from V8's sampling
 * heap profiler (every 64 bytes sampled, objects later collected included), counting only
 * allocations made inside `frame`: a measure of garbage that GC timing cannot hide.
 */
async function allocatedPerFrame(n, frame) {
  for (let i = 0; i < 2000; i++) frame(i);
  await post("HeapProfiler.enable");
  await post("HeapProfiler.startSampling", {
    samplingInterval: 64,
    includeObjectsCollectedByMajorGC: true,
    includeObjectsCollectedByMinorGC: true,
  });
  for (let i = 0; i < n; i++) frame(i);
  const { profile } = await post("HeapProfiler.stopSampling");
  await post("HeapProfiler.disable");
  let bytes = 0;
  const walk = (node, inside) => {
    const here = inside || node.callFrame.functionName === frame.name;
    if (here) bytes += node.selfSize;
    for (const c of node.children) walk(c, here);
  };
  walk(profile.head, false);
  return bytes / n;
}

describe("no garbage per frame", () => {
  it("the flat path (rig.input, solveFlat, rig.output): 100,000 frames", async () => {
    const rig = HandRig.fromVrm(robotBytes);
    // Pack the recording once through the object API, then replay the packed inputs.
    const packed = frames.map((f) => {
      rig.solve(f);
      return Float32Array.from(rig.input);
    });
    const input = rig.input;
    const output = rig.output;
    let sink = 0;
    const perFrame = await allocatedPerFrame(100000, function flatFrame(i) {
      input.set(packed[i % packed.length]);
      rig.solveFlat(i * 33.3);
      sink += output[0];
    });
    assert.ok(Number.isFinite(sink));
    // One allocation per frame would be at least 16 bytes a frame. Measured 0.29-0.38, once
    // 1.69 (in one of six runs: one-off allocations of V8 while it re-optimizes, a few hundred
    // KiB over the 100,000 frames), hence the margin.
    console.log(`# flat path: ${perFrame.toFixed(2)} bytes allocated per frame (JS)`);
    assert.ok(perFrame < 4, `the flat path allocates ${perFrame.toFixed(2)} bytes a frame`);
    rig.free();
  });

  it("the object API with the rig's own result object: 100,000 frames, a few bytes each", async () => {
    const rig = HandRig.fromVrm(robotBytes);
    const withWrists = frames.map((f) => ({ ...f, wrists: { right: { position: [-0.45, 1.3, 0.2] } } }));
    let sink = 0;
    const perFrame = await allocatedPerFrame(100000, function objectFrame(i) {
      sink += rig.solve(withWrists[i % withWrists.length]).bones.rightHand[3];
    });
    assert.ok(Number.isFinite(sink));
    // No objects or arrays per frame: the result and all its parts are reused. V8 still boxes
    // a few numbers on the way, how many depends on the JIT's state: 42-47 bytes a frame when
    // this test runs alone, 263 after the flat test above has optimized the same packing and
    // result code for frames without wrists (one "wrong map" deopt, then polymorphic code that
    // inlines less; self-contact's report fields added ~100 of them, the input checks of
    // 2026-12-02 ~40: 296-307). A fresh result object would be over 10 KB a frame.
    console.log(`# object API: ${perFrame.toFixed(0)} bytes allocated per frame (JS)`);
    assert.ok(perFrame < 320, `the object API allocates ${perFrame.toFixed(0)} bytes a frame`);
    rig.free();
  });

  it("the test itself sees garbage when there is some", async () => {
    const keep = new Array(64);
    const perFrame = await allocatedPerFrame(100000, function garbageFrame(i) {
      keep[i % 64] = { i, a: [i, i + 1, i + 2] };
    });
    assert.ok(perFrame > 32, `${perFrame} bytes a frame measured for an object and an array`);
  });
});

describe("soak", () => {
  it("5,000 rigs created and freed: wasm memory stays flat", () => {
    const rigs = [];
    for (let i = 0; i < 50; i++) rigs.push(HandRig.fromVrm(robotBytes));
    for (const r of rigs.splice(0)) r.free();
    const probe = HandRig.fromVrm(robotBytes);
    const start = probe.input.buffer.byteLength;
    probe.free();
    for (let i = 0; i < 5000; i++) {
      const r = HandRig.fromVrm(robotBytes);
      r.solve(frames[i % frames.length]);
      r.free();
    }
    const after = HandRig.fromVrm(robotBytes);
    const end = after.input.buffer.byteLength;
    after.free();
    console.log(`# 5,000 rigs created and freed: wasm memory ${start} -> ${end} bytes`);
    assert.ok(end - start <= 1 << 20, `wasm memory grew from ${start} to ${end} bytes`);
  });

  it("200,000 frames on one rig: wasm memory and the JS heap stay flat, the output stays right", () => {
    const rig = HandRig.fromVrm(robotBytes);
    const reference = rig.solve(frames[300], {});
    const bytes = rig.input.buffer.byteLength;
    gc();
    const heap = process.memoryUsage().heapUsed;
    for (let i = 0; i < 200000; i++) rig.solve(frames[i % frames.length]);
    gc();
    const heapGrowth = process.memoryUsage().heapUsed - heap;
    console.log(`# 200,000 frames on one rig: wasm memory ${bytes} -> ${rig.input.buffer.byteLength} bytes, JS heap ${heapGrowth >= 0 ? "+" : ""}${heapGrowth} bytes`);
    assert.equal(rig.input.buffer.byteLength, bytes, "wasm memory grew");
    assert.ok(heapGrowth < 1 << 20, `JS heap grew ${heapGrowth} bytes`);
    assert.deepEqual(rig.solve(frames[300], {}).bones, reference.bones);
    rig.free();
  });
});
