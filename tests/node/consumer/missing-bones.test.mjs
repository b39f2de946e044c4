// Avatars without the aligned finger's distal bone (issue 26, "missing bones") through the
// packed package: the rig warns once with console.warn naming what is missing and what stands
// in, `rig.alignedBones()` and `result.alignment.<side>.finger` / `.bone` report it, the flat
// output's `side.alignedBone` codes it, and alignment stays on.

import assert from "node:assert/strict";
import { describe, it } from "node:test";

import { HandRig, LAYOUT } from "handrig";
import { avatars, editedRobot, readBytes, readRecording } from "./support.mjs";

const frames = readRecording();
// The recording's hand is labelled "Left" (an un-mirrored right hand): it drives the avatar's
// right side with the default options.
const hand = frames[120].hands[0];

const FINGERS = ["Thumb", "Index", "Middle", "Ring", "Little"];

/** The robot without the humanoid bones `drop(name)` selects. */
function robotWithout(drop) {
  return editedRobot((json) => {
    const bones = json.extensions.VRMC_vrm.humanoid.humanBones;
    for (const name of Object.keys(bones)) if (drop(name)) delete bones[name];
  });
}

/** Runs `fn` with console.warn captured; returns the messages. */
function warnings(fn) {
  const seen = [];
  const original = console.warn;
  console.warn = (...args) => seen.push(args.join(" "));
  try {
    fn();
  } finally {
    console.warn = original;
  }
  return seen;
}

/** A frame with the recorded hand and a tracker wrist in front of the avatar's chest. */
function reachFrame(rig, timeMs) {
  const rest = rig.restWorldPositions();
  const chest = rest.upperChest ?? rest.chest ?? rest.spine;
  return { timeMs, hands: [hand], wrists: { right: { position: [chest[0] - 0.15, chest[1], chest[2] + 0.3] } } };
}

const cases = [
  ["without indexDistal", (n) => /IndexDistal$/.test(n), { finger: "index", bone: "rightIndexIntermediate" }],
  ["without the index finger", (n) => /Index/.test(n), { finger: "middle", bone: "rightMiddleDistal" }],
  ["without finger bones", (n) => FINGERS.some((f) => n.includes(f)), { finger: "palm", bone: "rightHand" }],
];

describe("missing bones: alignment with what the avatar has", () => {
  it("a full avatar aligns its index distal without a warning", () => {
    let rig;
    assert.deepEqual(
      warnings(() => (rig = HandRig.fromVrm(readBytes(avatars.robot)))),
      [],
    );
    assert.deepEqual(rig.alignedBones().right, { finger: "index", bone: "rightIndexDistal", standIn: false });
    const r = rig.solve(reachFrame(rig, 0));
    assert.equal(r.alignment.right.finger, "index");
    assert.equal(r.alignment.right.bone, "rightIndexDistal");
    const at = LAYOUT.output.sides + LAYOUT.output.sideStride;
    assert.equal(rig.output[at + LAYOUT.output.side.alignedBone], 0);
    rig.free();
  });

  for (const [name, drop, want] of cases) {
    it(`${name}: warns once, reports ${want.bone}, stays aligned`, () => {
      const bytes = robotWithout(drop);
      let rig;
      const seen = warnings(() => (rig = HandRig.fromVrm(bytes)));
      assert.equal(seen.length, 1, `one warning, got ${JSON.stringify(seen)}`);
      assert.match(seen[0], /rightIndexDistal is missing/);
      assert.match(seen[0], /leftIndexDistal is missing/);
      assert.ok(seen[0].includes(want.bone), `${seen[0]} names ${want.bone}`);
      assert.deepEqual(rig.alignedBones().right, { ...want, standIn: true });
      assert.equal(rig.alignedBones().left.finger, want.finger);

      const later = warnings(() => {
        for (let k = 0; k < 5; k++) {
          const r = rig.solve(reachFrame(rig, 33 * k));
          const a = r.alignment.right;
          assert.ok(a, "an alignment report");
          assert.equal(a.aligned, true);
          assert.equal(a.finger, want.finger);
          assert.equal(a.bone, want.bone);
          if (a.reachable) assert.ok(a.error < 1e-3, `alignment error ${a.error} m`);
        }
      });
      assert.deepEqual(later, [], "no warning per frame");
      const at = LAYOUT.output.sides + LAYOUT.output.sideStride;
      assert.equal(rig.output[at + LAYOUT.output.side.alignedBone], 1 + LAYOUT.bones.indexOf(want.bone));
      rig.free();
    });
  }

  it("each rig warns for itself; alignment and contact off: no warning", () => {
    const bytes = robotWithout((n) => /IndexDistal$/.test(n));
    const seen = warnings(() => {
      HandRig.fromVrm(bytes).free();
      HandRig.fromVrm(bytes).free();
    });
    assert.equal(seen.length, 2);
    const off = warnings(() =>
      HandRig.fromVrm(bytes, { alignment: { enabled: false }, contact: { enabled: false } }).free(),
    );
    assert.deepEqual(off, []);
  });
});
