// Memory over long runs (issues 10 and 13): the per-frame paths create no garbage, wasm memory
// does not grow with frames, and creating and freeing rigs returns their memory.

import assert from "node:assert/strict";
import { PerformanceObserver } from "node:perf_hooks";
import { describe, it } from "node:test";
import v8 from "node:v8";
import vm from "node:vm";

import { HandRig } from "handrig";
import { avatars, readBytes, readRecording } from "./support.mjs";

v8.setFlagsFromString("--expose-gc");
const gc = vm.runInNewContext("gc");

const robotBytes = readBytes(avatars.robot);
const frames = readRecording();

/**
 * Runs `frame(i)` `n` times after a warm-up and a full GC; returns the JS heap growth (bytes)
 * without collecting in between, and how many GCs ran meanwhile. Code that allocates nothing
 * leaves both at about zero; 16 bytes a frame would be 1.6 MB over 100,000 frames.
 */
function garbage(n, frame) {
  for (let i = 0; i < 2000; i++) frame(i);
  gc();
  gc();
  let collections = 0;
  const obs = new PerformanceObserver((list) => {
    collections += list.getEntries().length;
  });
  obs.observe({ entryTypes: ["gc"] });
  const before = process.memoryUsage().heapUsed;
  for (let i = 0; i < n; i++) frame(i);
  const grown = process.memoryUsage().heapUsed - before;
  obs.disconnect();
  return { grown, collections };
}

describe("no garbage per frame", () => {
  it("the flat path (rig.input, solveFlat, rig.output): 100,000 frames", () => {
    const rig = HandRig.fromVrm(robotBytes);
    // Pack the recording once through the object API, then replay the packed inputs.
    const packed = frames.map((f) => {
      rig.solve(f);
      return Float32Array.from(rig.input);
    });
    const input = rig.input;
    const output = rig.output;
    let sink = 0;
    const { grown, collections } = garbage(100000, (i) => {
      input.set(packed[i % packed.length]);
      rig.solveFlat(i * 33.3);
      sink += output[0];
    });
    assert.ok(Number.isFinite(sink));
    // One allocation per frame would be at least 16 bytes a frame, 1.6 MB.
    assert.ok(grown < 512 * 1024, `heap grew ${grown} bytes over 100,000 frames`);
    assert.equal(collections, 0, `${collections} garbage collections during the run`);
    rig.free();
  });

  it("the object API with the rig's own result object: 100,000 frames, a few bytes each", () => {
    const rig = HandRig.fromVrm(robotBytes);
    const withWrists = frames.map((f) => ({ ...f, wrists: { right: { position: [-0.45, 1.3, 0.2] } } }));
    let sink = 0;
    const { grown, collections } = garbage(100000, (i) => {
      sink += rig.solve(withWrists[i % withWrists.length]).bones.rightHand[3];
    });
    assert.ok(Number.isFinite(sink));
    // No objects or arrays per frame: the result and all its parts are reused. V8 still boxes
    // a few doubles on the way (measured about 70 bytes a frame, a minor GC every ~200,000
    // frames); a fresh result object would be over 10 KB a frame.
    assert.ok(grown < 128 * 100000, `heap grew ${grown} bytes over 100,000 frames`);
    assert.ok(collections <= 2, `${collections} garbage collections during the run`);
    rig.free();
  });

  it("the test itself sees garbage when there is some", () => {
    const { grown, collections } = garbage(100000, (i) => ({ i, a: [i, i + 1, i + 2] }));
    assert.ok(grown > 1024 * 1024 || collections > 0, `grown ${grown}, collections ${collections}`);
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
    assert.equal(rig.input.buffer.byteLength, bytes, "wasm memory grew");
    assert.ok(heapGrowth < 1 << 20, `JS heap grew ${heapGrowth} bytes`);
    assert.deepEqual(rig.solve(frames[300], {}).bones, reference.bones);
    rig.free();
  });
});
