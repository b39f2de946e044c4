// The packed package from CommonJS: require("handrig") and require("handrig/three-vrm") are
// ready at once, on the shared avatar and the real recording.

"use strict";

const assert = require("node:assert/strict");
const { describe, it, before } = require("node:test");

const handrig = require("handrig");
const adapter = require("handrig/three-vrm");
const { HandRig } = handrig;

let S;
before(async () => {
  S = await import("./support.mjs");
});

describe("require('handrig')", () => {
  it("exports HandRig, init, initSync and version; no default export in CommonJS", () => {
    assert.equal(typeof HandRig, "function");
    assert.equal(typeof HandRig.fromVrm, "function");
    assert.equal(typeof handrig.init, "function");
    assert.equal(typeof handrig.initSync, "function");
    assert.equal(handrig.version, process.env.HANDRIG_CARGO_VERSION);
    assert.equal(handrig.default, undefined);
  });

  it("is ready without init: fromVrm on debug-robot.vrm and every recording frame solved", () => {
    const rig = HandRig.fromVrm(S.readBytes(S.avatars.robot));
    assert.equal(rig.vrmVersion, "1");
    const names = rig.boneNames();
    assert.equal(names.length, 53);
    assert.equal(names[0], "hips");
    const results = S.solveRecording(rig);
    assert.equal(results.length, 621);
    for (const r of results) {
      // Every driven bone is in every result; the left hand has no tracked hand and rests.
      assert.ok(r.hands.right && !r.hands.left);
      assert.ok(!S.isIdentity(r.bones.rightHand) && S.isIdentity(r.bones.leftHand));
    }
    rig.free();
  });

  it("new HandRig(restPose) from another rig's rest positions reproduces them", () => {
    const a = HandRig.fromVrm(S.readBytes(S.avatars.robot));
    const rest = a.restWorldPositions();
    const b = new HandRig({ bones: rest, vrmVersion: "1" });
    const again = b.restWorldPositions();
    for (const [name, p] of Object.entries(rest)) {
      for (let i = 0; i < 3; i++) assert.ok(Math.abs(again[name][i] - p[i]) < 1e-6, `${name}`);
    }
    const frame = S.readRecording()[42];
    assert.deepEqual(b.solve(frame, {}).bones, a.solve(frame, {}).bones);
    a.free();
    b.free();
  });

  it("require('handrig/three-vrm') exports the adapter", () => {
    assert.equal(typeof adapter.restPoseFromVRM, "function");
    assert.equal(typeof adapter.applyToVRM, "function");
  });

  it("the adapter works from CommonJS on a three-vrm VRM", async () => {
    const vrm = await S.loadVRM(S.avatars.robot);
    const rest = adapter.restPoseFromVRM(vrm);
    assert.equal(rest.vrmVersion, "1");
    const rig = new HandRig(rest);
    const r = rig.solve(S.readRecording()[0]);
    assert.equal(adapter.applyToVRM(vrm, r), Object.keys(r.bones).length);
    const q = vrm.humanoid.getNormalizedBoneNode("rightHand").quaternion;
    assert.deepEqual([q.x, q.y, q.z, q.w], r.bones.rightHand);
    rig.free();
  });
});
