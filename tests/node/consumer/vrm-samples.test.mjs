// The VRM Consortium's own sample models (vrm-c/vrm-specification, samples/; pixiv Inc., VRM
// Public License 1.0 with redistribution allowed: tests/fixtures/vrm-samples/PROVENANCE.md):
// avatars handrig was not written against. Two humanoids without fingers whose `blink` and
// `happy` are texture-transform expressions with `isBinary` and `overrideBlink`, and whose
// look-at is of type `expression`; one with fingers, three unskinned quads and no look-at.
// Each is loaded both ways (HandRig.fromVrm and three-vrm with restPoseFromVRM), solves a real
// sign-language clip with its face, and takes the result through applyToVRM.

import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";
import { describe, it } from "node:test";

import { HandRig, LAYOUT } from "handrig";
import { applyToVRM, restPoseFromVRM } from "handrig/three-vrm";
import { assertUnitQuat, loadVRM, readBytes, repo, shared, threeNormalizedWorldPositions } from "./support.mjs";

const DIR = path.join(repo, "tests", "fixtures", "vrm-samples");
const SAMPLES = [
  { file: "VRMC_materials_mtoon_UV_Animation_Test.vrm", fingers: true, lookAt: false },
  { file: "VRMC_vrm_expressions_isBinary_Overridden.vrm", fingers: false, lookAt: true },
  { file: "VRMC_vrm_expressions_isBinary_Overrides.vrm", fingers: false, lookAt: true },
];

/** A FaceLandmarkerResult with these ARKit weights, the head turned `yaw` radians (the matrix). */
function faceResult(weights, yaw = 0) {
  const categories = [{ index: 0, score: 0, categoryName: "_neutral", displayName: "" }];
  LAYOUT.arkit.slice(0, 51).forEach((n, i) => categories.push({ index: i + 1, score: weights[n] ?? 0, categoryName: n, displayName: "" }));
  const c = Math.cos(yaw);
  const s = Math.sin(yaw);
  // Column-major 4 x 4, a turn about +Y and the face 40 cm before the camera.
  const data = [c, 0, -s, 0, 0, 1, 0, 0, s, 0, c, 0, 0, 0, -40, 1];
  return { faceBlendshapes: [{ categories, headIndex: -1, headName: "" }], facialTransformationMatrixes: [{ rows: 4, columns: 4, data }] };
}

const clip = JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", "eat.json"), "utf8")).frames;

/** Runs `fn` with console.warn captured; returns the messages. */
function warnings(fn) {
  const seen = [];
  const original = console.warn;
  console.warn = (...args) => seen.push(args.join(" "));
  try {
    return { value: fn(), seen };
  } finally {
    console.warn = original;
  }
}

describe("the VRM Consortium's sample models", () => {
  it("the three files are there, each a VRM 1.0 humanoid", () => {
    for (const s of SAMPLES) assert.ok(fs.existsSync(path.join(DIR, s.file)), s.file);
  });

  for (const sample of SAMPLES) {
    describe(sample.file, () => {
      it("fromVrm and three-vrm agree on the rest pose; a missing finger is named once", async () => {
        const file = path.join(DIR, sample.file);
        const vrm = await loadVRM(file);
        const three = await threeNormalizedWorldPositions(vrm);
        const { value: rig, seen } = warnings(() => HandRig.fromVrm(readBytes(file)));
        const ours = rig.restWorldPositions();
        assert.deepEqual(Object.keys(ours).sort(), Object.keys(three).sort());
        for (const [name, p] of Object.entries(ours)) {
          const d = Math.hypot(p[0] - three[name][0], p[1] - three[name][1], p[2] - three[name][2]);
          assert.ok(d <= 1e-5, `${name}: ${d} m from three-vrm's`);
        }
        if (sample.fingers) assert.deepEqual(seen, []);
        else assert.ok(seen.length === 1 && /leftIndexDistal is missing/.test(seen[0]) && /rightIndexDistal is missing/.test(seen[0]), `warnings: ${JSON.stringify(seen)}`);
        rig.free();
      });

      it("a real clip with its face solves on both rigs alike, every bone a unit quaternion, the arms down", async () => {
        const file = path.join(DIR, sample.file);
        const vrm = await loadVRM(file);
        const { value: fromFile } = warnings(() => HandRig.fromVrm(readBytes(file)));
        const { value: fromThree } = warnings(() => new HandRig(restPoseFromVRM(vrm)));
        let worst = 0;
        let worstAt = "";
        let lowest = Infinity;
        for (let i = 0; i < clip.length; i++) {
          const f = clip[i];
          const frame = { timeMs: f.timeMs, hands: f.hands, pose: f.pose, ...faceResult({ jawOpen: (i % 20) / 20 }) };
          const a = fromFile.solve(frame);
          const aBones = Object.fromEntries(Object.entries(a.bones).map(([k, q]) => [k, [...q]]));
          const b = fromThree.solve(frame);
          for (const [name, q] of Object.entries(aBones)) {
            assertUnitQuat(q, `frame ${i} ${name}`);
            const r = b.bones[name];
            const dot = Math.abs(q[0] * r[0] + q[1] * r[1] + q[2] * r[2] + q[3] * r[3]);
            const ang = 2 * Math.acos(Math.min(1, dot));
            if (ang > worst) { worst = ang; worstAt = `${name} on frame ${i}`; }
          }
          for (const v of Object.values(a.expressions)) assert.ok(v >= 0 && v <= 1, `frame ${i}: an expression weight ${v}`);
          // The upper arm's direction (rest: out to the side, along x): never a T-pose when
          // the pose's wrists hang below the shoulders or sign before the chest.
          if (i === 0) {
            const q = aBones.leftUpperArm;
            // +X turned by q: its y component (down is negative).
            const y = 2 * (q[0] * q[1] + q[3] * q[2]);
            lowest = Math.min(lowest, y);
          }
        }
        // The rest positions agree to 1e-5 m (f32 against three's f64), which the arm's IK
        // turns into about a milliradian; a rig without the look-at's offset differed by 0.2 rad
        // (its face placed elsewhere: the hand's contact on the mouth, frame 31).
        assert.ok(worst < 0.01, `the two rigs' bones differ by up to ${worst} rad (${worstAt})`);
        assert.ok(lowest < -0.3, `the left upper arm at the clip's start points ${lowest} of the way up (a T-pose is 0)`);
        fromFile.free();
        fromThree.free();
      });

      it("restPoseFromVRM passes the look-at's offset, and a bad one is named", async () => {
        const vrm = await loadVRM(path.join(DIR, sample.file));
        const rest = restPoseFromVRM(vrm);
        if (sample.lookAt) {
          const o = vrm.lookAt.offsetFromHeadBone;
          assert.deepEqual(rest.lookAtOffset, [o.x, o.y, o.z]);
          assert.ok(Math.hypot(...rest.lookAtOffset) > 0.01, `offset ${rest.lookAtOffset}`);
        } else {
          assert.equal(rest.lookAtOffset, undefined);
        }
        assert.throws(() => new HandRig({ ...rest, lookAtOffset: [0, "x", 0] }), /restPose\.lookAtOffset\[1\]/);
      });

      it("applyToVRM sets the avatar's blink and happy, and its look-at from the head's turn", async () => {
        const vrm = await loadVRM(path.join(DIR, sample.file));
        const { value: rig } = warnings(() => new HandRig(restPoseFromVRM(vrm), { face: { smoothing: false } }));
        let r;
        for (let i = 0; i < 10; i++) r = rig.solve({ timeMs: i * 33, ...faceResult({ eyeBlinkLeft: 1, eyeBlinkRight: 1, mouthSmileLeft: 1, mouthSmileRight: 1, eyeLookOutLeft: 0.8, eyeLookInRight: 0.8 }) });
        applyToVRM(vrm, r);
        const m = vrm.expressionManager;
        if (!m) {
          assert.ok(!sample.lookAt, "an avatar with no expression manager");
          rig.free();
          return;
        }
        if (m.getExpression("blink")) assert.ok(m.getValue("blink") > 0.5, `blink ${m.getValue("blink")} (result ${r.expressions.blink})`);
        if (m.getExpression("happy")) assert.ok(m.getValue("happy") > 0.3, `happy ${m.getValue("happy")} (result ${r.expressions.happy})`);
        if (sample.lookAt) {
          assert.ok(vrm.lookAt, "three-vrm made a look-at");
          assert.ok(Math.abs(vrm.lookAt.yaw) > 5, `look-at yaw ${vrm.lookAt.yaw} degrees from eyes turned 0.8`);
          // Its look-at is of type expression but it has no look* expressions: three-vrm's
          // update (with its isBinary and overrideBlink rules) must take what handrig set.
          vrm.update(0);
        }
        rig.free();
      });
    });
  }
});
