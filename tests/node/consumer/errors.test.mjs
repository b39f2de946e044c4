// Bad input through the packed package: a JS Error whose message names the field, and the rig
// keeps working afterwards (a wasm panic would poison the module and fail the "afterwards" part).

import assert from "node:assert/strict";
import { describe, it } from "node:test";

import { HandRig } from "handrig";
import { avatars, readBytes, readRecording } from "./support.mjs";

/** Asserts `fn` throws an Error (not a string, not a panic) whose message matches `pattern`. */
function throwsNaming(fn, pattern) {
  assert.throws(fn, (e) => {
    assert.ok(e instanceof Error, `threw a non-Error: ${String(e)}`);
    assert.match(e.message, pattern);
    assert.doesNotMatch(e.message, /unreachable|panicked|RuntimeError/);
    return true;
  });
}

const frames = readRecording();
const good = frames[10];
const hand = good.hands[0];
const robotBytes = readBytes(avatars.robot);

describe("solve() rejects bad frames by field, and the rig keeps working", () => {
  const rig = HandRig.fromVrm(robotBytes);
  const expected = rig.solve(good, {});
  const withHand = (patch) => ({ timeMs: 1, hands: [{ ...hand, ...patch }] });
  const nanLandmarks = hand.worldLandmarks.map((p, i) => (i === 7 ? [p[0], Number.NaN, p[2]] : p));
  const cases = {
    "20 world landmarks": [withHand({ worldLandmarks: hand.worldLandmarks.slice(0, 20) }), /frame\.hands\[0\]\.worldLandmarks/],
    "a NaN coordinate": [withHand({ worldLandmarks: nanLandmarks }), /frame\.hands\[0\]\.worldLandmarks\[7\]/],
    "Infinity in a flat Float32Array": [
      withHand({ worldLandmarks: Float32Array.from(hand.worldLandmarks.flat(), (v, i) => (i === 5 ? Infinity : v)) }),
      /frame\.hands\[0\]\.worldLandmarks\[5\]/,
    ],
    "a point with 2 numbers": [withHand({ worldLandmarks: hand.worldLandmarks.map((p, i) => (i === 3 ? [p[0], p[1]] : p)) }), /worldLandmarks\[3\]/],
    "an unknown handedness": [withHand({ handedness: "Middle" }), /frame\.hands\[0\]\.handedness/],
    "a missing handedness": [{ timeMs: 1, hands: [{ worldLandmarks: hand.worldLandmarks }] }, /frame\.hands\[0\]\.handedness/],
    "a non-finite timeMs": [{ ...good, timeMs: Number.NaN }, /frame\.timeMs/],
    "a string as frame": ["frame 1", /^frame/],
    "a wrist position with NaN": [{ timeMs: 1, wrists: { right: { position: [0, Number.NaN, 0] } } }, /frame\.wrists\.right\.position/],
    "a non-unit wrist rotation": [{ timeMs: 1, wrists: { left: { position: [0.3, 1.2, 0], rotation: [0, 0, 0, 2] } } }, /frame\.wrists\.left\.rotation/],
    "5 hands": [{ timeMs: 1, hands: [hand, hand, hand, hand, hand] }, /frame\.hands/],
    // Past the first points of a list of the common shapes (objects, or arrays with
    // visibility): the fast packing gives up there and the checking pass names the point.
    "a NaN .y in an object landmark": [
      withHand({ worldLandmarks: hand.worldLandmarks.map(([x, y, z], i) => ({ x, y: i === 12 ? Number.NaN : y, z })) }),
      /^frame\.hands\[0\]\.worldLandmarks\[12\]\.y: must be a finite number/,
    ],
    "a pose visibility of 1.5": [
      { timeMs: 1, pose: { worldLandmarks: Array.from({ length: 33 }, (_, i) => [0, 0, 0, i === 20 ? 1.5 : 0.9]) } },
      /^frame\.pose\.worldLandmarks\[20\]\[3\]: must be in 0\.\.1/,
    ],
    "a string visibility on an object": [
      { timeMs: 1, pose: { worldLandmarks: Array.from({ length: 33 }, (_, i) => ({ x: 0, y: 0, z: 0, visibility: i === 32 ? "1" : 1 })) } },
      /^frame\.pose\.worldLandmarks\[32\]\.visibility: must be a number/,
    ],
    "32 pose landmarks": [{ timeMs: 1, pose: { worldLandmarks: Array.from({ length: 32 }, () => ({ x: 0, y: 0, z: 0 })) } }, /frame\.pose\.worldLandmarks/],
  };
  for (const [name, [frame, pattern]] of Object.entries(cases)) {
    it(name, () => {
      throwsNaming(() => rig.solve(frame), pattern);
      assert.deepEqual(rig.solve(good, {}), expected, "the rig gives the same answer after the error");
    });
  }
});

describe("landmark lists of mixed shapes", () => {
  it("objects, arrays and typed arrays in one list solve like the recording's arrays", () => {
    const rig = HandRig.fromVrm(robotBytes);
    const expected = rig.solve(good, {});
    const mixed = (list) =>
      list.map((p, i) => (i % 3 === 0 ? { x: p[0], y: p[1], z: p[2] } : i % 3 === 1 ? Float32Array.from(p) : p));
    const frame = { ...good, hands: good.hands.map((h) => ({ ...h, worldLandmarks: mixed(h.worldLandmarks), landmarks: mixed(h.landmarks) })) };
    const fresh = HandRig.fromVrm(robotBytes);
    const got = fresh.solve(frame, {});
    // Exactly equal: the rig reads f32s either way (a Float32Array point only rounds earlier).
    assert.deepEqual(got.bones, expected.bones);
    rig.free();
    fresh.free();
  });
});

describe("constructors reject bad rest poses, options and files by field", () => {
  const rest = HandRig.fromVrm(robotBytes).restWorldPositions();
  const cases = {
    "an unknown bone name": [() => new HandRig({ bones: { ...rest, leftWing: [0, 1, 0] } }), /restPose\.bones.*leftWing/],
    "missing required bones": [
      () => {
        const { head, leftUpperArm, ...bones } = rest;
        return new HandRig({ bones });
      },
      /restPose\.bones.*(head|leftUpperArm)/,
    ],
    "a NaN rest position": [() => new HandRig({ bones: { ...rest, spine: [0, Number.NaN, 0] } }), /restPose\.bones\.spine/],
    "a bad vrmVersion": [() => new HandRig({ bones: rest, vrmVersion: "2" }), /restPose\.vrmVersion/],
    "no bones at all": [() => new HandRig({}), /restPose\.bones/],
    "an unknown option": [() => HandRig.fromVrm(robotBytes, { mirrror: true }), /options\.mirrror/],
    "an unknown nested option": [() => HandRig.fromVrm(robotBytes, { alignment: { wieght: 1 } }), /options\.alignment\.wieght/],
    "an out-of-range weight": [() => HandRig.fromVrm(robotBytes, { alignment: { weight: 2 } }), /options\.alignment\.weight/],
    "an unknown finger": [() => HandRig.fromVrm(robotBytes, { alignment: { finger: "pinky" } }), /finger/],
    "a truncated .vrm": [() => HandRig.fromVrm(robotBytes.subarray(0, 5000)), /^vrm/],
    "bytes that are not a .vrm": [() => HandRig.fromVrm(new TextEncoder().encode("{\"asset\":{\"version\":\"2.0\"}}")), /^vrm/],
    "an empty file": [() => HandRig.fromVrm(new Uint8Array(0)), /^vrm/],
  };
  for (const [name, [fn, pattern]] of Object.entries(cases)) {
    it(name, () => throwsNaming(fn, pattern));
  }

  it("fromVrm without bytes is a TypeError naming `bytes`", () => {
    assert.throws(() => HandRig.fromVrm(undefined), (e) => e instanceof TypeError && /^bytes/.test(e.message));
    assert.throws(() => HandRig.fromVrm("debug-robot.vrm"), (e) => e instanceof TypeError && /bytes.*String/.test(e.message));
  });

  it("the module keeps working after all of these", () => {
    const rig = HandRig.fromVrm(robotBytes);
    assert.ok(rig.solve(good).bones.rightHand);
    rig.free();
  });
});
