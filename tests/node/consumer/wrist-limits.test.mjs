// Issue 15, wrist limits, as a user meets them: a hand recording paired with another person's
// arm (the shared hand video with the Kinect session's right wrist, as the
// body-tracker recipe of docs/guide/frames.md maps it) used to bend the avatar's wrist back 120-150 degrees against
// the forearm. With the default `arm.wristLimits: true` the wrist stays within its anatomical
// range and the index distal still lands on the target DIP; `false` gives the old behaviour.
// The bend is measured on the result's world positions: the forearm (lowerArm -> hand) against
// the hand (hand -> middle proximal).

import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";
import { describe, it } from "node:test";

import { HandRig } from "handrig";
import { avatars, fixtureVrms, readBytes, readRecording, shared } from "./support.mjs";

const kinect = JSON.parse(fs.readFileSync(path.join(shared, "data", "pose", "kinect-upper-body.json"), "utf8"));
const video = readRecording();
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const len = (v) => Math.hypot(...v);
const angle = (a, b) => Math.acos(Math.max(-1, Math.min(1, (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (len(a) * len(b)))));
const deg = (r) => (r * 180) / Math.PI;

/** The Kinect right wrist for `rig`: left-handed recording frame to the avatar's, shoulder-relative, arm-scaled. */
function kinectRightWrists(rig) {
  const at = (n) => kinect.jointNames.indexOf(n);
  const [s, e, w] = ["SHOULDER_RIGHT", "ELBOW_RIGHT", "WRIST_RIGHT"].map(at);
  const toAvatar = ([x, y, z]) => [-x, y, z];
  const arms = kinect.frames.map((f) => len(sub(f.joints[e], f.joints[s])) + len(sub(f.joints[w], f.joints[e]))).sort((a, b) => a - b);
  const rest = rig.restWorldPositions();
  const scale = (len(sub(rest.rightLowerArm, rest.rightUpperArm)) + len(sub(rest.rightHand, rest.rightLowerArm))) / arms[arms.length >> 1];
  return kinect.frames.map((f) => {
    let o = sub(toAvatar(f.joints[w]), toAvatar(f.joints[s])).map((v) => v * scale);
    if (rig.vrmVersion === "0") o = [-o[0], o[1], -o[2]];
    return rest.rightUpperArm.map((p, k) => p + o[k]);
  });
}

/** Solves the paired session; per frame with a solved right hand: the wrist bend and the DIP miss. */
// The turn limit (arm.maxTurnSpeed) off: a hand paired with another person's arm turns faster
// than any arm, and this is about the solve (a slowed frame shows less than the solve).
function run(bytes, options) {
  const rig = HandRig.fromVrm(bytes, { ...options, "arm.maxTurnSpeed": 0 });
  const wrists = kinectRightWrists(rig);
  const out = [];
  for (const [i, position] of wrists.entries()) {
    const r = rig.solve({ timeMs: (i * 1000) / 30, hands: video[i].hands, wrists: { right: { position } } });
    if (r.hands.right?.status !== "solved" || !r.alignment.right) continue;
    const p = r.worldPositions;
    const bend = angle(sub(p.rightHand, p.rightLowerArm), sub(p.rightMiddleProximal, p.rightHand));
    const a = r.alignment.right;
    out.push({ bend, miss: a.reachable ? len(sub(p.rightIndexDistal, a.targetDip)) : null });
  }
  rig.free();
  return out;
}

describe("wrist limits: a hand paired with another person's arm", () => {
  for (const file of [avatars.robot, ...fixtureVrms()]) {
    it(`${path.basename(file)}: within the wrist's range by default, bent back beyond 90 degrees without`, () => {
      const bytes = readBytes(file);
      const limited = run(bytes, {});
      const free = run(bytes, { "arm.wristLimits": false });
      assert.ok(limited.length > 250 && free.length === limited.length);
      const worst = Math.max(...limited.map((f) => f.bend));
      // 80 degrees of flexion at most (the largest limit), plus the avatar's own hand axis
      // (hand -> middle proximal) a few degrees off its forearm's at rest.
      assert.ok(deg(worst) < 85, `largest bend with the limits: ${deg(worst)} degrees`);
      const beyond90 = free.filter((f) => deg(f.bend) > 90).length;
      assert.ok(beyond90 > 0.8 * free.length, `without the limits ${beyond90} of ${free.length} frames bend beyond 90 degrees`);
      // Fingertip alignment stays exact either way.
      for (const f of [...limited, ...free]) if (f.miss !== null) assert.ok(f.miss < 1e-4, `index distal ${f.miss} m from the target DIP`);
    });
  }

  it("arm.wristLimits takes a boolean, named in the error", () => {
    assert.throws(() => HandRig.fromVrm(readBytes(avatars.robot), { arm: { wristLimits: "no" } }), {
      message: 'options.arm.wristLimits: must be true or false, got string "no"',
    });
    const d = HandRig.optionDescriptions().find((o) => o.path === "arm.wristLimits");
    assert.deepEqual([d.type, d.default], ["boolean", true]);
  });
});
