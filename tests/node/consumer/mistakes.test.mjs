// Issue 15: a new user's mistakes, each with the message they should get (or the documented
// behaviour). Every case here was accepted silently, or answered misleadingly, before.

import assert from "node:assert/strict";
import { describe, it } from "node:test";

import { HandRig, LAYOUT } from "handrig";
import { applyToVRM } from "handrig/three-vrm";
import { avatars, editedRobot, holisticResult, isIdentity, landmark, loadVRM, readBytes, readRecording, throwsWith } from "./support.mjs";

const robotBytes = readBytes(avatars.robot);
const frames = readRecording();
const hand = frames[10].hands[0];

/** The angle (radians) between two rotations [x, y, z, w]. */
function angle(a, b) {
  const d = Math.abs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]);
  return 2 * Math.acos(Math.min(1, d));
}

describe("options: dotted paths, and every error names the field", () => {
  it("the paths optionDescriptions() returns are accepted, and take effect", () => {
    const nested = HandRig.fromVrm(robotBytes, { alignment: { weight: 0.25 }, mirror: true });
    const dotted = HandRig.fromVrm(robotBytes, { "alignment.weight": 0.25, mirror: true });
    const frame = { ...frames[100], wrists: { left: { position: [0.4, 1.3, 0.2] } } };
    const a = nested.solve(frame, {});
    const b = dotted.solve(frame, {});
    assert.deepEqual(b.ikTargets, a.ikTargets);
    const plain = HandRig.fromVrm(robotBytes, { mirror: true }).solve(frame, {});
    assert.notDeepEqual(b.ikTargets.left.position, plain.ikTargets.left.position, "the weight took effect");
    for (const d of HandRig.optionDescriptions()) {
      if (d.default === null) continue;
      HandRig.fromVrm(robotBytes, { [d.path]: d.default }).free();
    }
  });

  it("number options: the described numbers are short decimals, and both ends of each range are accepted", () => {
    const described = new Map(HandRig.optionDescriptions().map((d) => [d.path, d]));
    // Rust holds these as f32: the description gives the decimal, not the f32 widened.
    assert.equal(described.get("filter.minCutoff").min, 0.05);
    assert.equal(described.get("calibration.bodyScale").min, 0.1);
    assert.equal(described.get("arm.shoulderAngle").default, 0.26);
    assert.equal(described.get("arm.shoulderAngle").max, 1.5707964); // pi / 2 as an f32
    assert.equal(described.get("contact.depthTrust").default, 0.1);
    let checked = 0;
    for (const d of described.values()) {
      if (d.type !== "number") continue;
      for (const x of [d.min, d.max, d.default, d.step]) {
        if (x === null) continue;
        assert.ok(String(x).replace(/^-|\.|e.*$/g, "").replace(/^0+/, "").length <= 9, `${d.path}: ${x}`);
      }
      for (const end of [d.min, d.max]) HandRig.fromVrm(robotBytes, { [d.path]: end }).free();
      // Just outside either end: rejected, the message giving the range as described.
      const below = d.min - Math.max(1e-6, Math.abs(d.min) * 1e-4);
      const above = d.max + Math.max(1e-6, Math.abs(d.max) * 1e-4);
      for (const out of [below, above]) {
        assert.throws(() => HandRig.fromVrm(robotBytes, { [d.path]: out }), (e) => {
          assert.match(e.message, new RegExp(`^options\\.${d.path.replace(/\./g, "\\.")}: must be`));
          if (Number.isInteger(out) || !/integer/.test(e.message)) assert.ok(e.message.includes(`${d.min}..${d.max}`), e.message);
          return true;
        });
      }
      checked++;
    }
    assert.ok(checked >= 15, `${checked} number options`);
  });

  it("a group with an `enabled` switch takes a boolean: filter: false", () => {
    const frame = frames[200];
    const off = HandRig.fromVrm(robotBytes, { filter: false, dropout: false });
    const nested = HandRig.fromVrm(robotBytes, { filter: { enabled: false }, "dropout.enabled": false });
    const on = HandRig.fromVrm(robotBytes);
    for (const f of frames.slice(190, 200)) [off, nested, on].forEach((r) => r.solve(f));
    const a = off.solve(frame, {});
    assert.deepEqual(nested.solve(frame, {}).bones, a.bones);
    assert.notDeepEqual(on.solve(frame, {}).bones, a.bones, "filtering is on by default");
  });

  it("a string for a boolean names the field once, with no 'Error:' inside", () => {
    throwsWith(() => HandRig.fromVrm(robotBytes, { mirror: "true" }), 'options.mirror: must be true or false, got string "true"');
  });

  it("an unknown dotted path, a value for a group, and the same option twice", () => {
    throwsWith(() => HandRig.fromVrm(robotBytes, { "alignment.wieght": 1 }), "options.alignment.wieght: unknown option (did you mean alignment.weight?)");
    // Names from MediaPipe and other rigs, and other spellings, get a pointer; far ones do not.
    throwsWith(() => HandRig.fromVrm(robotBytes, { selfieMode: true }), "options.selfieMode: unknown option (did you mean inputMirrored?)");
    throwsWith(() => HandRig.fromVrm(robotBytes, { mirrored: true }), "options.mirrored: unknown option (did you mean mirror?)");
    throwsWith(() => HandRig.fromVrm(robotBytes, { filter: { minCutOff: 1 } }), "options.filter.minCutOff: unknown option (did you mean filter.minCutoff?)");
    throwsWith(() => HandRig.fromVrm(robotBytes, { smoothing: 1 }), "options.smoothing: unknown option");
    // No target given as null: the rig's own result, as with none.
    const rig = HandRig.fromVrm(robotBytes);
    assert.equal(rig.solve(frames[100], null), rig.solve(frames[101]));
    throwsWith(() => rig.solve(), "frame: must be an object { timeMs, hands?, pose?, wrists? }, got undefined");
    rig.free();
    throwsWith(() => HandRig.fromVrm(robotBytes, { calibration: true }), "options.calibration: must be an object of calibration.* options, got boolean true");
    throwsWith(
      () => HandRig.fromVrm(robotBytes, { alignment: { weight: 1 }, "alignment.weight": 0.5 }),
      "options.alignment.weight: given twice (as a nested object and as a dotted path)",
    );
    throwsWith(() => HandRig.fromVrm(robotBytes, { armSolver: "magic" }), /^options\.armSolver: must be one of "twoBone"/);
    throwsWith(() => HandRig.fromVrm(robotBytes, [1]), "options: must be an object, got an array of 1");
  });
});

describe("frame shapes that used to be accepted with nothing solved", () => {
  const rig = HandRig.fromVrm(robotBytes);

  it("the whole recording passed as the frame", () => {
    throwsWith(
      () => rig.solve(frames),
      `frame: must be one frame object { timeMs, hands?, pose?, wrists? }, got an array of ${frames.length} (a whole recording? solve its frames one at a time)`,
    );
  });

  it("an array, a Date or a Map as the frame", () => {
    throwsWith(() => rig.solve([]), /^frame: must be one frame object/);
    throwsWith(() => rig.solve(new Date()), "frame: must be a frame object { timeMs, hands?, pose?, wrists? }, got a Date");
    throwsWith(() => rig.solve(new Map([["hands", [hand]]])), "frame: must be a frame object { timeMs, hands?, pose?, wrists? }, got a Map");
  });

  it("a tasks-vision result without handedness", () => {
    throwsWith(
      () => rig.solve({ timeMs: 1, hands: { landmarks: [hand.landmarks], worldLandmarks: [hand.worldLandmarks] } }),
      "frame.hands.handedness: is missing: a HandLandmarker result needs `handedness` to tell the hands apart",
    );
    throwsWith(
      () => rig.solve({ landmarks: [hand.landmarks], worldLandmarks: [hand.worldLandmarks] }),
      /^frame\.handedness: is missing.*PoseLandmarker result goes in frame\.pose/,
    );
  });

  it("two landmark sets with one handedness entry", () => {
    throwsWith(
      () =>
        rig.solve({
          timeMs: 1,
          hands: {
            landmarks: [hand.landmarks, hand.landmarks],
            worldLandmarks: [hand.worldLandmarks, hand.worldLandmarks],
            handedness: [[{ categoryName: "Left", score: 0.9 }]],
          },
        }),
      "frame.hands.worldLandmarks: has 2 hand(s) but frame.hands.handedness has 1: one entry per hand",
    );
  });

  it("a single hand object in place of an array", () => {
    throwsWith(() => rig.solve({ timeMs: 1, hands: hand }), "frame.hands: must be an array of hands, got a single hand object: wrap it in [ ]");
  });

  it("an object with none of the frame's fields", () => {
    throwsWith(() => rig.solve({ when: 5, fingers: [hand] }), /^frame: has none of timeMs, hands, pose, wrists .*got keys when, fingers$/);
    // Near misses of the right names are named themselves (see "misnamed frame fields").
    throwsWith(() => rig.solve({ time: 5, hand: [hand] }), /^frame\.time: unknown field/);
  });

  it("the rig still works after all of these", () => {
    assert.equal(rig.solve(frames[10]).hands.right.status, "solved");
  });
});

describe("a .vrm missing a required bone names the file", () => {
  it("vrm: humanoid lacks required bone(s) ...", () => {
    const bytes = editedRobot((json) => delete json.extensions.VRMC_vrm.humanoid.humanBones.head);
    throwsWith(() => HandRig.fromVrm(bytes), "vrm: humanoid lacks required bone(s) head");
  });
});

describe("lost tracking: every driven bone in every result, applied by the adapter", () => {
  it("when the hand disappears its fingers hold briefly, then ease back to rest on the avatar (no freeze)", async () => {
    const vrm = await loadVRM(avatars.robot);
    const rig = HandRig.fromVrm(robotBytes);
    const driven = rig.drivenBones();
    assert.ok(driven.includes("rightIndexProximal") && driven.includes("leftUpperArm") && !driven.includes("head"));
    const t0 = frames[10].timeMs;
    const r1 = rig.solve(frames[10]);
    assert.deepEqual(Object.keys(r1.bones).sort(), [...driven].sort(), "every driven bone, every frame");
    applyToVRM(vrm, r1);
    const node = vrm.humanoid.getNormalizedBoneNode("rightIndexProximal");
    const solved = node.quaternion.toArray();
    assert.ok(!isIdentity(solved), "the finger moved");
    // Lost: held for dropout.holdMs (250 ms), then eased to rest over fadeOutMs (500 ms).
    const held = rig.solve({ timeMs: t0 + 100 });
    assert.deepEqual(Object.keys(held.bones).sort(), [...driven].sort());
    assert.equal(applyToVRM(vrm, held), driven.length);
    assert.deepEqual(node.quaternion.toArray(), solved, "held at 100 ms");
    applyToVRM(vrm, rig.solve({ timeMs: t0 + 500 }));
    const easing = node.quaternion.toArray();
    assert.ok(!isIdentity(easing) && easing.some((c, i) => Math.abs(c - solved[i]) > 1e-3), "easing at 500 ms");
    applyToVRM(vrm, rig.solve({ timeMs: t0 + 1000 }));
    assert.ok(isIdentity(node.quaternion.toArray()), "back at rest 750 ms after the loss");
    rig.free();
  });

  it("with dropout off, a lost hand and stopped wrists go back to rest at once (the arm to its idle rest)", () => {
    // The arm's idle rest (arm.idle "down", the default): what a rig that never saw the arm shows.
    const idle = HandRig.fromVrm(robotBytes).solve({ timeMs: 0 }, {}).bones;
    assert.ok(!isIdentity(idle.rightUpperArm), "down by the side, not the T-pose");
    for (const [options, rest] of [
      [{ dropout: false }, idle],
      [{ dropout: false, arm: { idle: "tpose" } }, { rightUpperArm: [0, 0, 0, 1], rightLowerArm: [0, 0, 0, 1] }],
    ]) {
      const rig = HandRig.fromVrm(robotBytes, options);
      const r1 = rig.solve({ ...frames[10], wrists: { right: { position: [-0.4, 1.2, 0.25] } } }, {});
      const r2 = rig.solve({ timeMs: frames[10].timeMs + 33 }, {});
      for (const bone of ["rightUpperArm", "rightLowerArm"]) {
        assert.ok(angle(r1.bones[bone], rest[bone]) > 0.1, `${bone} moved by the wrist`);
        assert.ok(angle(r2.bones[bone], rest[bone]) < 1e-3, `${JSON.stringify(options)}: ${bone} rests`);
      }
      assert.ok(!isIdentity(r1.bones.rightIndexProximal));
      assert.ok(isIdentity(r2.bones.rightIndexProximal), "the finger rests");
      rig.free();
    }
  });
});

describe("misnamed frame fields", () => {
  it("timestamp for timeMs, hand for hands, wrist for wrists: an Error naming the field, not a frame silently without them", () => {
    const rig = HandRig.fromVrm(robotBytes);
    const h = frames[100].hands;
    const cases = [
      [{ timestamp: 5, hands: h }, "frame.timestamp: unknown field: handrig reads the time from frame.timeMs (milliseconds)"],
      [{ time: 5, hands: h }, "frame.time: unknown field: handrig reads the time from frame.timeMs (milliseconds)"],
      [{ timeMs: 5, hand: h }, "frame.hand: unknown field: did you mean frame.hands (an array of hands)?"],
      [{ timeMs: 5, Hands: h }, "frame.Hands: unknown field: did you mean frame.hands (an array of hands)?"],
      [{ timeMs: 5, wrist: { left: { position: [0.3, 1.2, 0.1] } } }, "frame.wrist: unknown field: did you mean frame.wrists ({ left?, right? })?"],
      [{ timeMs: 5, wrists: { Right: { position: [0.3, 1.2, 0.1] } } }, "frame.wrists.Right: unknown field: did you mean frame.wrists.right?"],
      [{ timeMs: 5, poses: [{ worldLandmarks: [] }] }, "frame.poses: unknown field: did you mean frame.pose ({ worldLandmarks, landmarks? })?"],
    ];
    for (const [frame, message] of cases) throwsWith(() => rig.solve(frame), message);
    // After a rig's first three frames, checked only when the frame lacks its time or has no
    // hand to solve (a lookup of absent names every frame cost garbage).
    for (let k = 0; k < 3; k++) rig.solve({ timeMs: k, hands: h });
    assert.ok(rig.solve({ timeMs: 7, hands: h, poses: [] }, {}).hands.right);
    const fresh = HandRig.fromVrm(robotBytes);
    throwsWith(() => fresh.solve({ timeMs: 1, hands: h, poses: [] }), "frame.poses: unknown field: did you mean frame.pose ({ worldLandmarks, landmarks? })?");
    throwsWith(() => fresh.solve({ timeMs: 1, hands: h, wrist: {} }), "frame.wrist: unknown field: did you mean frame.wrists ({ left?, right? })?");
    fresh.free();
    // The right names, and both present (the right one wins), are fine.
    assert.ok(rig.solve({ timeMs: 5, hands: h }, {}).hands.right);
    assert.ok(rig.solve({ timeMs: 6, time: 6, hands: h, hand: "mine" }, {}).hands.right);
    rig.free();
  });
});

describe("tasks-vision HolisticLandmarker results", () => {
  it("solve({ timeMs, ...holisticResult }) drives the avatar as the same hands and pose given as a frame", async () => {
    const fs = await import("node:fs");
    const path = await import("node:path");
    const { shared } = await import("./support.mjs");
    const plain = HandRig.fromVrm(robotBytes);
    const holistic = HandRig.fromVrm(robotBytes);
    let hands = 0;
    for (const clip of ["thanks", "sister"]) {
      for (const f of JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", `${clip}.json`), "utf8")).frames) {
        // Holistic names hands by the subject's side: its left hand is the one Hands labels "Right".
        const side = (label) => f.hands.filter((h) => h.handedness === label);
        // Frames where Hands gave one label twice have no Holistic counterpart.
        if (side("Left").length > 1 || side("Right").length > 1) continue;
        const result = holisticResult(f);
        const want = plain.solve({ timeMs: f.timeMs, hands: f.hands.map((h) => ({ ...h, score: 1 })), pose: f.pose }, {});
        const got = holistic.solve({ timeMs: f.timeMs, ...result }, {});
        assert.deepEqual(got.bones, want.bones, `${clip} frame ${f.frame}`);
        assert.deepEqual(got.ikTargets, want.ikTargets, `${clip} frame ${f.frame}`);
        hands += f.hands.length;
      }
    }
    assert.ok(hands > 100, `${hands} hands`);
    const bad = { timeMs: 1, leftHandLandmarks: [[{ x: 0, y: 0, z: 0 }]], leftHandWorldLandmarks: [] };
    assert.throws(() => holistic.solve(bad), (e) => /^frame\.leftHandWorldLandmarks: must be a list of one hand/.test(e.message));
    plain.free();
    holistic.free();
  });
});

describe("legacy Holistic results", () => {
  it("leftHandLandmarks is the subject's left hand: it drives the side a Hands 'Right' label does", async () => {
    const fs = await import("node:fs");
    const path = await import("node:path");
    const { shared } = await import("./support.mjs");
    const clip = JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", "thanks.json"), "utf8"));
    const rig = HandRig.fromVrm(robotBytes, { filter: false, dropout: false });
    let checked = 0;
    for (const f of clip.frames) {
      for (const h of f.hands) {
        const key = h.handedness === "Left" ? "rightHandLandmarks" : "leftHandLandmarks";
        const hands = rig.solve({ timeMs: f.timeMs, hands: [h] }, {}).hands;
        const holistic = rig.solve({ timeMs: f.timeMs, [key]: h.landmarks, imageAspect: 640 / 480 }, {}).hands;
        assert.deepEqual(Object.keys(holistic), Object.keys(hands), `frame ${f.frame}: ${key}`);
        checked++;
      }
    }
    assert.ok(checked > 50, `${checked} hands`);
    rig.free();
  });

  it("a result passed as it comes: the pose's world landmarks under their minified name (za, or ea) drive the arms", async () => {
    const fs = await import("node:fs");
    const path = await import("node:path");
    const { shared } = await import("./support.mjs");
    const clip = JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", "eat.json"), "utf8"));
    const pt = ([x, y, z, visibility]) => ({ x, y, z, visibility });
    for (const key of ["za", "ea"]) {
      let driven = 0;
      // Arms without a wrist at the T-pose (identity): a rotation away from it is the pose's.
      const plain = HandRig.fromVrm(robotBytes, { arm: { idle: "tpose" } });
      const holistic = HandRig.fromVrm(robotBytes, { arm: { idle: "tpose" } });
      for (const f of clip.frames) {
        const world = f.pose.worldLandmarks.map(pt);
        const image = f.pose.landmarks.map(pt);
        const want = plain.solve({ timeMs: f.timeMs, pose: { worldLandmarks: world, landmarks: image } }, {});
        const got = holistic.solve({ timeMs: f.timeMs, poseLandmarks: image, [key]: world, image: {}, segmentationMask: {} }, {});
        assert.deepEqual(got.bones, want.bones, `${key}: frame ${f.frame}`);
        if (Math.abs(want.bones.rightUpperArm[3]) < 0.999 || Math.abs(want.bones.leftUpperArm[3]) < 0.999) driven++;
      }
      assert.ok(driven > clip.frames.length / 2, `the pose drives the arms in ${driven} frames`);
      plain.free();
      holistic.free();
    }
  });
});

describe("issue 30: mistakes a new user makes, named", () => {
  const asl = async (clip) => {
    const fs = await import("node:fs");
    const path = await import("node:path");
    const { shared } = await import("./support.mjs");
    return JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", `${clip}.json`), "utf8")).frames;
  };
  const pt = landmark;

  it("a result nested under a field of the app's own (holistic, results): an Error naming the field", async () => {
    const f = (await asl("thanks"))[20];
    const result = {
      poseLandmarks: [f.pose.landmarks.map(pt)],
      poseWorldLandmarks: [f.pose.worldLandmarks.map(pt)],
      leftHandLandmarks: [],
      leftHandWorldLandmarks: [],
      rightHandLandmarks: [],
      rightHandWorldLandmarks: [],
    };
    const rig = HandRig.fromVrm(robotBytes, { arm: { idle: "tpose" } });
    throwsWith(() => rig.solve({ timeMs: 1, holistic: result }), /^frame\.holistic: unknown field holding an object: handrig reads timeMs, hands, pose, .*rig\.solve\(\{ timeMs, \.\.\.result \}\)/);
    throwsWith(() => rig.solve({ timeMs: 1, results: [hand] }), /^frame\.results: unknown field holding an array of 1: /);
    // Spread into the frame, the same result drives the arms; numbers and strings of the app's
    // own ride along unremarked.
    const good = rig.solve({ timeMs: 1, frame: 20, source: "webcam", ...result }, {});
    assert.ok(!isIdentity(good.bones.rightUpperArm) || !isIdentity(good.bones.leftUpperArm), "the pose drove an arm");
    rig.free();
  });

  it("image landmarks given as hand world landmarks: an Error saying they look image-normalized (object, result and flat paths)", () => {
    const rig = HandRig.fromVrm(robotBytes);
    const message = /^frame\.hands\[0\]\.worldLandmarks: these look like image-normalized landmarks \(within the image's 0\.\.1, centered far from the origin\): world landmarks are meters/;
    throwsWith(() => rig.solve({ timeMs: 1, hands: [{ ...hand, worldLandmarks: hand.landmarks }] }), message);
    const result = { landmarks: [hand.landmarks.map(pt)], worldLandmarks: [hand.landmarks.map(pt)], handedness: [[{ categoryName: hand.handedness, score: 0.9 }]] };
    throwsWith(() => rig.solve({ timeMs: 1, hands: result }), message);
    // The flat path: the same check, in Rust.
    rig.input.fill(0);
    const L = LAYOUT.input;
    rig.input[L.handCount] = 1;
    const h = L.hands;
    rig.input[h + L.hand.handedness] = hand.handedness === "Right" ? 1 : 0;
    rig.input[h + L.hand.score] = 1;
    rig.input[h + L.hand.hasWorld] = 1;
    hand.landmarks.forEach((p, k) => rig.input.set(p.slice(0, 3), h + L.hand.world + 3 * k));
    throwsWith(() => rig.solveFlat(1), message);
    // Real world landmarks, on every frame of the recording: accepted.
    for (const f of frames) rig.solve(f);
    rig.free();
  });

  it("pose world landmarks in pixels: an Error saying so", async () => {
    const f = (await asl("eat"))[30];
    const rig = HandRig.fromVrm(robotBytes, { torso: "pose" });
    const pixels = f.pose.landmarks.map(([x, y, z, v]) => [x * 640, y * 480, z * 640, v]);
    throwsWith(
      () => rig.solve({ timeMs: 1, pose: { worldLandmarks: pixels, landmarks: f.pose.landmarks } }),
      /^frame\.pose\.worldLandmarks: a point is more than 4 m from the hips: pose world landmarks are meters centered between the hips \(pixels given\?/,
    );
    assert.ok(rig.solve({ timeMs: 2, pose: f.pose }, {}).bones.chest, "the real pose is read");
    rig.free();
  });

  it("solve(landmarks, \"Right\"), Kalidokit's call shape: the frame is blamed, with what handrig takes", () => {
    const rig = HandRig.fromVrm(robotBytes);
    throwsWith(
      () => rig.solve(hand.landmarks, "Right"),
      /^frame: must be a frame object \{ timeMs, hands\?, pose\?, wrists\? \}, got an array of 21 with string "Right" as a second argument: that is Kalidokit's Hand\.solve\(landmarks, side\) call shape, not handrig's\. Pass the MediaPipe result in one frame: rig\.solve\(\{ timeMs, hands: handLandmarkerResult \}\)/,
    );
    throwsWith(() => rig.solve(frames[10], "Left"), /^target: must be an object to fill with the result, got string "Left"; handrig takes no side argument/);
    assert.equal(rig.solve(frames[10]).hands.right.status, "solved", "the rig still works");
    rig.free();
  });

  it("timeMs in seconds (0.033 a frame): one console warning per rig; milliseconds: none", () => {
    const warned = [];
    const warn = console.warn;
    console.warn = (m) => warned.push(String(m));
    try {
      const seconds = HandRig.fromVrm(robotBytes);
      for (let i = 0; i < 40; i++) seconds.solve({ ...frames[100 + i], timeMs: i / 30 });
      assert.equal(warned.length, 1, warned.join("\n"));
      assert.match(warned[0], /^handrig: frame\.timeMs advanced by 0\.033 a frame for 5 frames: it looks like seconds\. timeMs is milliseconds/);
      const ms = HandRig.fromVrm(robotBytes);
      for (const f of frames.slice(100, 400)) ms.solve(f);
      // Repeated times (a frame solved twice) and a paused clock are not seconds either.
      for (let i = 0; i < 20; i++) ms.solve({ ...frames[400], timeMs: frames[400].timeMs + (i >> 1) * 33 });
      assert.equal(warned.length, 1, warned.join("\n"));
      // Three seconds-like steps at a time, then a millisecond one: not enough.
      const few = HandRig.fromVrm(robotBytes);
      for (let i = 0; i < 40; i++) few.solve({ ...frames[100 + i], timeMs: Math.floor(i / 4) * 100 + (i % 4) * 0.033 });
      assert.equal(warned.length, 1, warned.join("\n"));
      [seconds, ms, few].forEach((r) => r.free());
    } finally {
      console.warn = warn;
    }
  });
});
