// Issue 28: any glTF humanoid. HandRig.fromGltf on the generated Mixamo- and Unreal-named
// bodies (tests/fixtures/avatars), rig.boneMap(), and the plain three.js adapter `handrig/three`
// (restPoseFromSkeleton, applyToSkeleton) against three-vrm driving the VRM of the same body:
// after applyToSkeleton, every bound bone of a GLTFLoader-loaded Mixamo body stands where the VRM
// body's raw bone stands after applyToVRM + vrm.update, within 0.1 mm, on every frame of an ASL
// clip; also with random bone rolls written into the three.js scene (bone rotations, children and
// inverse bind matrices, the skinned rest shape unchanged) and with the model turned to face -Z.

import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";
import { describe, it } from "node:test";

import { HandRig } from "handrig";
import { applyToSkeleton, restPoseFromSkeleton, sanitizeNodeName } from "handrig/three";
import { applyToVRM } from "handrig/three-vrm";
import { loadGltf, loadVRM, readBytes, repo, shared } from "./support.mjs";

const dir = path.join(repo, "tests", "fixtures", "avatars");
const file = (name) => path.join(dir, name);
const clip = (name) => JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", `${name}.json`), "utf8"));
const OPTIONS = { mirror: true };
const frameOf = (f) => ({ timeMs: f.timeMs, hands: f.hands, pose: f.pose });

/**
 * Angle (degrees) of the rotation between two quaternions (q and -q equal), accurate near 0:
 * 2 atan2(|vector part of a b*|, |scalar part|). (2 acos|a.b| is not: two f32 quaternions a few
 * ulps off unit length read as 0.05 degrees apart.)
 */
function angleDeg(a, b) {
  const [ax, ay, az, aw] = a;
  const [bx, by, bz, bw] = [-b[0], -b[1], -b[2], b[3]];
  const x = aw * bx + ax * bw + ay * bz - az * by;
  const y = aw * by - ax * bz + ay * bw + az * bx;
  const z = aw * bz + ax * by - ay * bx + az * bw;
  const w = aw * bw - ax * bx - ay * by - az * bz;
  return (2 * Math.atan2(Math.hypot(x, y, z), Math.abs(w)) * 180) / Math.PI;
}

/** A deterministic uniform random rotation per call (Shoemake), as a THREE.Quaternion. */
function randomRotations(THREE, seed) {
  let s = seed >>> 0;
  const next = () => {
    s = (Math.imul(s, 1664525) + 1013904223) >>> 0;
    return s / 2 ** 32;
  };
  return () => {
    const [u1, u2, u3] = [next(), next(), next()];
    const a = Math.sqrt(1 - u1);
    const b = Math.sqrt(u1);
    const t = 2 * Math.PI;
    return new THREE.Quaternion(a * Math.sin(t * u2), a * Math.cos(t * u2), b * Math.sin(t * u3), b * Math.cos(t * u3));
  };
}

/** Sample vertices of the skinned body at its current pose (three's own skinning). */
function skinnedSample(THREE, scene) {
  let mesh;
  scene.traverse((o) => {
    if (o.isSkinnedMesh && !mesh) mesh = o;
  });
  scene.updateMatrixWorld(true);
  mesh.skeleton.update();
  const out = [];
  const count = mesh.geometry.attributes.position.count;
  for (let i = 0; i < count; i += 97) {
    const v = new THREE.Vector3().fromBufferAttribute(mesh.geometry.attributes.position, i);
    mesh.applyBoneTransform(i, v);
    out.push(v.applyMatrix4(mesh.matrixWorld));
  }
  return out;
}

/**
 * Gives every bone of the scene a random roll R (its frame turned): quaternion q -> q R, each
 * child's position and rotation -> R^-1 p, R^-1 q_c, and the bone's inverse bind matrix ->
 * R^-1 * IBM, so the skinned rest shape stays the same. Returns how many bones were rolled.
 */
function rollBones(THREE, scene, seed) {
  const random = randomRotations(THREE, seed);
  let mesh;
  scene.traverse((o) => {
    if (o.isSkinnedMesh && !mesh) mesh = o;
  });
  const bones = mesh.skeleton.bones;
  for (let j = 0; j < bones.length; j++) {
    const bone = bones[j];
    const R = random();
    const Rinv = R.clone().invert();
    bone.quaternion.multiply(R);
    for (const c of bone.children) {
      c.position.applyQuaternion(Rinv);
      c.quaternion.premultiply(Rinv);
    }
    mesh.skeleton.boneInverses[j].premultiply(new THREE.Matrix4().makeRotationFromQuaternion(Rinv));
  }
  scene.updateMatrixWorld(true);
  return bones.length;
}

/** Drives the VRM (three-vrm) and the glTF scene (handrig/three) over a clip; largest bone distance. */
async function compareWithVrm(THREE, { vrmFile, scene, rig, binding, frames }) {
  const vrm = await loadVRM(vrmFile);
  const vrmRig = HandRig.fromVrm(readBytes(vrmFile), OPTIONS);
  const a = new THREE.Vector3();
  const b = new THREE.Vector3();
  let worst = { d: 0, bone: "", frame: -1 };
  let worstAngle = 0;
  let compared = 0;
  frames.forEach((f, k) => {
    const r1 = vrmRig.solve(frameOf(f));
    applyToVRM(vrm, r1);
    const bones1 = Object.fromEntries(Object.entries(r1.bones).map(([n, q]) => [n, [...q]]));
    vrm.update(0);
    vrm.scene.updateMatrixWorld(true);
    const r2 = rig.solve(frameOf(f));
    for (const [n, q] of Object.entries(r2.bones)) worstAngle = Math.max(worstAngle, angleDeg(q, bones1[n]));
    assert.equal(applyToSkeleton(scene, r2, binding), Object.keys(r2.bones).length);
    scene.updateMatrixWorld(true);
    for (const [bone, node] of Object.entries(binding)) {
      const raw = vrm.humanoid.getRawBoneNode(bone);
      if (!raw) continue;
      raw.getWorldPosition(a);
      scene.getObjectByName(sanitizeNodeName(node)).getWorldPosition(b);
      const d = a.distanceTo(b);
      compared++;
      if (!(d <= worst.d)) worst = { d, bone, frame: k };
    }
  });
  vrmRig.free();
  assert.ok(compared > frames.length * 50, `${compared} bone positions compared`);
  return { worst, worstAngle };
}

describe("HandRig.fromGltf", () => {
  for (const body of ["woman", "man", "child"]) {
    it(`${body}: Mixamo and Unreal names bound, result.bones as fromVrm's (Mixamo) and as the adapter's rest pose gives`, async () => {
      const frames = clip("thanks").frames;
      const vrm = HandRig.fromVrm(readBytes(file(`${body}-vrm1.vrm`)), OPTIONS);
      const mixamo = HandRig.fromGltf(readBytes(file(`${body}-mixamo.glb`)), OPTIONS);
      const unreal = HandRig.fromGltf(readBytes(file(`${body}-unreal.glb`)), OPTIONS);
      const mm = mixamo.boneMap();
      assert.equal(Object.keys(mm).length, 54);
      assert.equal(mm.leftUpperArm, "mixamorig:LeftArm");
      assert.equal(mm.leftThumbMetacarpal, "mixamorig:LeftHandThumb1");
      const um = unreal.boneMap();
      assert.equal(um.hips, "pelvis");
      assert.equal(um.leftIndexProximal, "index_01_l");
      assert.equal(vrm.boneMap(), null);
      // The adapter binds the same nodes from a GLTFLoader scene (three's sanitized names).
      const scene = (await loadGltf(file(`${body}-unreal.glb`))).scene;
      const rest = restPoseFromSkeleton(scene);
      assert.deepEqual(rest.boneMap, Object.fromEntries(Object.entries(um).map(([b, n]) => [b, sanitizeNodeName(n)])));
      assert.equal(rest.vrmVersion, "1");
      const fromScene = new HandRig(rest, OPTIONS);
      let worstMixamo = 0;
      let worstUnreal = 0;
      for (const f of frames) {
        const want = vrm.solve(frameOf(f));
        const got = mixamo.solve(frameOf(f));
        assert.deepEqual(Object.keys(got.bones), Object.keys(want.bones));
        for (const n of Object.keys(want.bones)) worstMixamo = Math.max(worstMixamo, angleDeg(got.bones[n], want.bones[n]));
        const u = unreal.solve(frameOf(f));
        const s = fromScene.solve(frameOf(f));
        for (const n of Object.keys(u.bones)) worstUnreal = Math.max(worstUnreal, angleDeg(u.bones[n], s.bones[n]));
      }
      for (const r of [vrm, mixamo, unreal, fromScene]) r.free();
      assert.ok(worstMixamo < 0.05, `Mixamo vs VRM: ${worstMixamo} deg`);
      assert.ok(worstUnreal < 0.05, `Unreal: fromGltf vs restPoseFromSkeleton: ${worstUnreal} deg`);
    });
  }

  it("options.skeleton.boneMap binds any names; bad rigs are Errors naming the bone", () => {
    const bytes = readBytes(file("woman-unreal.glb"));
    const auto = HandRig.fromGltf(bytes);
    const map = auto.boneMap();
    auto.free();
    const byMap = HandRig.fromGltf(bytes, { skeleton: { boneMap: map }, mirror: true });
    assert.deepEqual(byMap.boneMap(), map);
    byMap.free();
    const bad = (edit, re) => {
      const m = { ...map };
      edit(m);
      assert.throws(() => HandRig.fromGltf(bytes, { skeleton: { boneMap: m } }), re);
    };
    bad((m) => delete m.leftHand, /^Error: gltf: missing required bone\(s\) leftHand/);
    bad((m) => ([m.leftIndexProximal, m.leftIndexIntermediate] = [m.leftIndexIntermediate, m.leftIndexProximal]),
      /wrong hierarchy: leftIndexIntermediate \(node \d+ "index_01_l"\) is not below leftIndexProximal/);
    bad((m) => (m.rightHand = m.leftHand), /duplicate binding: leftHand and rightHand are both bound to node \d+ "hand_l"/);
    bad((m) => (m.leftWing = "hand_l"), /options\.skeleton\.boneMap: unknown bone name "leftWing"/);
    bad((m) => (m.head = 7), /options\.skeleton\.boneMap\.head: must be a node name/);
    bad((m) => (m.head = "Head"), /boneMap\.head: no node named "Head"/);
    assert.throws(() => HandRig.fromGltf(bytes, { skeleton: { bonemap: map } }), /options\.skeleton\.bonemap: unknown option/);
    assert.throws(() => HandRig.fromGltf(bytes, { skeleton: { boneMap: map }, mirorr: true }), /options\.mirorr: unknown option/);
    assert.throws(() => HandRig.fromGltf(new Uint8Array(16)), /^Error: gltf: not a glTF binary/);
  });
});

describe("handrig/three: a GLTFLoader Mixamo body driven like three-vrm drives its VRM", () => {
  const cases = [
    { name: "as exported", roll: false, turn: false, vrm: "man-vrm1.vrm" },
    { name: "with random bone rolls", roll: true, turn: false, vrm: "man-vrm1.vrm" },
    { name: "rolled and turned to face -Z", roll: true, turn: true, vrm: "man-vrm0.vrm" },
  ];
  for (const c of cases) {
    it(`man-mixamo.glb ${c.name}: every bone within 0.1 mm of the VRM's on every frame`, async (t) => {
      const THREE = await import("three");
      const scene = (await loadGltf(file("man-mixamo.glb"))).scene;
      if (c.roll) {
        const before = skinnedSample(THREE, scene);
        const rolled = rollBones(THREE, scene, 28);
        assert.ok(rolled > 50, `${rolled} bones rolled`);
        const after = skinnedSample(THREE, scene);
        const moved = Math.max(...before.map((v, i) => v.distanceTo(after[i])));
        assert.ok(moved < 1e-6, `the rolls moved the skinned rest shape by ${moved} m`);
        let turned = 0;
        scene.traverse((o) => o.isBone && Math.abs(o.quaternion.w) < 0.999 && turned++);
        assert.ok(turned > 50, `${turned} bones turned`);
      }
      if (c.turn) {
        // The half turn inside the model (its Armature node), so the root stays unturned.
        const armature = scene.getObjectByName("Armature");
        armature.quaternion.premultiply(new THREE.Quaternion(0, 1, 0, 0));
        armature.position.applyQuaternion(new THREE.Quaternion(0, 1, 0, 0));
        scene.updateMatrixWorld(true);
      }
      const rest = restPoseFromSkeleton(scene);
      assert.equal(rest.vrmVersion, c.turn ? "0" : "1");
      assert.equal(Object.keys(rest.boneMap).length, 54);
      const rig = new HandRig(rest, OPTIONS);
      const frames = clip("eat").frames;
      const { worst, worstAngle } = await compareWithVrm(THREE, {
        vrmFile: file(c.vrm), scene, rig, binding: rest.boneMap, frames,
      });
      if (c.roll) {
        // Control: the same rotations written as they are (no P^-1 q P B) put the bones far off,
        // so the comparison above can fail.
        const result = rig.solve(frameOf(frames[frames.length - 1]));
        for (const [bone, q] of Object.entries(result.bones)) {
          const node = rest.boneMap[bone] && scene.getObjectByName(rest.boneMap[bone]);
          if (node) node.quaternion.fromArray(q);
        }
        scene.updateMatrixWorld(true);
        const hand = scene.getObjectByName(rest.boneMap.rightHand).getWorldPosition(new THREE.Vector3());
        const want = result.worldPositions.rightHand;
        const off = Math.hypot(hand.x - want[0], hand.y - want[1], hand.z - want[2]);
        assert.ok(off > 0.01, `naive write: right hand only ${off} m off`);
      }
      rig.free();
      t.diagnostic(`largest distance ${(worst.d * 1000).toFixed(6)} mm (${worst.bone}, frame ${worst.frame}); result.bones vs the VRM's: ${worstAngle.toExponential(2)} deg`);
      assert.ok(worst.d < 1e-4, `${worst.bone} is ${worst.d} m from the VRM's on frame ${worst.frame}`);
      assert.ok(worstAngle < 0.05, `result.bones differ from the VRM's by ${worstAngle} deg`);
    });
  }

  it("applyToSkeleton takes rig.boneMap() of a fromGltf rig (file names, sanitized by three)", async () => {
    const scene = (await loadGltf(file("woman-mixamo.glb"))).scene;
    const rig = HandRig.fromGltf(readBytes(file("woman-mixamo.glb")), OPTIONS);
    const binding = rig.boneMap();
    const f = clip("eat").frames[40];
    const result = rig.solve(frameOf(f));
    assert.equal(applyToSkeleton(scene, result, binding), Object.keys(result.bones).length);
    scene.updateMatrixWorld(true);
    const p = new (await import("three")).Vector3();
    let worst = 0;
    for (const [bone, want] of Object.entries(result.worldPositions)) {
      if (!binding[bone]) continue;
      scene.getObjectByName(sanitizeNodeName(binding[bone])).getWorldPosition(p);
      worst = Math.max(worst, Math.hypot(p.x - want[0], p.y - want[1], p.z - want[2]));
    }
    rig.free();
    assert.ok(worst < 1e-5, `largest distance from result.worldPositions ${worst} m`);
  });

  it("restPoseFromSkeleton: no humanoid, missing nodes and duplicate bindings are Errors naming the bone", async () => {
    const THREE = await import("three");
    const empty = new THREE.Group();
    empty.add(new THREE.Object3D());
    assert.throws(() => restPoseFromSkeleton(empty), /restPoseFromSkeleton: no humanoid found/);
    const scene = (await loadGltf(file("man-unreal.glb"))).scene;
    assert.throws(() => restPoseFromSkeleton(scene, { hips: "pelvis", leftHand: "hand_x" }), /boneMap\.leftHand: no node named "hand_x"/);
    assert.throws(() => restPoseFromSkeleton(scene, { leftHand: "hand_l", rightHand: "hand_l" }), /duplicate binding: leftHand and rightHand are both bound to node "hand_l"/);
    assert.throws(() => restPoseFromSkeleton({}), /root must be a three\.js Object3D/);
  });
});
