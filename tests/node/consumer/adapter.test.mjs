// handrig/three-vrm: restPoseFromVRM -> new HandRig -> solve -> applyToVRM, on three-vrm VRMs
// loaded in Node. The end-to-end check is forward kinematics: after applyToVRM, three's own
// matrices put every bone where handrig's result.worldPositions says, for VRM 1.0 and 0.x alike.
// That holds only if the rotations are applied as they are (no VRM 0.x sign flip).

import assert from "node:assert/strict";
import path from "node:path";
import { describe, it } from "node:test";

import { HandRig } from "handrig";
import { applyToVRM, restPoseFromVRM } from "handrig/three-vrm";
import { avatars, fixtureVrms, loadVRM, readRecording, threeNormalizedWorldPositions } from "./support.mjs";

async function rawWorld(vrm) {
  const THREE = await import("three");
  vrm.scene.updateMatrixWorld(true);
  const positions = {};
  const rotations = {};
  for (const name of Object.keys(vrm.humanoid.normalizedRestPose)) {
    const node = vrm.humanoid.getRawBoneNode(name);
    if (!node) continue;
    positions[name] = node.getWorldPosition(new THREE.Vector3()).toArray();
    rotations[name] = node.getWorldQuaternion(new THREE.Quaternion());
  }
  return { positions, rotations };
}

function assertPositionsMatch(actual, expected, tolerance, what) {
  for (const [name, p] of Object.entries(expected)) {
    const q = actual[name];
    assert.ok(q, `${what}: ${name} missing`);
    const d = Math.hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
    assert.ok(d <= tolerance, `${what}: ${name} is ${d} m away`);
  }
}

function assertSameRotation(a, b, what) {
  const dot = Math.abs(a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w);
  assert.ok(dot > 1 - 1e-6, `${what}: rotations differ (|dot| = ${dot})`);
}

/** A right wrist target the arm can reach: 30% of the way from the rest hand to the upper arm. */
function reachableWrist(rest) {
  const hand = rest.bones.rightHand;
  const upper = rest.bones.rightUpperArm;
  return hand.map((h, k) => h + 0.3 * (upper[k] - h));
}

async function roundTrip(file) {
  const THREE = await import("three");
  const vrm = await loadVRM(file);
  const rest = restPoseFromVRM(vrm);
  // Wrist limits off: step 2 checks that a given wrist rotation comes out exactly (the limits
  // would turn this one, bent beyond the wrist's range, toward the forearm).
  const rig = new HandRig(rest, { arm: { wristLimits: false } });
  assert.equal(rig.vrmVersion, vrm.meta.metaVersion);
  const before = await rawWorld(vrm);

  // 1. A frame of the real recording plus a wrist, so hand, fingers and arm are all solved.
  const result = rig.solve({ ...readRecording()[250], wrists: { right: { position: reachableWrist(rest) } } });
  const solved = Object.keys(result.bones);
  assert.ok(solved.includes("rightUpperArm") && solved.includes("rightLowerArm"), `arm not solved: ${solved}`);
  assert.equal(applyToVRM(vrm, result), solved.length);
  for (const name of solved) {
    const q = vrm.humanoid.getNormalizedBoneNode(name).quaternion;
    assert.deepEqual([q.x, q.y, q.z, q.w], result.bones[name], `${name} written as given`);
  }
  // Normalized rig: three's forward kinematics == handrig's.
  assertPositionsMatch(await threeNormalizedWorldPositions(vrm), result.worldPositions, 1e-4, "normalized");
  // vrm.update copies normalized rotations to the model's own bones: the skeleton that renders.
  vrm.update(0);
  assertPositionsMatch((await rawWorld(vrm)).positions, result.worldPositions, 1e-4, "raw bones after vrm.update");

  // 2. A wrist rotation given in the model's own frame comes out as the hand's world rotation,
  //    on the normalized bone and (times its rest rotation) on the model's bone. A VRM 0.x
  //    sign flip anywhere on the way would turn the hand the other way about y and z.
  const r = new THREE.Quaternion().setFromEuler(new THREE.Euler(0.4, -0.7, 0.2));
  const wristOnly = rig.solve({ timeMs: 1, wrists: { right: { position: reachableWrist(rest), rotation: r.toArray() } } });
  rig.free();
  applyToVRM(vrm, wristOnly);
  vrm.update(0);
  const after = await rawWorld(vrm);
  const normalizedHand = vrm.humanoid.getNormalizedBoneNode("rightHand").getWorldQuaternion(new THREE.Quaternion());
  assertSameRotation(normalizedHand, r, "normalized rightHand world rotation");
  assertSameRotation(after.rotations.rightHand, r.clone().multiply(before.rotations.rightHand), "raw rightHand world rotation");
  return { vrm, result };
}

describe("handrig/three-vrm", () => {
  it("debug-robot.vrm (VRM 1.0): applied rotations put the skeleton where handrig says", async () => {
    const { result } = await roundTrip(avatars.robot);
    assert.ok(result.bones.rightIndexDistal, "fingers solved");
  });

  it("odd-armature-vrm0.vrm (VRM 0.x, no fingers, off T-pose): same, with no sign flip", async () => {
    await roundTrip(avatars.odd0);
  });

  for (const file of fixtureVrms()) {
    it(`tests/fixtures/${path.basename(file)}: same`, async () => {
      await roundTrip(file);
    });
  }

  it("restPoseFromVRM ignores the current pose and the scene transform", async () => {
    const vrm = await loadVRM(avatars.robot);
    const rest = restPoseFromVRM(vrm);
    vrm.scene.position.set(1, 2, 3);
    vrm.scene.rotation.y = Math.PI;
    vrm.humanoid.getNormalizedBoneNode("rightUpperArm").quaternion.set(0, 0, Math.SQRT1_2, Math.SQRT1_2);
    vrm.update(0);
    assert.deepEqual(restPoseFromVRM(vrm), rest);
  });

  it("applyToVRM skips bones the avatar lacks and returns the count written", async () => {
    const vrm = await loadVRM(avatars.odd0);
    const n = applyToVRM(vrm, { bones: { rightHand: [0, 0, 0, 1], rightIndexProximal: [0, 0, 0, 1] } });
    assert.equal(n, 1);
  });

  it("rejects what is not a three-vrm VRM or a solve result", async () => {
    const vrm = await loadVRM(avatars.robot);
    assert.throws(() => restPoseFromVRM({}), (e) => e instanceof TypeError && /vrm\.humanoid/.test(e.message));
    assert.throws(() => restPoseFromVRM(null), TypeError);
    assert.throws(
      () => restPoseFromVRM({ humanoid: vrm.humanoid, meta: { metaVersion: "2" } }),
      /vrm\.meta\.metaVersion/,
    );
    assert.throws(() => applyToVRM(vrm, {}), (e) => e instanceof TypeError && /result\.bones/.test(e.message));
    assert.throws(() => applyToVRM(undefined, { bones: {} }), /vrm\.humanoid/);
  });
});
