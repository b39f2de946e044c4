// Self-contact retargeting (issue 14) through the packed package: the `contact.*` options
// (nested, dotted, `contact.faceAnchors` as an object of points, every error naming the
// field), the `frame.face` input, `result.alignment.<side>.contact`, the flat output's contact
// fields and `rig.contactModel()`.

import assert from "node:assert/strict";
import { describe, it } from "node:test";

import { HandRig, LAYOUT } from "handrig";
import { assertFiniteVec, avatars, readBytes, readRecording, throwsWith } from "./support.mjs";

const robotBytes = readBytes(avatars.robot);
const frames = readRecording();
// The recording's hand is labelled "Left" (an un-mirrored right hand): it drives the avatar's
// right side with the default options.
const hand = frames[120].hands[0];

const ANCHORS = ["nose", "chin", "mouth", "leftCheek", "rightCheek", "leftEar", "rightEar", "forehead"];
const add = (a, b) => a.map((x, i) => x + b[i]);
const sub = (a, b) => a.map((x, i) => x - b[i]);
const dist = (a, b) => Math.hypot(...sub(a, b));

/**
 * A user (average adult face, 6 cm in front of the avatar's) touching their nose with the
 * recorded hand's index fingertip: tracker wrist and face points in the avatar's frame.
 */
function noseTouch(rig) {
  const nose = rig.contactModel().anchors.nose;
  const eyes = add(nose, [0, 0.045, 0.035]);
  const face = {
    nose: add(eyes, [0, -0.045, 0.025]),
    leftEye: add(eyes, [0.0315, 0, 0]),
    rightEye: add(eyes, [-0.0315, 0, 0]),
    leftEar: add(eyes, [0.0725, -0.02, -0.085]),
    rightEar: add(eyes, [-0.0725, -0.02, -0.085]),
    mouth: add(eyes, [0, -0.07, 0.012]),
  };
  // MediaPipe camera axes to the avatar's (un-mirrored): (x, -y, -z).
  const w = hand.worldLandmarks;
  const tip = [w[8][0] - w[0][0], w[0][1] - w[8][1], w[0][2] - w[8][2]];
  return { timeMs: 0, hands: [hand], wrists: { right: { position: sub(face.nose, tip) } }, face };
}

describe("contact: options", () => {
  it("are described, with contact.faceAnchors as a points option", () => {
    const d = new Map(HandRig.optionDescriptions().map((o) => [o.path, o]));
    for (const p of ["enabled", "radius", "weight", "hands", "faceAnchors", "colliders", "torsoRadius", "headRadius", "depthTrust"]) {
      assert.ok(d.has(`contact.${p}`), `contact.${p}`);
    }
    const fa = d.get("contact.faceAnchors");
    assert.equal(fa.type, "points");
    assert.deepEqual(fa.names, ANCHORS);
    assert.equal(fa.default, null);
    assert.equal(d.get("contact.enabled").default, true);
    assert.equal(d.get("contact.radius").default, 0.5);
  });

  it("nested, dotted and `contact: false` are accepted; faceAnchors moves the model's anchors", () => {
    const plain = HandRig.fromVrm(robotBytes);
    const head = plain.restWorldPositions().head;
    const given = HandRig.fromVrm(robotBytes, { contact: { faceAnchors: { nose: [0, 0.05, 0.2], chin: { x: 0, y: -0.1, z: 0.1 } } } });
    const m = given.contactModel();
    assert.ok(dist(m.anchors.nose, add(head, [0, 0.05, 0.2])) < 1e-5);
    assert.ok(dist(m.anchors.chin, add(head, [0, -0.1, 0.1])) < 1e-5);
    assert.ok(dist(m.anchors.mouth, plain.contactModel().anchors.mouth) < 1e-6, "others stay derived");
    const dotted = HandRig.fromVrm(robotBytes, { "contact.faceAnchors": { nose: [0, 0.05, 0.2] }, "contact.radius": 0.8 });
    assert.ok(dist(dotted.contactModel().anchors.nose, m.anchors.nose) < 1e-6);
    const off = HandRig.fromVrm(robotBytes, { contact: false });
    const r = off.solve(noseTouch(off), {});
    assert.equal(r.alignment.right.contact, null);
    for (const rig of [plain, given, dotted, off]) rig.free();
  });

  it("errors name the field", () => {
    throwsWith(
      () => HandRig.fromVrm(robotBytes, { contact: { faceAnchors: { nostril: [0, 0, 0] } } }),
      `options.contact.faceAnchors.nostril: unknown point (expected one of ${ANCHORS.join(", ")})`,
    );
    throwsWith(
      () => HandRig.fromVrm(robotBytes, { contact: { faceAnchors: { nose: [0, 0] } } }),
      "options.contact.faceAnchors.nose: must have 3 numbers [x, y, z], got 2",
    );
    throwsWith(() => HandRig.fromVrm(robotBytes, { contact: { faceAnchors: [0, 0, 0] } }), /^options\.contact\.faceAnchors: must be an object/);
    throwsWith(() => HandRig.fromVrm(robotBytes, { "contact.radius": 5 }), /^options\.contact\.radius: must be in 0\.05.*\.\.3, got 5$/);
    throwsWith(
      () => HandRig.fromVrm(robotBytes, { contact: { faceAnchors: { nose: [0, 0, 20] } } }),
      /^options\.contact\.faceAnchors\.nose: must be \[x, y, z\]: finite meters within 10 of the head bone$/,
    );
    throwsWith(() => HandRig.fromVrm(robotBytes, { contact: { wieght: 1 } }), "options.contact.wieght: unknown option (did you mean contact.weight?)");
  });
});

describe("contact: frame.face and the report", () => {
  it("a fingertip on the user's nose lands on the avatar's nose; plain alignment misses it", () => {
    const rig = HandRig.fromVrm(robotBytes, { filter: false, dropout: false });
    const frame = noseTouch(rig);
    const r = rig.solve(frame, {});
    const c = r.alignment.right.contact;
    assert.deepEqual(Object.keys(c).sort(), ["anchor", "distance", "handWeight", "push", "weight"]);
    assert.equal(c.anchor, "nose");
    assert.equal(c.weight, 1);
    assert.equal(c.handWeight, 0);
    assert.ok(r.alignment.right.reachable);
    // The avatar's index fingertip after IK is on the anchor, and the report says so.
    const tip = r.fingertips.right.index;
    const nose = rig.contactModel().anchors.nose;
    assert.ok(dist(tip, nose) < 0.005, `fingertip ${dist(tip, nose)} m from the nose`);
    assert.ok(Math.abs(c.distance - dist(tip, nose)) < 1e-4);

    const plain = HandRig.fromVrm(robotBytes, { filter: false, dropout: false, contact: { enabled: false } });
    const p = plain.solve(frame, {});
    assert.ok(dist(p.fingertips.right.index, nose) > 0.03, "the user's face is 6 cm in front of the avatar's");

    // The flat output carries the same report.
    const O = LAYOUT.output;
    const at = O.sides + 1 * O.sideStride;
    const out = rig.output;
    assert.equal(out[at + O.side.contactPresent], 1);
    assert.equal(out[at + O.side.contactAnchor], 0);
    assert.equal(out[at + O.side.contactWeight], 1);
    assert.ok(Math.abs(out[at + O.side.contactDistance] - c.distance) < 1e-6);
    rig.free();
    plain.free();
  });

  it("far from the face the weight is 0 and the target is plain alignment", () => {
    const rig = HandRig.fromVrm(robotBytes, { filter: false, dropout: false, contact: { colliders: false } });
    const plain = HandRig.fromVrm(robotBytes, { filter: false, dropout: false, contact: false });
    const frame = noseTouch(rig);
    frame.wrists.right.position = add(frame.wrists.right.position, [-0.1, -0.3, 0.3]);
    const a = rig.solve(frame, {});
    const b = plain.solve(frame, {});
    assert.equal(a.alignment.right.contact.weight, 0);
    assert.equal(a.alignment.right.contact.anchor, "chin");
    assert.ok(dist(a.ikTargets.right.position, b.ikTargets.right.position) < 1e-6);
    rig.free();
    plain.free();
  });

  it("frame.face errors name the point", () => {
    const rig = HandRig.fromVrm(robotBytes);
    throwsWith(() => rig.solve({ face: { nose: [0, Number.NaN, 0] } }), /^frame\.face\.nose\[1\]: /);
    throwsWith(() => rig.solve({ face: { nostril: [0, 0, 0] } }), /^frame\.face: unknown point "nostril"/);
    throwsWith(() => rig.solve({ face: [0, 0, 0] }), /^frame\.face: must be \{ nose\?/);
    // The rig keeps working.
    assert.ok(rig.solve(noseTouch(rig)).alignment.right);
    rig.free();
  });

  it("contactModel() describes the anchors and colliders at rest", () => {
    const rig = HandRig.fromVrm(robotBytes);
    const m = rig.contactModel();
    assert.deepEqual(Object.keys(m.anchors), ANCHORS);
    for (const n of ANCHORS) assertFiniteVec(m.anchors[n], 3, n);
    assert.ok(m.headBreadth > 0.1 && m.headBreadth < 1);
    assert.ok(m.colliders.torso.radius > 0 && m.colliders.head.radius > 0);
    assertFiniteVec(m.colliders.head.center, 3, "head center");
    // Left is +X on a VRM 1.0 avatar.
    assert.ok(m.anchors.leftEar[0] > m.anchors.rightEar[0]);
    rig.free();
  });
});
