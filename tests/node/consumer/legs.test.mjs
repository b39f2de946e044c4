// Legs, feet and hips (issue 51) through the package: the synthetic squat and walk of
// eval/frames/legs-synthetic.json (pose only, legs in view; eval_legs --write-frames) solved on a
// three-vrm VRM: the legs are driven and move, the hips go down in the squat, applyToVRM puts the
// normalized hips at their rest position plus result.hipsOffset (object result and flat output
// alike), and a MotionRecorder's BVH carries the hips' translation. A head-and-shoulders frame
// leaves the legs and the hips at rest.

import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";
import { describe, it } from "node:test";

import { HandRig, LAYOUT, MotionRecorder } from "handrig";
import { applyToVRM, restPoseFromVRM } from "handrig/three-vrm";
import { avatarFiles, isIdentity, loadVRM, repo, shared } from "./support.mjs";

const frames = JSON.parse(fs.readFileSync(path.join(repo, "eval", "frames", "legs-synthetic.json"), "utf8")).frames;
const woman = avatarFiles(".vrm").find((f) => f.endsWith("woman-vrm1.vrm"));

/** The normalized hips node's position. */
const hipsAt = (vrm) => vrm.humanoid.getNormalizedBoneNode("hips").position.toArray();

describe("legs through the package", () => {
  it("a squat lowers the hips, applyToVRM moves the normalized hips, the BVH carries it", async () => {
    const vrm = await loadVRM(woman);
    const rest = restPoseFromVRM(vrm);
    const restHips = [...vrm.humanoid.normalizedRestPose.hips.position];
    const rig = new HandRig(rest);
    assert.ok(rig.drivenBones().includes("leftUpperLeg") && rig.drivenBones().includes("rightFoot"));
    const recorder = new MotionRecorder(rig);
    let lowest = 0;
    let bent = 0;
    for (const f of frames) {
      const result = rig.solve(f);
      recorder.add(result.timeMs, result);
      lowest = Math.min(lowest, result.hipsOffset[1]);
      const knee = result.bones.leftLowerLeg;
      bent = Math.max(bent, 2 * Math.acos(Math.min(1, Math.abs(knee[3]))));
      applyToVRM(vrm, result);
      const at = hipsAt(vrm);
      for (let c = 0; c < 3; c++) assert.ok(Math.abs(at[c] - (restHips[c] + result.hipsOffset[c])) < 1e-6, `hips[${c}]`);
      assert.equal(typeof result.feetPlanted.left, "boolean");
    }
    // The squat takes the woman's hips down by a good part of her legs; the knees bend.
    assert.ok(lowest < -0.15, `hips lowest offset ${lowest}`);
    assert.ok(bent > 1, `largest knee bend ${bent} rad`);
    // The flat output: the same hips position.
    applyToVRM(vrm, rig.output);
    const O = LAYOUT.output;
    const out = rig.output;
    const at = hipsAt(vrm);
    for (let c = 0; c < 3; c++) assert.ok(Math.abs(at[c] - (restHips[c] + out[O.hipsOffset + c])) < 1e-6);
    // The BVH's root Y position (cm) spans the squat.
    const bvh = recorder.toBVH();
    const motion = bvh.slice(bvh.indexOf("Frame Time")).split("\n").slice(1).filter((l) => l.trim());
    const ys = motion.map((l) => Number(l.trim().split(/\s+/)[1]));
    assert.ok(Math.max(...ys) - Math.min(...ys) > 15, `BVH hips Y spans ${Math.max(...ys) - Math.min(...ys)} cm`);
    rig.free();
  });

  it("head and shoulders: legs and hips stay at rest", async () => {
    const vrm = await loadVRM(woman);
    const rig = new HandRig(restPoseFromVRM(vrm));
    const restHips = [...vrm.humanoid.normalizedRestPose.hips.position];
    const asl = JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", "again.json"), "utf8")).frames;
    for (const f of asl) {
      const result = rig.solve({ timeMs: f.timeMs, pose: f.pose, hands: [] });
      for (const bone of ["leftUpperLeg", "leftLowerLeg", "leftFoot", "rightUpperLeg", "rightLowerLeg", "rightFoot"]) {
        assert.ok(isIdentity(result.bones[bone]), `${bone} moved`);
      }
      assert.deepEqual(result.hipsOffset, [0, 0, 0]);
      applyToVRM(vrm, result);
      assert.deepEqual(hipsAt(vrm), restHips);
    }
    rig.free();
  });
});
