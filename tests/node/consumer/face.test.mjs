// The face (issue 50) through the package: a FaceLandmarkerResult spread into the frame gives
// result.face / .expressions / .arkit / .lookAt and turns the head; legacy 468-point landmarks
// (no blendshapes) blink; applyToVRM drives real three-vrm objects (a VRMExpressionManager with
// the 52 ARKit expressions under prefixed names, perfect sync; one with presets only; the
// VRMLookAt); handrig/three sets plain morph targets by name; the usual mistakes are named.

import assert from "node:assert/strict";
import { describe, it } from "node:test";

import { HandRig, LAYOUT, MotionRecorder } from "handrig";
import { applyFaceToMorphTargets } from "handrig/three";
import { applyToVRM, restPoseFromVRM } from "handrig/three-vrm";
import { avatarFiles, avatars, loadVRM, readBytes, throwsWith } from "./support.mjs";

const robot = readBytes(avatars.robot);

const ARKIT = LAYOUT.arkit;

/** A FaceLandmarkerResult: blendshapes by name (others 0), a matrix turning the head by `yaw` radians. */
function faceResult(weights = {}, yaw = 0, landmarks = null) {
  const categories = [{ index: 0, score: 0.1, categoryName: "_neutral", displayName: "" }];
  ARKIT.slice(0, 51).forEach((name, i) => categories.push({ index: i + 1, score: weights[name] ?? 0, categoryName: name, displayName: "" }));
  const c = Math.cos(yaw);
  const s = Math.sin(yaw);
  // Column-major rotation about y, translated 40 cm in front of the camera.
  const data = [c, 0, -s, 0, 0, 1, 0, 0, s, 0, c, 0, 1, -2, -40, 1];
  return {
    faceLandmarks: [landmarks ?? meshPoints(0.3)],
    faceBlendshapes: [{ categories, headIndex: -1, headName: "" }],
    facialTransformationMatrixes: [{ rows: 4, columns: 4, data }],
  };
}

/** 478 landmarks of a flat face whose eyes measure `ear` (opening over width). */
function meshPoints(ear, count = 478) {
  const pts = Array.from({ length: count }, () => ({ x: 0.5, y: 0.5, z: 0 }));
  const eye = ([outer, up1, up2, inner, low1, low2], cx) => {
    pts[outer] = { x: cx - 0.03, y: 0.45, z: 0 };
    pts[inner] = { x: cx + 0.03, y: 0.45, z: 0 };
    for (const [u, l, dx] of [[up1, low2, -0.01], [up2, low1, 0.01]]) {
      pts[u] = { x: cx + dx, y: 0.45 - ear * 0.03, z: 0 };
      pts[l] = { x: cx + dx, y: 0.45 + ear * 0.03, z: 0 };
    }
  };
  eye([33, 160, 158, 133, 153, 144], 0.42);
  eye([263, 387, 385, 362, 380, 373], 0.58);
  Object.assign(pts[13], { x: 0.5, y: 0.6 });
  Object.assign(pts[14], { x: 0.5, y: 0.6 });
  pts[61] = { x: 0.46, y: 0.6, z: 0 };
  pts[291] = { x: 0.54, y: 0.6, z: 0 };
  pts[10] = { x: 0.5, y: 0.3, z: 0 };
  pts[152] = { x: 0.5, y: 0.75, z: 0 };
  pts[234] = { x: 0.39, y: 0.5, z: 0 };
  pts[454] = { x: 0.61, y: 0.5, z: 0 };
  return pts;
}

/** three-vrm VRMExpressions registered on the VRM's manager under `names`. */
async function withExpressions(vrm, names) {
  const { VRMExpression, VRMExpressionManager } = await import("@pixiv/three-vrm");
  const manager = new VRMExpressionManager();
  // The generated avatars carry their own expressions (issue 50): replaced by these, also in the
  // scene where an AnimationMixer looks them up by name.
  for (const e of vrm.expressionManager?.expressions ?? []) e.removeFromParent();
  for (const name of names) {
    const expression = new VRMExpression(name);
    manager.registerExpression(expression);
    vrm.scene.add(expression); // where an AnimationMixer finds it, as VRMLoaderPlugin puts them
  }
  vrm.expressionManager = manager;
  return manager;
}

const vrm1 = () => avatarFiles(".vrm").find((f) => f.endsWith("woman-vrm1.vrm"));

describe("the face", () => {
  it("a FaceLandmarker result spread into the frame: presets, ARKit weights, look-at, the head", async () => {
    const vrm = await loadVRM(vrm1());
    const rig = new HandRig(restPoseFromVRM(vrm), { face: { smoothing: false, calibrationTime: 0 } });
    const none = rig.solve({ timeMs: 0 });
    assert.equal(none.face, null);
    assert.equal(none.bones.head, undefined, "no face: the head is not driven");
    rig.solve({ timeMs: 10, ...faceResult() });
    const r = rig.solve({ timeMs: 43, ...faceResult({ jawOpen: 0.6, eyeBlinkLeft: 0.95, eyeLookOutLeft: 0.5, eyeLookInRight: 0.5 }, 0.3) });
    assert.equal(r.face, "tracked");
    assert.ok(r.expressions.aa > 0.3, `aa ${r.expressions.aa}`);
    assert.ok(r.expressions.blinkLeft > 0.9 && r.expressions.blinkRight === 0, JSON.stringify(r.expressions));
    assert.ok(r.lookAt.yaw > 5, `yaw ${r.lookAt.yaw}: toward the avatar's left`);
    assert.ok(Math.abs(r.arkit[ARKIT.indexOf("jawOpen")] - 0.6) < 1e-6);
    assert.ok(Array.isArray(r.bones.head) && Array.isArray(r.bones.neck), "the face turns the neck and head");
    const sum = ["aa", "ih", "ou", "ee", "oh"].reduce((a, n) => a + r.expressions[n], 0);
    assert.ok(sum <= 1 + 1e-6);
    // Lost: held, then eased out, then gone (head no longer in bones).
    assert.equal(rig.solve({ timeMs: 100 }).face, "lost");
    const gone = rig.solve({ timeMs: 2000 });
    assert.equal(gone.face, null);
    assert.equal(gone.bones.head, undefined);
  });

  it("perfect sync: 52 ARKit expressions with a prefix each get their weight within 0.05 (smoothing off)", async () => {
    const vrm = await loadVRM(vrm1());
    const manager = await withExpressions(vrm, ARKIT.map((n) => `BlendShape.${n[0].toUpperCase()}${n.slice(1)}`));
    const rig = new HandRig(restPoseFromVRM(vrm), { face: { smoothing: false } });
    const weights = Object.fromEntries(ARKIT.slice(0, 51).map((n, i) => [n, ((i * 0.37) % 1) * 0.9]));
    rig.solve({ timeMs: 0, ...faceResult(weights) });
    applyToVRM(vrm, rig.solve({ timeMs: 33, ...faceResult(weights) }));
    for (const n of ARKIT.slice(0, 51)) {
      const got = manager.getValue(`BlendShape.${n[0].toUpperCase()}${n.slice(1)}`);
      assert.ok(Math.abs(got - weights[n]) <= 0.05, `${n}: ${got} vs ${weights[n]}`);
    }
  });

  it("presets only: the presets move, three-vrm's look-at takes yaw and pitch, and a mirrored image swaps sides", async () => {
    const vrm = await loadVRM(vrm1());
    const manager = await withExpressions(vrm, ["aa", "ih", "ou", "ee", "oh", "blink", "blinkLeft", "blinkRight", "happy", "angry", "sad", "relaxed", "surprised"]);
    const rig = new HandRig(restPoseFromVRM(vrm), { inputMirrored: true, face: { calibrationTime: 0 } });
    for (let t = 0; t < 10; t++) rig.solve({ timeMs: t * 33, ...faceResult() });
    const r = rig.solve({ timeMs: 330, ...faceResult({ jawOpen: 0.7, eyeBlinkLeft: 0.95, eyeLookDownLeft: 0.4, eyeLookDownRight: 0.4 }) });
    applyToVRM(vrm, r);
    assert.ok(manager.getValue("aa") > 0.3, `aa ${manager.getValue("aa")}`);
    // A mirrored (selfie) image: MediaPipe's Left is the left of the face it sees, the user's right eye, the avatar's right.
    assert.ok(manager.getValue("blinkRight") > 0.5 && manager.getValue("blinkLeft") === 0, `blinkRight ${manager.getValue("blinkRight")}`);
    if (vrm.lookAt) {
      assert.equal(vrm.lookAt.pitch, r.lookAt.pitch);
      assert.ok(r.lookAt.pitch > 0, "looking down: three-vrm's pitch > 0");
      vrm.update(1 / 30);
    }
    // The flat output path does the same.
    applyToVRM(vrm, rig.output);
    assert.ok(manager.getValue("aa") > 0.3);
  });

  it("MotionRecorder: a .vrma with expressions and look-at, played by @pixiv/three-vrm-animation, reproduces them within 0.01", async () => {
    const THREE = await import("three");
    const { GLTFLoader } = await import("three/examples/jsm/loaders/GLTFLoader.js");
    const { VRMAnimationLoaderPlugin, VRMLookAtQuaternionProxy, createVRMAnimationClip } = await import("@pixiv/three-vrm-animation");
    const vrm = await loadVRM(vrm1());
    const names = ["aa", "ih", "ou", "ee", "oh", "blink", "blinkLeft", "blinkRight", "happy", "angry", "sad", "relaxed", "surprised"];
    const manager = await withExpressions(vrm, names);
    const rig = new HandRig(restPoseFromVRM(vrm), { face: { calibrationTime: 0 } });
    const recorder = new MotionRecorder(rig);
    const expected = [];
    for (let k = 0; k < 30; k++) {
      const t = k * 33;
      const w = { jawOpen: 0.5 + 0.4 * Math.sin(k / 3), eyeBlinkLeft: k % 10 < 2 ? 0.95 : 0, mouthSmileLeft: 0.5, mouthSmileRight: 0.5, eyeLookOutLeft: 0.15 * (1 + Math.sin(k / 5)), eyeLookInRight: 0.15 * (1 + Math.sin(k / 5)), eyeLookDownLeft: 0.2, eyeLookDownRight: 0.2 };
      const r = rig.solve({ timeMs: t, ...faceResult(w) });
      recorder.add(t, r);
      expected.push({ t, expressions: { ...r.expressions }, yaw: r.lookAt.yaw, pitch: r.lookAt.pitch });
    }
    assert.ok(expected.some((e) => e.expressions.aa > 0.3) && expected.some((e) => Math.abs(e.yaw) > 2));
    const bytes = recorder.toVRMA();
    const loader = new GLTFLoader();
    loader.register((parser) => new VRMAnimationLoaderPlugin(parser));
    const gltf = await loader.parseAsync(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength), "");
    const [animation] = gltf.userData.vrmAnimations;
    assert.equal(animation.expressionTracks.preset.size, names.length);
    assert.ok(animation.lookAtTrack, "the look-at track");
    assert.ok(vrm.lookAt, "the avatar has a look-at");
    const proxy = new VRMLookAtQuaternionProxy(vrm.lookAt);
    proxy.name = "lookAtQuaternionProxy";
    vrm.scene.add(proxy);
    const mixer = new THREE.AnimationMixer(vrm.scene);
    const action = mixer.clipAction(createVRMAnimationClip(animation, vrm));
    action.setLoop(THREE.LoopOnce, 1);
    action.clampWhenFinished = true;
    action.play();
    for (const e of expected) {
      mixer.setTime(e.t / 1000);
      for (const n of names) assert.ok(Math.abs(manager.getValue(n) - e.expressions[n]) <= 0.01, `${n} at ${e.t} ms: ${manager.getValue(n)} vs ${e.expressions[n]}`);
      assert.ok(Math.abs(vrm.lookAt.yaw - e.yaw) <= 0.01, `yaw at ${e.t} ms: ${vrm.lookAt.yaw} vs ${e.yaw}`);
      assert.ok(Math.abs(vrm.lookAt.pitch - e.pitch) <= 0.01, `pitch at ${e.t} ms: ${vrm.lookAt.pitch} vs ${e.pitch}`);
    }
    // A recording without a face writes none (the file as before).
    const plain = new MotionRecorder(rig);
    plain.add(0, rig.solve({ timeMs: 5000 }));
    const json = new TextDecoder().decode(plain.toVRMA()).match(/\{"asset".*\}/)?.[0] ?? "";
    assert.ok(!json.includes("expressions") && !json.includes("lookAt"));
  });

  it("landmarks beside blendshapes: the results are those without them; checked in a rig's first frames only", () => {
    const withMesh = HandRig.fromVrm(robot, { face: { calibrationTime: 0.2 } });
    const without = HandRig.fromVrm(robot, { face: { calibrationTime: 0.2 } });
    for (let t = 0; t < 12; t++) {
      // Eyes that the landmark fallback would read as open, then closed.
      const face = faceResult({ jawOpen: t / 12, eyeBlinkRight: t > 8 ? 0.9 : 0 }, 0.1 * t, meshPoints(t > 6 ? 0.05 : 0.3));
      const a = withMesh.solve({ timeMs: t * 33, ...face }, {});
      const { faceLandmarks, ...rest } = face;
      assert.equal(faceLandmarks.length, 1);
      const b = without.solve({ timeMs: t * 33, ...rest }, {});
      assert.deepEqual(a, b, `frame ${t}`);
    }
    const pixels = meshPoints(0.3).map((p) => ({ x: p.x * 640, y: p.y * 480, z: p.z }));
    const rig = HandRig.fromVrm(robot);
    throwsWith(() => rig.solve({ timeMs: 0, ...faceResult(), faceLandmarks: [pixels] }), /^frame\.faceLandmarks\[0\]\[33\]: x and y must be normalized/);
    for (let t = 0; t < 3; t++) rig.solve({ timeMs: t * 33, ...faceResult() });
    // Past the first frames, landmarks beside blendshapes are not read (the rig would not use them).
    assert.equal(rig.solve({ timeMs: 100, ...faceResult(), faceLandmarks: [pixels] }).face, "tracked");
    // Without blendshapes they are read and checked in every frame.
    throwsWith(() => rig.solve({ timeMs: 133, faceLandmarks: [pixels] }), /^frame\.faceLandmarks\[0\]\[33\]: x and y must be normalized/);
  });

  it("legacy 468 landmarks without blendshapes: a closed eye blinks", () => {
    const rig = HandRig.fromVrm(robot, { face: { calibrationTime: 0.2 } });
    let r;
    for (let t = 0; t < 8; t++) r = rig.solve({ timeMs: t * 33, faceLandmarks: meshPoints(0.3, 468) });
    assert.equal(r.expressions.blink, 0);
    r = rig.solve({ timeMs: 300, faceLandmarks: meshPoints(0.05, 468) });
    assert.ok(r.expressions.blink > 0.5, `blink ${r.expressions.blink}`);
  });

  it("handrig/three: plain morph targets by name (VRM 0.x and VRChat names)", async () => {
    const THREE = await import("three");
    const geometry = new THREE.BufferGeometry();
    const mesh = new THREE.Mesh(geometry);
    mesh.morphTargetDictionary = { "vrc.v_aa": 0, Blink_L: 1, Blink_R: 2, Joy: 3 };
    mesh.morphTargetInfluences = [0, 0, 0, 0];
    const root = new THREE.Group();
    root.add(mesh);
    const rig = HandRig.fromVrm(robot, { face: { calibrationTime: 0, smoothing: false } });
    rig.solve({ timeMs: 0, ...faceResult() });
    const r = rig.solve({ timeMs: 33, ...faceResult({ jawOpen: 0.7, eyeBlinkLeft: 0.95, mouthSmileLeft: 0.8, mouthSmileRight: 0.8 }) });
    assert.equal(applyFaceToMorphTargets(root, r), 1);
    const [aa, bl, br, joy] = mesh.morphTargetInfluences;
    assert.ok(aa > 0.3 && bl > 0.9 && br === 0 && joy > 0.5, JSON.stringify(mesh.morphTargetInfluences));
  });

  it("names the usual mistakes", () => {
    const rig = HandRig.fromVrm(robot);
    const face = faceResult();
    throwsWith(() => rig.solve({ timeMs: 0, face }), /^frame\.face: holds a FaceLandmarker result: spread it into the frame/);
    throwsWith(() => rig.solve({ timeMs: 0, faceResult: face }), /^frame\.faceResult: unknown field holding an object.*FaceLandmarker result is spread too/);
    const short = { ...face, facialTransformationMatrixes: [{ rows: 4, columns: 4, data: face.facialTransformationMatrixes[0].data.slice(0, 12) }] };
    throwsWith(() => rig.solve({ timeMs: 0, ...short }), "frame.facialTransformationMatrixes[0].data: must have 16 numbers (a 4x4 matrix, column-major), got 12");
    const d = face.facialTransformationMatrixes[0].data;
    const rowMajor = [0, 1, 2, 3].flatMap((r) => [0, 1, 2, 3].map((c) => d[c * 4 + r]));
    throwsWith(() => rig.solve({ timeMs: 0, ...face, facialTransformationMatrixes: [{ rows: 4, columns: 4, data: rowMajor }] }), /facialTransformationMatrixes\[0\]\.data: .*column-major/);
    const pixels = meshPoints(0.3).map((p) => ({ x: p.x * 640, y: p.y * 480, z: p.z }));
    throwsWith(() => rig.solve({ timeMs: 0, faceLandmarks: [pixels] }), /^frame\.faceLandmarks\[0\]\[33\]: x and y must be normalized image coordinates/);
    throwsWith(() => rig.solve({ timeMs: 0, faceLandmarks: [meshPoints(0.3).slice(0, 400)] }), "frame.faceLandmarks[0]: must have 468 or 478 landmarks (MediaPipe's face mesh), got 400");
    const bad = faceResult({ jawOpen: 0.5 });
    bad.faceBlendshapes[0].categories[1].categoryName = "mouthOpen";
    throwsWith(() => rig.solve({ timeMs: 0, ...bad }), /^frame\.faceBlendshapes\[0\]\.categories\[1\]\.categoryName: "mouthOpen" is not an ARKit blendshape name/);
    // The rig is still usable.
    assert.equal(rig.solve({ timeMs: 33, ...faceResult() }).face, "tracked");
  });
});
