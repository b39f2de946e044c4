// MotionRecorder (docs/guide/export.md): the shared ASL clips solved on the generated avatars (VRM 1.0
// and 0.x) and the robot, written with toVRMA() and read back the way a three-vrm app reads a
// .vrma (GLTFLoader + VRMAnimationLoaderPlugin, createVRMAnimationClip, an AnimationMixer
// sampled at every recorded time): every driven normalized bone must be within 0.5 degrees of
// handrig's result. The same recording plays on another avatar (the same normalized rotations,
// VRM 0.x turned as three-vrm-animation turns it); toBVH() read back by three's BVHLoader gives
// the same rotations and the avatar's offsets. The files pass the Khronos glTF validator.

import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";
import { before, describe, it } from "node:test";

import { HandRig, MotionRecorder } from "handrig";
import * as THREE from "three";
import { GLTFLoader } from "three/examples/jsm/loaders/GLTFLoader.js";
import { BVHLoader } from "three/examples/jsm/loaders/BVHLoader.js";
import { VRMAnimationLoaderPlugin, VRMLookAtQuaternionProxy, createVRMAnimationClip } from "@pixiv/three-vrm-animation";
import validator from "gltf-validator";

import { spawnSync } from "node:child_process";

import { codeBlocks, docPage } from "./readme-blocks.mjs";
import { CHILD_NODE_FLAGS, CHILD_TIMEOUT_MS, avatarFiles, avatars, loadVRM, readBytes, shared } from "./support.mjs";

const DEG = Math.PI / 180;
const LIMIT = 0.5 * DEG;

const aslDir = path.join(shared, "data", "asl");
const clips = fs
  .readdirSync(aslDir)
  .filter((f) => f.endsWith(".json"))
  .sort()
  .map((f) => ({ name: f, frames: JSON.parse(fs.readFileSync(path.join(aslDir, f), "utf8")).frames }));

const people = avatarFiles(".vrm").filter((f) => /-(vrm0|vrm1)\.vrm$/.test(f));
const targets = [...people.filter((f) => /(woman|child)-vrm[01]/.test(f)), avatars.robot];

/** Angle between two unit quaternions (q and -q alike). */
function angle(a, b) {
  const d = Math.abs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]);
  return 2 * Math.acos(Math.min(1, d));
}

/** A VRM 0.x model's rotation in VRM 1.0's convention (turned 180 degrees about Y), or as it is. */
const toVrm1 = (q, v) => (v === "0" ? [-q[0], q[1], -q[2], q[3]] : q.slice());

/** Solves a clip, recording it; returns the recorder and a copy of every frame's bones. */
function record(rig, frames, recorder = new MotionRecorder(rig)) {
  rig.reset();
  const result = {};
  const expected = [];
  for (const f of frames) {
    rig.solve({ timeMs: f.timeMs, hands: f.hands, pose: f.pose }, result);
    recorder.add(f.timeMs, result);
    expected.push({ timeMs: f.timeMs, bones: structuredClone(result.bones), hips: result.worldPositions.hips.slice() });
  }
  return { recorder, expected };
}

async function loadVRMA(bytes) {
  const loader = new GLTFLoader();
  loader.register((parser) => new VRMAnimationLoaderPlugin(parser));
  const copy = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
  const gltf = await loader.parseAsync(copy, "");
  const [animation] = gltf.userData.vrmAnimations ?? [];
  assert.ok(animation, "VRMAnimationLoaderPlugin found a VRM animation");
  return animation;
}

/**
 * Plays `bytes` on `vrm` with an AnimationMixer and calls `check(i, node(name))` at every
 * expected frame's time (seconds from the first frame).
 */
async function play(bytes, vrm, times, check) {
  const animation = await loadVRMA(bytes);
  // The look-at proxy three-vrm-animation's README has apps add (else it adds one, with a warning).
  if (vrm.lookAt && !vrm.scene.children.some((o) => o instanceof VRMLookAtQuaternionProxy)) {
    const proxy = new VRMLookAtQuaternionProxy(vrm.lookAt);
    proxy.name = "lookAtQuaternionProxy";
    vrm.scene.add(proxy);
  }
  const clip = createVRMAnimationClip(animation, vrm);
  assert.ok(clip.tracks.length > 0, "the clip has tracks");
  const mixer = new THREE.AnimationMixer(vrm.scene);
  const action = mixer.clipAction(clip);
  action.setLoop(THREE.LoopOnce, 1);
  action.clampWhenFinished = true;
  action.play();
  const node = (name) => vrm.humanoid.getNormalizedBoneNode(name);
  for (let i = 0; i < times.length; i++) {
    mixer.setTime((times[i] - times[0]) / 1000);
    check(i, node);
  }
  mixer.stopAllAction();
  mixer.uncacheRoot(vrm.scene);
  return clip;
}

describe("MotionRecorder.toVRMA: round trip through @pixiv/three-vrm-animation", () => {
  for (const file of [...people, avatars.robot]) {
    it(`${path.basename(file)}: every driven bone within 0.5 degrees at every frame of the ASL clips`, async () => {
      const vrm = await loadVRM(file);
      const rig = HandRig.fromVrm(readBytes(file), { torso: "pose" });
      const driven = rig.drivenBones();
      assert.ok(driven.length >= 40, `${driven.length} driven bones`);
      let worst = 0;
      let moved = 0;
      let frames = 0;
      for (const { name, frames: clipFrames } of clips) {
        const { recorder, expected } = record(rig, clipFrames);
        assert.equal(recorder.frameCount, clipFrames.length);
        assert.equal(recorder.duration, clipFrames.at(-1).timeMs - clipFrames[0].timeMs);
        const bytes = recorder.toVRMA();
        await play(
          bytes,
          vrm,
          expected.map((e) => e.timeMs),
          (i, node) => {
            for (const bone of driven) {
              const n = node(bone);
              assert.ok(n, `${name}: the avatar has ${bone}`);
              const want = expected[i].bones[bone];
              const a = angle(n.quaternion.toArray(), want);
              if (a > worst) worst = a;
              if (angle(want, [0, 0, 0, 1]) > 20 * DEG) moved++;
            }
          },
        );
        frames += expected.length;
      }
      rig.free();
      assert.ok(frames > 300, `${frames} frames`);
      assert.ok(moved > frames, `${moved} bone-frames turned more than 20 degrees: the clips move the avatar`);
      assert.ok(worst < LIMIT, `largest angle ${(worst / DEG).toFixed(4)} degrees`);
    });
  }

  it("plays on a different avatar: the same normalized rotations (VRM 0.x turned as three-vrm-animation turns it)", async () => {
    const source = people.find((f) => f.endsWith("man-vrm1.vrm") && !f.includes("woman"));
    const rig = HandRig.fromVrm(readBytes(source), { torso: "pose" });
    const { recorder, expected } = record(rig, clips[0].frames);
    const driven = rig.drivenBones();
    const bytes = recorder.toVRMA();
    rig.free();
    for (const file of targets) {
      const vrm = await loadVRM(file);
      const v = vrm.meta.metaVersion;
      let worst = 0;
      let compared = 0;
      await play(
        bytes,
        vrm,
        expected.map((e) => e.timeMs),
        (i, node) => {
          for (const bone of driven) {
            const n = node(bone);
            if (!n) continue; // a bone the target lacks
            // In the file: VRM 1.0's convention; on a 0.x avatar three-vrm-animation turns it back.
            const want = toVrm1(expected[i].bones[bone], v);
            worst = Math.max(worst, angle(n.quaternion.toArray(), want));
            compared++;
          }
        },
      );
      assert.ok(compared > 30 * expected.length, `${path.basename(file)}: ${compared} bone-frames compared`);
      assert.ok(worst < LIMIT, `${path.basename(file)}: largest angle ${(worst / DEG).toFixed(4)} degrees`);
    }
  });

  it("the file: a valid glTF 2.0 (Khronos validator), nodes at the avatar's rest pose in VRM 1.0's convention, LINEAR, seconds", async () => {
    for (const file of [people.find((f) => f.endsWith("woman-vrm0.vrm")), avatars.robot]) {
      const rig = HandRig.fromVrm(readBytes(file));
      const { recorder } = record(rig, clips[1].frames);
      const bytes = recorder.toVRMA();
      const report = await validator.validateBytes(bytes);
      assert.equal(report.issues.numErrors, 0, JSON.stringify(report.issues.messages.slice(0, 5)));
      assert.equal(report.issues.numWarnings, 0, JSON.stringify(report.issues.messages.slice(0, 5)));
      // The JSON chunk.
      const view = new DataView(bytes.buffer, bytes.byteOffset);
      const json = JSON.parse(Buffer.from(bytes.subarray(20, 20 + view.getUint32(12, true))).toString());
      const ext = json.extensions.VRMC_vrm_animation;
      assert.equal(ext.specVersion, "1.0");
      assert.deepEqual(json.extensionsUsed, ["VRMC_vrm_animation"]);
      const rest = rig.restWorldPositions();
      const sign = rig.vrmVersion === "0" ? -1 : 1;
      // World positions of the nodes (translations summed down the hierarchy) = rest, turned for 0.x.
      const parent = new Map();
      json.nodes.forEach((n, k) => (n.children ?? []).forEach((c) => parent.set(c, k)));
      const world = (k) => {
        const t = json.nodes[k].translation;
        const p = parent.has(k) ? world(parent.get(k)) : [0, 0, 0];
        return [p[0] + t[0], p[1] + t[1], p[2] + t[2]];
      };
      assert.deepEqual(Object.keys(ext.humanoid.humanBones).sort(), rig.boneNames().slice().sort());
      for (const [bone, { node }] of Object.entries(ext.humanoid.humanBones)) {
        assert.equal(json.nodes[node].rotation, undefined, `${bone}: no rest rotation`);
        const w = world(node);
        const r = rest[bone];
        const d = Math.hypot(w[0] - sign * r[0], w[1] - r[1], w[2] - sign * r[2]);
        assert.ok(d < 1e-6, `${bone}: node at ${w}, rest ${r} (${rig.vrmVersion})`);
      }
      const [anim] = json.animations;
      assert.equal(anim.channels.length, rig.drivenBones().length, "one rotation track per driven bone, no hips translation");
      for (const s of anim.samplers) assert.equal(s.interpolation, "LINEAR");
      const times = json.accessors[anim.samplers[0].input];
      assert.equal(times.min[0], 0);
      assert.ok(Math.abs(times.max[0] - recorder.duration / 1000) < 1e-6, `last key at ${times.max[0]} s`);
      rig.free();
    }
  });

  it("key reduction: a smaller file, every frame within the tolerance", async () => {
    const file = people.find((f) => f.endsWith("woman-vrm1.vrm"));
    const vrm = await loadVRM(file);
    const rig = HandRig.fromVrm(readBytes(file), { torso: "pose" });
    const driven = rig.drivenBones();
    const { recorder, expected } = record(rig, clips.find((c) => c.name === "please.json").frames);
    const full = recorder.toVRMA();
    const tolerance = 0.5 * DEG;
    const reduced = recorder.toVRMA({ tolerance });
    assert.ok(reduced.length < 0.8 * full.length, `${reduced.length} bytes, ${full.length} without reduction`);
    let worst = 0;
    await play(
      reduced,
      vrm,
      expected.map((e) => e.timeMs),
      (i, node) => {
        for (const bone of driven) worst = Math.max(worst, angle(node(bone).quaternion.toArray(), expected[i].bones[bone]));
      },
    );
    // float32 keys: a hair over the tolerance at most.
    assert.ok(worst < tolerance + 0.01 * DEG, `largest angle ${(worst / DEG).toFixed(4)} degrees`);
    assert.ok(worst > 0.05 * DEG, `largest angle ${(worst / DEG).toFixed(4)} degrees: keys were dropped`);
    rig.free();
  });

  it("a moved hips becomes a hips translation track (scaled by three-vrm-animation to the avatar's hips height)", async () => {
    for (const file of [people.find((f) => f.endsWith("child-vrm0.vrm")), people.find((f) => f.endsWith("child-vrm1.vrm"))]) {
      const vrm = await loadVRM(file);
      const rig = HandRig.fromVrm(readBytes(file));
      const recorder = new MotionRecorder(rig);
      const { expected } = record(rig, clips[0].frames, recorder);
      // The rig keeps the hips at rest (hips translation is not an input); move it here, in the model's frame.
      recorder.clear();
      const moved = expected.map((e, i) => ({ ...e, hips: [e.hips[0] + 0.002 * i, e.hips[1] - 0.001 * i, e.hips[2] + 0.003 * i] }));
      for (const e of moved) recorder.add(e.timeMs, { bones: e.bones, worldPositions: { hips: e.hips } });
      let worst = 0;
      const clip = await play(
        recorder.toVRMA(),
        vrm,
        moved.map((e) => e.timeMs),
        (i, node) => {
          const p = node("hips").position.toArray();
          worst = Math.max(worst, Math.hypot(p[0] - moved[i].hips[0], p[1] - moved[i].hips[1], p[2] - moved[i].hips[2]));
        },
      );
      assert.ok(clip.tracks.some((t) => t.name.endsWith(".position")), "a position track");
      assert.ok(worst < 1e-5, `${path.basename(file)}: hips ${worst} m from where it was recorded`);
      rig.free();
    }
  });
});

describe("MotionRecorder.toBVH: read back by three's BVHLoader", () => {
  for (const file of [people.find((f) => f.endsWith("man-vrm0.vrm")), people.find((f) => f.endsWith("woman-vrm1.vrm")), avatars.robot]) {
    it(`${path.basename(file)}: the same rotations within 0.5 degrees at every frame, the avatar's offsets`, () => {
      const rig = HandRig.fromVrm(readBytes(file), { torso: "pose" });
      const v = rig.vrmVersion;
      const sign = v === "0" ? -1 : 1;
      const rest = rig.restWorldPositions();
      const driven = rig.drivenBones();
      let worst = 0;
      let moved = 0;
      for (const { name, frames } of clips) {
        const { recorder, expected } = record(rig, frames);
        const { skeleton, clip } = new BVHLoader().parse(recorder.toBVH());
        const bones = new Map(skeleton.bones.map((b) => [b.name, b]));
        // The hierarchy: the avatar's bones, offsets in centimeters, the hips at the origin (its
        // position channels hold its place).
        for (const bone of rig.boneNames()) assert.ok(bones.has(bone), `${name}: ${bone} in the hierarchy`);
        for (const b of skeleton.bones) {
          if (b.name === "ENDSITE" || b.name === "hips") continue;
          const p = b.parent.name;
          const want = [0, 1, 2].map((c) => (rest[b.name][c] - rest[p][c]) * 100 * (c === 1 ? 1 : sign));
          const d = Math.hypot(b.position.x - want[0], b.position.y - want[1], b.position.z - want[2]);
          assert.ok(d < 1e-3, `${b.name}: offset ${b.position.toArray()} cm, expected ${want}`);
        }
        const track = (n, kind) => clip.tracks.find((t) => t.name === `${n}.${kind}`);
        const hips = track("hips", "position");
        assert.equal(hips.times.length, expected.length, `${name}: one BVH frame per recorded frame (uniform 30 fps)`);
        for (let i = 0; i < expected.length; i++) {
          const dh = Math.hypot(hips.values[3 * i] - sign * rest.hips[0] * 100, hips.values[3 * i + 1] - rest.hips[1] * 100, hips.values[3 * i + 2] - sign * rest.hips[2] * 100);
          assert.ok(dh < 1e-3, `${name} frame ${i}: hips at ${hips.values.slice(3 * i, 3 * i + 3)} cm`);
          assert.ok(Math.abs(hips.times[i] - (expected[i].timeMs - expected[0].timeMs) / 1000) < 1e-3, `${name} frame ${i}: time`);
          for (const bone of driven) {
            const t = track(bone, "quaternion");
            const got = Array.from(t.values.subarray(4 * i, 4 * i + 4));
            const want = toVrm1(expected[i].bones[bone], v);
            worst = Math.max(worst, angle(got, want));
            if (angle(want, [0, 0, 0, 1]) > 20 * DEG) moved++;
          }
        }
      }
      rig.free();
      assert.ok(moved > 1000, `${moved} bone-frames turned more than 20 degrees`);
      assert.ok(worst < LIMIT, `largest angle ${(worst / DEG).toFixed(4)} degrees`);
    });
  }

  it("Euler angles stay continuous and follow the documented order Rz * Rx * Ry (degrees)", () => {
    const rig = HandRig.fromVrm(readBytes(avatars.robot));
    const recorder = new MotionRecorder(rig);
    // One bone turning steadily past 180 degrees about Y, then about a tilted axis: the written
    // angles must not jump by a whole turn between frames.
    const bone = rig.drivenBones().find((b) => b === "rightLowerArm");
    const identity = Object.fromEntries(rig.drivenBones().map((b) => [b, [0, 0, 0, 1]]));
    const axis = new THREE.Vector3(0.3, 1, 0.2).normalize();
    const quats = [];
    for (let i = 0; i <= 90; i++) {
      const q = new THREE.Quaternion().setFromAxisAngle(axis, i * 4 * DEG).toArray();
      quats.push(q);
      recorder.add(i * 10, { bones: { ...identity, [bone]: q } });
    }
    const text = recorder.toBVH();
    assert.match(text, /ROOT hips\n\{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation/);
    assert.match(text, /JOINT rightLowerArm\n\s*\{\n\s*OFFSET [^\n]+\n\s*CHANNELS 3 Zrotation Xrotation Yrotation/);
    assert.match(text, /Frames: 91\nFrame Time: 0\.010000\n/);
    // The column of the bone: joints in hierarchy order, the hips with 6 channels.
    const joints = [...text.matchAll(/(?:ROOT|JOINT) (\w+)/g)].map((m) => m[1]);
    const col = 6 + 3 * (joints.indexOf(bone) - 1);
    const rows = text.split("Frame Time: 0.010000\n")[1].trim().split("\n").map((l) => l.split(" ").map(Number));
    let jump = 0;
    rows.forEach((row, i) => {
      const [z, x, y] = row.slice(col, col + 3);
      const q = new THREE.Quaternion().setFromEuler(new THREE.Euler(x * DEG, y * DEG, z * DEG, "ZXY")).toArray();
      assert.ok(angle(q, quats[i]) < 1e-4, `frame ${i}: Rz * Rx * Ry of (${z}, ${x}, ${y}) degrees`);
      if (i > 0) jump = Math.max(jump, ...[0, 1, 2].map((c) => Math.abs(row[col + c] - rows[i - 1][col + c])));
    });
    assert.ok(jump < 10, `largest change between frames ${jump} degrees (4 degrees of turn a frame)`);
    rig.free();
  });
});

describe("MotionRecorder: input and state", () => {
  let rig;
  before(() => {
    rig = HandRig.fromVrm(readBytes(avatars.robot));
  });

  it("copies the result: a reused result object does not change what was recorded", () => {
    const recorder = new MotionRecorder(rig);
    const frames = clips[0].frames;
    const result = {};
    rig.reset();
    rig.solve({ timeMs: frames[30].timeMs, hands: frames[30].hands, pose: frames[30].pose }, result);
    recorder.add(0, result);
    const first = recorder.toBVH();
    rig.solve({ timeMs: frames[60].timeMs, hands: frames[60].hands, pose: frames[60].pose }, result);
    assert.equal(recorder.toBVH(), first);
    recorder.add(100, result);
    assert.notEqual(recorder.toBVH(), first);
  });

  it("rejects bad input naming the field, and keeps what it had", () => {
    const recorder = new MotionRecorder(rig);
    assert.throws(() => new MotionRecorder({}), /^TypeError: rig: must be a HandRig/);
    assert.throws(() => recorder.toVRMA(), /toVRMA: no frames recorded/);
    assert.throws(() => recorder.toBVH(), /toBVH: no frames recorded/);
    const r = rig.solve({ timeMs: 0 }, {});
    recorder.add(10, r);
    assert.throws(() => recorder.add(5, r), /timeMs: 5 goes back in time/);
    assert.throws(() => recorder.add(NaN, r), /timeMs: must be a finite number/);
    assert.throws(() => recorder.add(20, null), /result: must be a HandRig.solve\(\) result/);
    const bad = structuredClone(r);
    bad.bones.rightHand = [0, 0, NaN, 1];
    assert.throws(() => recorder.add(20, bad), /result\.bones\.rightHand\[2\]: must be a finite number/);
    delete bad.bones.rightHand;
    assert.throws(() => recorder.add(20, bad), /result\.bones\.rightHand: must be a quaternion/);
    assert.equal(recorder.frameCount, 1);
    recorder.add(10, r); // the same time replaces the last frame
    assert.equal(recorder.frameCount, 1);
    recorder.add(40, r);
    assert.equal(recorder.frameCount, 2);
    assert.equal(recorder.duration, 30);
    assert.throws(() => recorder.toVRMA({ tolerance: -1 }), /options\.tolerance must be an angle in radians/);
    assert.throws(() => recorder.toVRMA({ tolerence: 0.01 }), /toVRMA: unknown option "tolerence"/);
    assert.throws(() => recorder.toBVH({ unit: "mm" }), /options\.unit must be "cm" or "m"/);
    recorder.clear();
    assert.equal(recorder.frameCount, 0);
    assert.equal(recorder.duration, 0);
  });

  it("keeps working after the rig is freed, and grows past its first storage", () => {
    const other = HandRig.fromVrm(readBytes(avatars.robot));
    const recorder = new MotionRecorder(other);
    const r = other.solve({ timeMs: 0 }, {});
    other.free();
    for (let i = 0; i < 1000; i++) recorder.add(i * 33, r);
    assert.equal(recorder.frameCount, 1000);
    assert.ok(recorder.toVRMA().length > 1000 * 4 * 40);
  });
});

describe("docs/guide/export.md: a recording in Node", () => {
  it("runs as written: thanks.vrma plays through three-vrm-animation, thanks.bvh has every frame", async () => {
    const [block] = codeBlocks(docPage("guide/export.md"), "### A recording in Node");
    assert.ok(block, "the block");
    // Inside the consumer project, so that "handrig" resolves to the installed package.
    const dir = fs.mkdtempSync(path.join(process.cwd(), "export-doc-"));
    try {
      const avatar = people.find((f) => f.endsWith("woman-vrm1.vrm"));
      fs.copyFileSync(avatar, path.join(dir, "avatar.vrm"));
      fs.copyFileSync(path.join(aslDir, "thanks.json"), path.join(dir, "thanks.json"));
      fs.writeFileSync(path.join(dir, "record.mjs"), block);
      const run = spawnSync(process.execPath, [...CHILD_NODE_FLAGS, "record.mjs"], { cwd: dir, encoding: "utf8", timeout: CHILD_TIMEOUT_MS });
      assert.equal(run.status, 0, run.stderr);
      const frames = clips.find((c) => c.name === "thanks.json").frames;
      assert.equal(run.stdout.trim(), `${frames.length} frames, ${frames.at(-1).timeMs - frames[0].timeMs} ms`);
      const vrm = await loadVRM(avatar);
      let moved = 0;
      const clip = await play(
        new Uint8Array(fs.readFileSync(path.join(dir, "thanks.vrma"))),
        vrm,
        frames.map((f) => f.timeMs),
        (i, node) => {
          if (angle(node("rightLowerArm").quaternion.toArray(), [0, 0, 0, 1]) > 20 * DEG) moved++;
        },
      );
      assert.ok(clip.tracks.length >= 40, `${clip.tracks.length} tracks`);
      assert.ok(moved > frames.length / 2, `the right elbow bent in ${moved} frames`);
      const bvh = new BVHLoader().parse(fs.readFileSync(path.join(dir, "thanks.bvh"), "utf8"));
      assert.equal(bvh.clip.tracks[0].times.length, frames.length);
    } finally {
      fs.rmSync(dir, { recursive: true, force: true });
    }
  });
});

describe("docs/guide/export.md: the playback block", () => {
  it("plays a handrig .vrma with no three-vrm-animation warning (the look-at proxy); without the proxy the warning is the app's, not the file's", async () => {
    const [block] = codeBlocks(docPage("guide/export.md"), "### What the `.vrma` holds");
    assert.ok(block?.includes("createVRMAnimationClip"), "the playback block");
    const avatar = people.find((f) => f.endsWith("woman-vrm1.vrm"));
    const rig = HandRig.fromVrm(readBytes(avatar));
    const { recorder } = record(rig, clips.find((c) => c.name === "thanks.json").frames);
    rig.free();
    const bytes = recorder.toVRMA();
    // The block as written, its imports given and the file parsed instead of fetched.
    const body = block
      .replace(/^import .*$/gm, "")
      .replace('loader.loadAsync("thanks.vrma")', 'loader.parseAsync(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength), "")')
      .concat("\nreturn { clip, mixer };");
    const AsyncFunction = (async () => {}).constructor;
    const runBlock = new AsyncFunction("THREE", "GLTFLoader", "VRMAnimationLoaderPlugin", "VRMLookAtQuaternionProxy", "createVRMAnimationClip", "vrm", "bytes", body);
    const [vrm, bare] = [await loadVRM(avatar), await loadVRM(avatar)];
    const warnings = [];
    const warn = console.warn;
    console.warn = (...a) => warnings.push(a.join(" "));
    try {
      assert.ok(vrm.lookAt, "the avatar has a look-at (what the warning is about)");
      const { clip, mixer } = await runBlock(THREE, GLTFLoader, VRMAnimationLoaderPlugin, VRMLookAtQuaternionProxy, createVRMAnimationClip, vrm, bytes);
      mixer.update(0.5);
      assert.ok(clip.tracks.length >= 30, `${clip.tracks.length} tracks`);
      assert.deepEqual(warnings, []);
      // The file has no look-at or expressions; the warning comes from a scene without the proxy.
      const animation = await loadVRMA(bytes);
      assert.equal(animation.lookAtTrack, null);
      assert.equal(animation.expressionTracks.preset.size + animation.expressionTracks.custom.size, 0);
      createVRMAnimationClip(animation, bare);
      assert.equal(warnings.length, 1, warnings.join("\n"));
      assert.match(warnings[0], /VRMLookAtQuaternionProxy is not found/);
    } finally {
      console.warn = warn;
    }
  });
});
