// handrig/worker in Node: the page side (createRigWorker) and the worker side (serveRig) joined by
// a MessageChannel (the same structured clone and transfer as a Worker's, on one thread), with
// the package's own rig on each end. The Vite build of it in Chromium: www/tests/vite-apps.test.mjs.

import assert from "node:assert/strict";
import fs from "node:fs";
import { createRequire } from "node:module";
import path from "node:path";
import { after, describe, it } from "node:test";
import * as handrig from "handrig";
import * as compat from "handrig/compat";
import { createRigWorker, readRotation, serveRig } from "handrig/worker";
import { shared } from "./support.mjs";

const { HandRig, LAYOUT } = handrig;
const require = createRequire(import.meta.url);
const avatarPath = path.join(shared, "avatars", "debug-robot.vrm");
const avatar = () => new Uint8Array(fs.readFileSync(avatarPath)).buffer;
const frames = JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", "eat.json"), "utf8")).frames;

/** A "worker" for the page side and the scope serveRig answers on, joined by a MessageChannel. */
const open = [];
function pair(lib = handrig) {
  const { port1, port2 } = new MessageChannel();
  serveRig(lib, port2);
  port1.terminate = () => {
    port1.close();
    port2.close();
  };
  open.push(port1);
  return port1;
}
// Open ports keep Node running (the rejected createRigWorker calls leave theirs).
after(() => open.forEach((p) => p.terminate()));

describe("handrig/worker", () => {
  it("has the same exports under require and import", () => {
    assert.deepEqual(Object.keys(require("handrig/worker")).sort(), ["createRigWorker", "readRotation", "serveRig"]);
  });

  it("solves a clip frame by frame as a rig on this side does, in two ping-ponged buffers", async () => {
    // Arms without a wrist at the T-pose (identity), so a rotation away from it is the tracking's.
    const options = { arm: { idle: "tpose" } };
    const rig = await createRigWorker(pair(), { avatar: avatar(), options });
    const local = HandRig.fromVrm(new Uint8Array(fs.readFileSync(avatarPath)), options);
    assert.deepEqual(rig.bones, local.boneNames());
    assert.equal(rig.latest, null);
    const seen = [];
    const q = [0, 0, 0, 1];
    let compared = 0;
    let moved = 0;
    let expected;
    rig.onResult = ({ output, timeMs, solveUs }) => {
      assert.equal(output.length, LAYOUT.output.length);
      assert.equal(timeMs, expected.timeMs);
      assert.ok(solveUs >= 0);
      assert.deepEqual(Array.from(output), Array.from(local.output), `frame at ${timeMs} ms`);
      for (const bone of ["rightUpperArm", "rightIndexProximal"]) {
        const want = expected.result.bones[bone];
        const got = readRotation(output, bone, q);
        assert.deepEqual(got, Array.from(want));
        if (Math.abs(got[3]) < 0.99) moved++;
      }
      // Two buffers go back and forth, transferred (not copied): the output of two results ago
      // went back to the worker with the frame after it, so it is detached here.
      seen.push(output);
      if (seen.length >= 3) assert.equal(seen.at(-3).buffer.byteLength, 0, "transferred back to the worker");
      compared++;
    };
    for (const frame of frames) {
      expected = { timeMs: frame.timeMs, result: local.solve(frame) };
      assert.equal(rig.solve(frame), true, "the worker is idle: the frame is sent");
      await rig.idle();
    }
    assert.equal(compared, frames.length);
    assert.ok(moved > frames.length / 2, `${moved} rotations away from rest`);
    assert.equal(seen.at(-1), rig.latest);
    assert.equal(rig.latest.buffer.byteLength, 4 * LAYOUT.output.length);
    assert.deepEqual(rig.stats, { frames: frames.length, sent: frames.length, solved: frames.length, dropped: 0, failed: 0 });
    rig.terminate();
    local.free();
  });

  it("never queues: while the worker is busy a newer frame replaces the pending one", async () => {
    const rig = await createRigWorker(pair(), { avatar: avatar() });
    const times = [];
    rig.onResult = ({ timeMs }) => times.push(timeMs);
    const sent = frames.map((f) => rig.solve(f));
    assert.deepEqual(sent, frames.map((_, i) => i === 0));
    await rig.idle();
    assert.deepEqual(times, [frames[0].timeMs, frames.at(-1).timeMs], "the first and the newest are solved");
    assert.deepEqual(rig.stats, { frames: frames.length, sent: 2, solved: 2, dropped: frames.length - 2, failed: 0 });
    rig.terminate();
  });

  it("reports a bad frame without losing the rig, and rejects a bad avatar with the rig's error", async () => {
    const rig = await createRigWorker(pair(), { avatar: avatar() });
    const errors = [];
    rig.onError = (m) => errors.push(m);
    rig.solve({ timeMs: 0, hands: "nope" });
    await rig.idle();
    assert.equal(errors.length, 1);
    assert.match(errors[0], /hands/);
    rig.solve(frames[10]);
    await rig.idle();
    assert.equal(rig.stats.failed, 1);
    assert.equal(rig.stats.solved, 1);
    assert.notEqual(rig.latest, null);
    rig.terminate();
    await assert.rejects(createRigWorker(pair(), { avatar: new Uint8Array([1, 2, 3]).buffer }), /^Error: vrm: truncated: 3 bytes/);
    await assert.rejects(createRigWorker(pair(), { avatar: avatar(), options: { smoothing: "lots" } }), /smoothing/);
  });

  it("serves handrig/compat the same way", async () => {
    const rig = await createRigWorker(pair(compat), { avatar: avatar(), options: { arm: { idle: "tpose" } } });
    rig.solve(frames[20]);
    await rig.idle();
    const q = readRotation(rig.latest, "rightUpperArm");
    assert.ok(q && Math.abs(q[3]) < 0.99, `rightUpperArm ${q}`);
    rig.terminate();
  });

  it("readRotation: null for a bone the rig does not drive, an Error for a name that is no bone", () => {
    const out = new Float32Array(LAYOUT.output.length);
    assert.equal(readRotation(out, "rightIndexProximal"), null);
    out[LAYOUT.output.boneFlags + LAYOUT.bones.indexOf("rightIndexProximal")] = 2;
    out[LAYOUT.output.boneRotations + 4 * LAYOUT.bones.indexOf("rightIndexProximal") + 3] = 1;
    assert.deepEqual(readRotation(out, "rightIndexProximal"), [0, 0, 0, 1]);
    assert.throws(() => readRotation(out, "rightPinky"), /readRotation: bone "rightPinky" is not one of LAYOUT.bones/);
  });
});
