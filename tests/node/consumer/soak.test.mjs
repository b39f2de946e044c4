// Memory over long runs (issues 10 and 13): the per-frame paths create no garbage, wasm memory
// does not grow with frames, and creating and freeing rigs returns their memory.

import assert from "node:assert/strict";
import inspector from "node:inspector";
import { describe, it } from "node:test";
import v8 from "node:v8";
import vm from "node:vm";

import { HandRig, LAYOUT } from "handrig";
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

  it("the object API with a FaceLandmarkerResult spread into each frame (issue 50): 50,000 frames, a few bytes each", async () => {
    const rig = HandRig.fromVrm(robotBytes);
    // 32 results (MediaPipe's shapes: 478 landmarks, 52 categories with their index, the
    // matrix), cycled; the hand video's frames beside them.
    const names = ["_neutral", ...LAYOUT.arkit.filter((n) => n !== "tongueOut")];
    const results = Array.from({ length: 32 }, (_, k) => {
      const c = Math.cos(k / 20);
      const s = Math.sin(k / 20);
      return {
        faceLandmarks: [Array.from({ length: 478 }, (_, i) => ({ x: 0.4 + (i % 20) * 0.01, y: 0.4 + Math.floor(i / 20) * 0.01, z: 0, visibility: 0, presence: 0 }))],
        faceBlendshapes: [{ categories: names.map((categoryName, index) => ({ index, score: ((index * 7 + k) % 10) / 10, categoryName, displayName: "" })), headIndex: -1, headName: "" }],
        facialTransformationMatrixes: [{ rows: 4, columns: 4, data: [c, 0, -s, 0, 0, 1, 0, 0, s, 0, c, 0, 1, -2, -40, 1] }],
      };
    });
    // Object.assign, not { ...f, ...result }: V8 (Node 20) makes frames built by two spreads
    // whose reads of absent fields (frame.wrists, .torso, ... in packFrame) leave ~30 bytes of
    // garbage each, ~280 bytes a frame with or without the face's fields read
    // (docs/measurements/2026-12-06-face.md); this test measures the face's own reading.
    const withFace = frames.map((f, i) => Object.assign({}, f, results[i % results.length]));
    let sink = 0;
    const perFrame = await allocatedPerFrame(50000, function faceFrame(i) {
      const r = rig.solve(withFace[i % withFace.length]);
      sink += r.arkit[0] + r.expressions.aa;
    });
    assert.ok(Number.isFinite(sink));
    assert.equal(rig.solve(withFace[0]).face, "tracked");
    // Reading the face (its fields, 52 categories, the matrix; the landmarks beside
    // blendshapes in the first frames only) and filling result.expressions / .arkit / .lookAt
    // make no objects (an object per category would be over 800 bytes a frame); V8 boxes a
    // few numbers on the way as in the test above, as many as its JIT state has it: measured 38
    // bytes a frame alone, 105 after the tests above; the bound is theirs.
    console.log(`# object API with a face: ${perFrame.toFixed(0)} bytes allocated per frame (JS)`);
    assert.ok(perFrame < 320, `the object API with a face allocates ${perFrame.toFixed(0)} bytes a frame`);
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
