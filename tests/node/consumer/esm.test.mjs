// The packed package from Node ES modules: ready on import, the shared avatar and the real
// recording, MediaPipe's result shapes, the mirror table, free().

import assert from "node:assert/strict";
import { createRequire } from "node:module";
import { describe, it } from "node:test";
import fs from "node:fs";

import init, { HandRig, init as namedInit, initSync, version } from "handrig";
import {
  assertResultWellFormed,
  avatars,
  handBones,
  quatAngle,
  readBytes,
  readRecording,
  solveRecording,
  isIdentity,
} from "./support.mjs";

const require = createRequire(import.meta.url);

describe("import('handrig') in Node", () => {
  it("is ready without init: static and instance calls work at once", () => {
    const options = HandRig.optionDescriptions();
    assert.ok(Array.isArray(options) && options.length > 0);
    for (const o of options) {
      assert.equal(typeof o.path, "string");
      assert.ok(["boolean", "enum", "number", "numbers", "points"].includes(o.type), `${o.path}: type ${o.type}`);
      assert.equal(typeof o.description, "string");
    }
    const rig = HandRig.fromVrm(readBytes(avatars.robot));
    assert.equal(rig.boneNames().length, 53);
    rig.free();
  });

  it("init is a resolved no-op (code shared with browsers can await it)", async () => {
    assert.equal(init, namedInit);
    assert.equal(await init(), undefined);
    assert.equal(initSync(), undefined);
    assert.equal(version, require("handrig/package.json").version);
  });

  it("shares one WebAssembly instance with require('handrig')", () => {
    assert.equal(require("handrig").HandRig, HandRig);
  });

  it("fromVrm takes a Buffer, Uint8Array, ArrayBuffer or DataView alike", () => {
    const buf = fs.readFileSync(avatars.robot);
    const u8 = new Uint8Array(buf);
    const inputs = [buf, u8, u8.buffer, new DataView(u8.buffer)];
    const expected = HandRig.fromVrm(u8).restWorldPositions();
    assert.equal(Object.keys(expected).length, 53);
    for (const input of inputs) {
      const rig = HandRig.fromVrm(input);
      assert.deepEqual(rig.restWorldPositions(), expected);
      assert.equal(rig.vrmVersion, "1");
      rig.free();
    }
  });
});

describe("the real recording on debug-robot.vrm (fromVrm)", () => {
  const frames = readRecording();

  it("solves all 621 frames with finite numbers and unit quaternions", () => {
    const rig = HandRig.fromVrm(readBytes(avatars.robot));
    const results = solveRecording(rig);
    assert.equal(results.length, 621);
    assert.equal(frames.length, 621);
    rig.free();
  });

  it("the subject's right hand (labelled \"Left\", unmirrored video) drives the avatar's RIGHT hand", () => {
    const rig = HandRig.fromVrm(readBytes(avatars.robot));
    const right = new Set(handBones("right"));
    const rightFingers = handBones("right").filter((b) => b !== "rightHand" && rig.boneNames().includes(b));
    assert.equal(rightFingers.length, 15);
    const handAngles = [];
    const rightArm = ["rightShoulder", "rightUpperArm", "rightLowerArm"];
    let armMoved = 0;
    // The rest a rig shows with nothing tracked: arms down by the sides (arm.idle "down").
    const idle = HandRig.fromVrm(readBytes(avatars.robot)).solve({ timeMs: 0 }, {}).bones;
    assert.ok(!isIdentity(idle.leftUpperArm) && !isIdentity(idle.rightLowerArm), "the idle arms hang down, not the T-pose");
    const same = (a, b) => Math.abs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]) > 1 - 1e-6;
    frames.forEach((frame, i) => {
      const r = rig.solve(frame);
      assert.equal(r.hands.right?.status, "solved", `frame ${i}: the right hand not solved`);
      assert.equal(r.hands.left, undefined, `frame ${i}: a left hand reported`);
      for (const b of rightFingers) assert.ok(r.bones[b], `frame ${i}: ${b} missing from bones`);
      // Every driven bone is reported; hand-only input moves the right hand and its arm (placed
      // from the hand's image: handsOnly), nothing else (the left arm stays at its idle rest).
      for (const [b, q] of Object.entries(r.bones)) {
        if (!right.has(b) && !rightArm.includes(b)) assert.ok(same(q, idle[b]), `frame ${i}: hand-only input moved ${b}`);
      }
      if (r.ikTargets.right && !same(r.bones.rightUpperArm, idle.rightUpperArm)) armMoved++;
      handAngles.push(quatAngle(r.bones.rightHand));
    });
    // The hand turns during the video: its rotation is not one constant.
    const spread = Math.max(...handAngles) - Math.min(...handAngles);
    assert.ok(spread > 0.3, `rightHand rotation angle spread ${spread} rad over the recording`);
    assert.ok(armMoved > frames.length / 2, `the right arm placed from the hand in ${armMoved} frames`);
    rig.free();
  });

  it("inputMirrored and mirror pick the side as in the README table", () => {
    const cases = [
      { inputMirrored: false, mirror: false, side: "right" },
      { inputMirrored: false, mirror: true, side: "left" },
      { inputMirrored: true, mirror: false, side: "left" },
      { inputMirrored: true, mirror: true, side: "right" },
    ];
    const bytes = readBytes(avatars.robot);
    const rotations = {};
    for (const c of cases) {
      const rig = HandRig.fromVrm(bytes, { inputMirrored: c.inputMirrored, mirror: c.mirror });
      const other = c.side === "right" ? "left" : "right";
      for (const i of [0, 200, 400, 620]) {
        const r = rig.solve(frames[i]);
        assert.ok(r.hands[c.side] && !isIdentity(r.bones[`${c.side}Hand`]), `${JSON.stringify(c)} frame ${i}: ${c.side}Hand not solved`);
        assert.ok(!r.hands[other] && isIdentity(r.bones[`${other}Hand`]), `${JSON.stringify(c)} frame ${i}: ${other}Hand solved`);
      }
      rotations[`${c.inputMirrored}/${c.mirror}`] = rig.solve(frames[200]).bones[`${c.side}Hand`];
      rig.free();
    }
    // x is flipped when inputMirrored XOR mirror, so the two cases with the same flip see the
    // same landmarks and must give the same rotation.
    const close = (a, b) => Math.abs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]) > 1 - 1e-6;
    assert.ok(close(rotations["false/false"], rotations["true/true"]));
    assert.ok(close(rotations["false/true"], rotations["true/false"]));
  });
});

describe("MediaPipe result shapes", () => {
  const frame = readRecording()[300];
  const hand = frame.hands[0];
  const obj = (p) => ({ x: p[0], y: p[1], z: p[2] });
  const solveOnce = (options) => {
    const rig = HandRig.fromVrm(readBytes(avatars.robot), options);
    const r = rig.solve({ timeMs: frame.timeMs, hands: [hand] });
    rig.free();
    return r;
  };
  const reference = solveOnce({});
  // World landmarks alone place no arm (arms from hands alone read the image landmarks).
  const worldOnly = solveOnce({ handsOnly: false });

  const shapes = {
    "handrig hands with {x,y,z} points": {
      timeMs: frame.timeMs,
      hands: [{ handedness: hand.handedness, score: hand.score, worldLandmarks: hand.worldLandmarks.map(obj), landmarks: hand.landmarks.map(obj) }],
    },
    "handrig hands with a flat Float32Array(63)": {
      timeMs: frame.timeMs,
      hands: [{ handedness: hand.handedness, score: hand.score, worldLandmarks: Float32Array.from(hand.worldLandmarks.flat()) }],
    },
    "tasks-vision HandLandmarkerResult as frame.hands": {
      timeMs: frame.timeMs,
      hands: {
        landmarks: [hand.landmarks.map(obj)],
        worldLandmarks: [hand.worldLandmarks.map(obj)],
        handedness: [[{ categoryName: hand.handedness, displayName: hand.handedness, score: hand.score, index: 0 }]],
      },
    },
    "tasks-vision HandLandmarkerResult as the frame": {
      landmarks: [hand.landmarks.map(obj)],
      worldLandmarks: [hand.worldLandmarks.map(obj)],
      handednesses: [[{ categoryName: hand.handedness, score: hand.score, index: 0 }]],
    },
    "legacy @mediapipe/hands results": {
      multiHandLandmarks: [hand.landmarks.map(obj)],
      multiHandWorldLandmarks: [hand.worldLandmarks.map(obj)],
      multiHandedness: [{ label: hand.handedness, score: hand.score, index: 0 }],
    },
  };
  for (const [name, input] of Object.entries(shapes)) {
    it(`${name} gives the same bones`, () => {
      const rig = HandRig.fromVrm(readBytes(avatars.robot));
      const r = rig.solve(input);
      assertResultWellFormed(r, name);
      const want = input.hands?.[0]?.landmarks || input.landmarks || input.hands?.landmarks || input.multiHandLandmarks ? reference : worldOnly;
      assert.deepEqual(Object.keys(r.bones).sort(), Object.keys(want.bones).sort());
      for (const [b, q] of Object.entries(want.bones)) {
        const p = r.bones[b];
        const dot = Math.abs(q[0] * p[0] + q[1] * p[1] + q[2] * p[2] + q[3] * p[3]);
        // Float32Array input rounds the landmarks to f32, as the wasm side does anyway.
        assert.ok(dot > 1 - 1e-6, `${b}: ${p} vs ${q}`);
      }
      rig.free();
    });
  }
});

describe("free()", () => {
  it("is idempotent; a freed rig throws an Error that says so", () => {
    const rig = HandRig.fromVrm(readBytes(avatars.robot));
    assert.equal(rig.freed, false);
    rig.free();
    rig.free();
    assert.equal(rig.freed, true);
    assert.throws(() => rig.solve(readRecording()[0]), (e) => e instanceof Error && /freed/.test(e.message));
    assert.throws(() => rig.boneNames(), /freed/);
    assert.throws(() => rig.vrmVersion, /freed/);
  });

  it("Symbol.dispose frees the rig where the runtime has it", { skip: typeof Symbol.dispose !== "symbol" && "no Symbol.dispose in this Node" }, () => {
    const rig = HandRig.fromVrm(readBytes(avatars.robot));
    rig[Symbol.dispose]();
    assert.equal(rig.freed, true);
  });
});
