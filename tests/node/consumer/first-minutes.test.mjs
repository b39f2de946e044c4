// Issue 48: the mistakes of a new user's first minutes that used to solve silently wrong, each
// with its named error or one-time warning: a frame without timeMs (and its fallback), timeMs
// misspelled, frame numbers as timeMs, a result nested under a field of the app's after a
// rig's first frames, a Holistic result as frame.pose, and a hand list not wrapped in its
// outer list.

import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";
import { describe, it } from "node:test";

import { HandRig } from "handrig";
import { avatars, holisticResult, isIdentity, landmark as pt, readBytes, readRecording, shared, throwsWith } from "./support.mjs";

const robotBytes = readBytes(avatars.robot);
const frames = readRecording();
const hand = frames[10].hands[0];

/** Runs `fn` with console.warn captured; returns the warnings. */
function warnings(fn) {
  const warned = [];
  const warn = console.warn;
  console.warn = (m) => warned.push(String(m));
  try {
    fn();
  } finally {
    console.warn = warn;
  }
  return warned;
}

/** A clip of the shared ASL recordings: hands and pose on the same frames. */
function asl(clip) {
  return JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", `${clip}.json`), "utf8")).frames;
}


describe("time", () => {
  it("a frame without timeMs warns once per rig and is taken as one 30 fps frame after the last", () => {
    const clip = frames.slice(100, 160);
    let untimed;
    let results;
    const warned = warnings(() => {
      const rig = HandRig.fromVrm(robotBytes);
      // Hands lost for a second on the way: the dropout hold must run out, as with real times.
      results = clip.map((f, i) => rig.solve(i >= 20 && i < 50 ? {} : { hands: f.hands }, {}));
      untimed = rig;
    });
    assert.equal(warned.length, 1, warned.join("\n"));
    assert.match(warned[0], /^handrig: frame\.timeMs is missing: each frame without it is taken as 33\.3 ms \(one frame at 30 fps\) after the last\./);
    const timed = HandRig.fromVrm(robotBytes);
    clip.forEach((f, i) => {
      const want = timed.solve(i >= 20 && i < 50 ? { timeMs: (i * 1000) / 30 } : { timeMs: (i * 1000) / 30, hands: f.hands }, {});
      assert.ok(Math.abs(results[i].timeMs - want.timeMs) < 1e-9, `frame ${i}: timeMs ${results[i].timeMs}`);
      assert.deepEqual(results[i].bones, want.bones, `frame ${i}`);
    });
    // The hold ran out while the hands were away: the finger eased back to rest.
    assert.ok(isIdentity(results[49].bones.rightIndexProximal), String(results[49].bones.rightIndexProximal));
    assert.ok(!isIdentity(results[19].bones.rightIndexProximal), "the finger was bent before");
    // After frames with time, an untimed one follows the last by 33.3 ms.
    untimed.solve({ timeMs: 5000, hands: clip[0].hands });
    const w2 = warnings(() => assert.ok(Math.abs(untimed.solve({ hands: clip[1].hands }, {}).timeMs - 5033.333) < 1e-3));
    assert.deepEqual(w2, [], "said once per rig");
    [untimed, timed].forEach((r) => r.free());
  });

  it("timeMs misspelled (timems, time_ms, timeMS): an Error naming the field", () => {
    const rig = HandRig.fromVrm(robotBytes);
    for (const key of ["timems", "time_ms", "timeMS", "TimeMs"]) {
      throwsWith(() => rig.solve({ [key]: 5, hands: [hand] }), `frame.${key}: unknown field: handrig reads the time from frame.timeMs (milliseconds)`);
    }
    rig.free();
  });

  it("timeMs given frame numbers (advancing by exactly 1 or 2): one warning per rig; real times: none", () => {
    const clip = frames.slice(100, 160);
    const byOne = warnings(() => {
      const rig = HandRig.fromVrm(robotBytes);
      clip.forEach((f, i) => rig.solve({ ...f, timeMs: i }));
      rig.free();
    });
    assert.equal(byOne.length, 1, byOne.join("\n"));
    assert.match(byOne[0], /^handrig: frame\.timeMs advanced by 1 a frame for 5 frames: it looks like frame numbers\. timeMs is milliseconds/);
    const everyOther = warnings(() => {
      const rig = HandRig.fromVrm(robotBytes);
      clip.forEach((f, i) => rig.solve({ ...f, timeMs: 1000 + 2 * i }));
      rig.free();
    });
    assert.equal(everyOther.length, 1, everyOther.join("\n"));
    const real = warnings(() => {
      const rig = HandRig.fromVrm(robotBytes);
      for (const f of frames.slice(100, 400)) rig.solve(f);
      // Whole milliseconds 33 or 34 apart (a rounded clock), and a frame solved twice, are fine.
      for (let i = 0; i < 20; i++) rig.solve({ ...frames[400], timeMs: 20000 + Math.round((i >> 1) * 33.4) });
      rig.free();
    });
    assert.deepEqual(real, []);
  });
});

describe("frame shapes", () => {
  it("a result nested under a field of the app's after the rig's first frames: an Error naming the field", () => {
    const rig = HandRig.fromVrm(robotBytes);
    const f = asl("thanks")[20];
    for (let k = 0; k < 5; k++) rig.solve({ timeMs: k * 33, ...holisticResult(f) });
    throwsWith(() => rig.solve({ timeMs: 200, holistic: holisticResult(f) }), /^frame\.holistic: unknown field holding an object: handrig reads timeMs, hands, pose/);
    throwsWith(() => rig.solve({ timeMs: 233, tracking: { hands: [hand] } }), /^frame\.tracking: unknown field holding an object/);
    // Frames with nothing detected are fine (a result with empty lists, or the time alone).
    const empty = { faceLandmarks: [], poseLandmarks: [], poseWorldLandmarks: [], leftHandLandmarks: [], rightHandLandmarks: [] };
    rig.solve({ timeMs: 266, ...empty });
    rig.solve({ timeMs: 300 });
    rig.solve({ timeMs: 333, hands: [] });
    rig.free();
  });

  it("a Holistic result as frame.pose: an Error saying to spread it into the frame", () => {
    const rig = HandRig.fromVrm(robotBytes);
    const f = asl("thanks")[20];
    assert.ok(f.hands.length > 0);
    throwsWith(
      () => rig.solve({ timeMs: 1, pose: holisticResult(f) }),
      "frame.pose: is a Holistic result (it has leftHandLandmarks / rightHandLandmarks): as frame.pose its hands would be ignored. Spread it into the frame instead: rig.solve({ timeMs, ...holisticResult })",
    );
    // Its pose alone, and a PoseLandmarker result, are a pose.
    const { poseWorldLandmarks, poseLandmarks } = holisticResult(f);
    rig.solve({ timeMs: 2, pose: { poseWorldLandmarks } });
    rig.solve({ timeMs: 3, pose: { worldLandmarks: poseWorldLandmarks, landmarks: poseLandmarks } });
    rig.free();
  });

  it("one hand's landmarks where a list of hands belongs: an Error saying to wrap it", () => {
    const rig = HandRig.fromVrm(robotBytes);
    const f = asl("thanks").find((x) => x.hands.some((h) => h.handedness === "Left"));
    const h = f.hands.find((x) => x.handedness === "Left");
    // tasks-vision Holistic: each side is a list of hands.
    throwsWith(
      () => rig.solve({ timeMs: 1, rightHandLandmarks: h.landmarks.map(pt), rightHandWorldLandmarks: h.worldLandmarks.map(pt) }),
      "frame.rightHandWorldLandmarks: is one hand's 21 points, not a list of hands: wrap it in [ ] (one list of points per hand)",
    );
    throwsWith(
      () => rig.solve({ timeMs: 2, rightHandLandmarks: h.landmarks.map(pt), rightHandWorldLandmarks: [h.worldLandmarks.map(pt)] }),
      "frame.rightHandLandmarks: is one hand's 21 points, not a list of hands: wrap it in [ ] (one list of points per hand)",
    );
    // HandLandmarker: one list per hand.
    const category = [{ categoryName: "Left", score: 0.9 }];
    throwsWith(
      () => rig.solve({ timeMs: 3, hands: { landmarks: [h.landmarks], worldLandmarks: h.worldLandmarks, handedness: [category] } }),
      "frame.hands.worldLandmarks: is one hand's 21 points, not a list of hands: wrap it in [ ] (one list of points per hand)",
    );
    throwsWith(
      () => rig.solve({ timeMs: 4, multiHandLandmarks: h.landmarks, multiHandedness: [{ label: "Left", score: 0.9 }] }),
      "frame.multiHandLandmarks: is one hand's 21 points, not a list of hands: wrap it in [ ] (one list of points per hand)",
    );
    throwsWith(
      () => rig.solve({ timeMs: 5, hands: h.worldLandmarks }),
      "frame.hands: is one hand's 21 landmarks, not a list of hands: give [{ handedness, worldLandmarks, landmarks? }] or a HandLandmarker result",
    );
    // Wrapped, each is read.
    const solvedHands = (frame) => Object.keys(rig.solve(frame, {}).hands).length;
    assert.equal(solvedHands({ timeMs: 6, rightHandLandmarks: [h.landmarks.map(pt)], rightHandWorldLandmarks: [h.worldLandmarks.map(pt)] }), 1);
    assert.equal(solvedHands({ timeMs: 7, hands: { landmarks: [h.landmarks], worldLandmarks: [h.worldLandmarks], handedness: [category] } }), 1);
    rig.free();
  });
});
