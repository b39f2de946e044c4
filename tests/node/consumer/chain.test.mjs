// The standalone chain API (issue 9) and the retargeting report (issue 11) through the packed
// package: ChainSolver for FABRIK and CCD, field-named errors, typed-array solves; the avatar's
// fingertips and `handStrategy: "retarget"` in the result.

import assert from "node:assert/strict";
import { describe, it } from "node:test";

import { ChainSolver, HandRig } from "handrig";
import { avatars, readBytes, readRecording } from "./support.mjs";

const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);

describe("ChainSolver", () => {
  const joints = [[0, 0, 0], [0, 0.3, 0], [0, 0.55, 0], [0, 0.75, 0], [0, 0.9, 0]];
  for (const method of ["fabrik", "ccd"]) {
    it(`${method}: reaches a reachable target, keeps bone lengths, bends toward the pole`, () => {
      const s = new ChainSolver({ method, joints, iterations: 500 });
      const target = [0.35, 0.45, 0.1];
      const r = s.solve({ target, pole: [0, 0.5, 1] });
      assert.ok(r.reached && r.error < 1e-4, `error ${r.error}`);
      assert.ok(dist(r.joints[4], target) < 1e-4);
      for (let k = 0; k < 4; k++) {
        const rest = dist(joints[k], joints[k + 1]);
        assert.ok(Math.abs(dist(r.joints[k], r.joints[k + 1]) - rest) < 1e-5, `bone ${k}`);
      }
      assert.ok(r.joints[2][2] > 0, "middle joint on the pole's side (+z)");
      assert.equal(r.rotations.length, 4);
      // Out of reach: a straight chain toward the target.
      const far = s.solve({ target: [0, 0, 5] }, {});
      assert.equal(far.reached, false);
      assert.equal(far.reachable, false);
      for (const p of far.joints) assert.ok(Math.abs(p[0]) < 1e-5 && Math.abs(p[1]) < 1e-5, `${p}`);
      s.free();
      assert.equal(s.freed, true);
    });
  }

  it("solveInto fills typed arrays, and matches solve", () => {
    const a = new ChainSolver({ joints, constraints: [null, { type: "cone", maxAngle: 0.8 }, null, null] });
    const b = new ChainSolver({ joints, constraints: [null, { type: "cone", maxAngle: 0.8 }, null, null] });
    const out = { joints: new Float32Array(15), rotations: new Float32Array(16) };
    const got = a.solveInto([0.3, 0.5, 0], out);
    assert.equal(got, out);
    const want = b.solve({ target: [0.3, 0.5, 0] });
    for (let k = 0; k < 5; k++) for (let c = 0; c < 3; c++) assert.equal(out.joints[3 * k + c], Math.fround(want.joints[k][c]));
    assert.equal(out.reached, want.reached);
  });

  it("errors name the field", () => {
    const throwsWith = (fn, re) => assert.throws(fn, (e) => e instanceof Error && re.test(e.message));
    throwsWith(() => new ChainSolver({ joints: [[0, 0, 0], [0, 1, 0]] }), /^options\.joints: needs at least 3 joints/);
    throwsWith(() => new ChainSolver({ joints: [[0, 0, 0], [0, 0, 0], [0, 1, 0]] }), /^options\.joints\[1\]/);
    throwsWith(() => new ChainSolver({ joints: [[0, 0, 0], [0, 1, 0], [0, Number.NaN, 0]] }), /^options\.joints\[2\]\[1\]/);
    throwsWith(() => new ChainSolver({ joints, constraints: [{ type: "cone", maxAngle: -1 }, null, null, null] }), /^options\.constraints\[0\]\.maxAngle/);
    throwsWith(() => new ChainSolver({ joints, constraints: [{ type: "ball" }] }), /^options\.constraints\[0\]\.type/);
    throwsWith(() => new ChainSolver({ joints, method: "jacobian" }), /^options\.method/);
    throwsWith(() => new ChainSolver({ joints, iteration: 3 }), /^options\.iteration: unknown option \(expected one of method, joints, /);
    const s = new ChainSolver({ joints });
    throwsWith(() => s.solve({ target: [Number.NaN, 0, 0] }), /^target\[0\]/);
    assert.ok(s.solve({ target: [0.2, 0.5, 0] }).reached, "works after a rejected goal");
  });
});

describe("fingertips and retargeting in the result", () => {
  const frames = readRecording();
  it("every strategy reports the avatar's fingertips; retarget reports targets near them", () => {
    const analytic = HandRig.fromVrm(readBytes(avatars.robot));
    const retarget = HandRig.fromVrm(readBytes(avatars.robot), { handStrategy: "retarget" });
    const errors = [];
    for (const f of frames.slice(0, 200)) {
      const a = analytic.solve(f);
      assert.ok(a.fingertips.right.index && a.fingertips.left.thumb, "fingertips on both sides");
      assert.equal(a.retarget.right, undefined, "no report for analytic");
      const r = retarget.solve(f);
      const rep = r.retarget.right;
      assert.ok(rep && rep.scale > 0.5 && rep.scale < 2 && rep.iterations >= 0);
      for (const finger of ["thumb", "index", "middle", "ring", "little"]) {
        errors.push(dist(r.fingertips.right[finger], rep.targets[finger]));
      }
    }
    errors.sort((x, y) => x - y);
    const median = errors[errors.length >> 1];
    assert.ok(median < 0.004, `median fingertip-to-target distance ${(median * 1000).toFixed(2)} mm`);
    // Calibration from an open hand: a number or null per side.
    const scale = retarget.calibrateHandScale();
    assert.ok(scale.left === null && (scale.right === null || scale.right > 0));
  });
});
