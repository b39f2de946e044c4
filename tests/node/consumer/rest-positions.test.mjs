// Issue 2's acceptance check: rest positions from HandRig.fromVrm (handrig's own glTF/VRM
// reader, in wasm) equal, to 1e-5 m, what three-vrm computes for the same file: the world
// positions of its normalized humanoid bones (@pixiv/three-vrm from npm, GLTFLoader in Node).

import assert from "node:assert/strict";
import path from "node:path";
import { describe, it } from "node:test";

import { HandRig } from "handrig";
import { restPoseFromVRM } from "handrig/three-vrm";
import { avatarFiles, avatars, fixtureVrms, loadVRM, readBytes, threeNormalizedWorldPositions } from "./support.mjs";

const TOLERANCE_M = 1e-5;

function maxDistance(a, b) {
  let worst = { name: null, d: 0 };
  for (const name of Object.keys(a)) {
    const d = Math.hypot(a[name][0] - b[name][0], a[name][1] - b[name][1], a[name][2] - b[name][2]);
    if (!(d <= worst.d)) worst = { name, d };
  }
  return worst;
}

async function compare(file, t) {
  const vrm = await loadVRM(file);
  const three = await threeNormalizedWorldPositions(vrm);
  const rig = HandRig.fromVrm(readBytes(file));
  const ours = rig.restWorldPositions();
  const version = rig.vrmVersion;
  const boneNames = rig.boneNames();
  rig.free();

  assert.deepEqual(Object.keys(ours).sort(), Object.keys(three).sort(), "same set of humanoid bones");
  assert.deepEqual([...boneNames].sort(), Object.keys(three).sort(), "boneNames() lists the same bones");
  assert.equal(version, vrm.meta.metaVersion, "vrmVersion");
  const worst = maxDistance(ours, three);
  assert.ok(worst.d <= TOLERANCE_M, `${path.basename(file)}: ${worst.name} differs by ${worst.d} m`);

  // The adapter's rest pose (summed from normalizedRestPose) is three's too, so an app using
  // `new HandRig(restPoseFromVRM(vrm))` gets the same rig as `HandRig.fromVrm(bytes)`.
  const adapted = restPoseFromVRM(vrm);
  assert.equal(adapted.vrmVersion, vrm.meta.metaVersion);
  assert.deepEqual(Object.keys(adapted.bones).sort(), Object.keys(three).sort());
  const adapterWorst = maxDistance(adapted.bones, three);
  assert.ok(adapterWorst.d <= 1e-9, `restPoseFromVRM: ${adapterWorst.name} differs from three by ${adapterWorst.d} m`);
  t.diagnostic(`${path.basename(file)}: ${Object.keys(ours).length} bones, largest difference ${worst.d.toExponential(2)} m (${worst.name})`);
  return { bones: Object.keys(ours).length, worst };
}

describe("rest world positions: HandRig.fromVrm vs three-vrm's normalized humanoid", () => {
  it("debug-robot.vrm (VRM 1.0, Blender bone rolls, 53 bones)", async (t) => {
    const r = await compare(avatars.robot, t);
    assert.equal(r.bones, 53);
  });

  it("odd-armature-vrm0.vrm (VRM 0.x, 17 bones, off T-pose)", async (t) => {
    const r = await compare(avatars.odd0, t);
    assert.equal(r.bones, 17);
  });

  const fixtures = fixtureVrms();
  it("tests/fixtures holds the generated avatars (VRM 0.x with fingers, VRM 1.0)", () => {
    assert.ok(fixtures.length >= 2, `found ${fixtures.map((f) => path.basename(f))}`);
  });
  for (const file of fixtures) {
    it(`tests/fixtures/${path.basename(file)}`, async (t) => {
      await compare(file, t);
    });
  }

  // The human avatars of tools/avatars (issue 25): skinned MakeHuman bodies, 54 bones each.
  const humans = avatarFiles(".vrm");
  it("tests/fixtures/avatars holds the human avatars (woman, man, child; VRM 1.0 and 0.x)", () => {
    assert.equal(humans.length, 6, `found ${humans.map((f) => path.basename(f))}`);
  });
  for (const file of humans) {
    it(`tests/fixtures/avatars/${path.basename(file)}`, async (t) => {
      const r = await compare(file, t);
      assert.equal(r.bones, 54);
    });
  }
});
