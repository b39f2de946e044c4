// Issue 26: the skin read from the file. `HandRig.fromVrm(bytes)` reads the skinned meshes in
// Rust and must learn the same body as `new HandRig(restPoseFromVRM(vrm))`, which passes
// three-vrm's loaded meshes (`restPose.skin`): the contact model at rest (face anchors on the
// skin, colliders, head breadth) within 1 mm, on every generated body (woman, man, child) as
// VRM 1.0 and 0.x. `HandRig.fromGltf` on the same body named the Mixamo way gives it too. And the
// skin matters: without it (the bone-based model) the anchors are centimeters elsewhere, so
// these comparisons can fail.

import assert from "node:assert/strict";
import path from "node:path";
import { describe, it } from "node:test";

import { HandRig, LAYOUT } from "handrig";
import { restPoseFromVRM } from "handrig/three-vrm";
import { loadVRM, readBytes, repo } from "./support.mjs";

const file = (name) => path.join(repo, "tests", "fixtures", "avatars", name);

/** Every number of a contact model, flat, with its name (anchors, head breadth, colliders). */
function flat(model) {
  const out = [];
  const walk = (v, at) => {
    if (v === null) out.push([at, null]);
    else if (typeof v === "number") out.push([at, v]);
    else if (Array.isArray(v)) v.forEach((x, i) => walk(x, `${at}[${i}]`));
    else for (const k of Object.keys(v)) walk(v[k], at ? `${at}.${k}` : k);
  };
  walk(model, "");
  return out;
}

/** Largest difference between two contact models' numbers (meters), and where. */
function largestDifference(a, b) {
  const fa = flat(a);
  const fb = flat(b);
  assert.deepEqual(
    fa.map(([k]) => k),
    fb.map(([k]) => k),
    "same anchors and colliders",
  );
  let worst = [0, ""];
  fa.forEach(([k, x], i) => {
    const d = Math.abs(x - fb[i][1]);
    if (d > worst[0]) worst = [d, k];
  });
  return worst;
}

/** Largest distance between the two models' face anchors (meters). */
function anchorGap(a, b) {
  return Math.max(...Object.keys(a.anchors).map((n) => Math.hypot(...a.anchors[n].map((x, k) => x - b.anchors[n][k]))));
}

function contactModel(make) {
  const rig = make();
  try {
    return rig.contactModel();
  } finally {
    rig.free();
  }
}

describe("the skin read from the file (issue 26)", () => {
  for (const body of ["woman", "man", "child"]) {
    for (const version of ["vrm1", "vrm0"]) {
      const name = `${body}-${version}.vrm`;
      it(`${name}: fromVrm's contact model equals restPoseFromVRM's within 1 mm`, async (t) => {
        const vrm = await loadVRM(file(name));
        const rest = restPoseFromVRM(vrm);
        assert.ok(rest.skin && rest.skin.bones.length > 10000, "three-vrm's skin");
        const fromThree = contactModel(() => new HandRig(rest));
        const fromFile = contactModel(() => HandRig.fromVrm(readBytes(file(name))));
        const [d, where] = largestDifference(fromFile, fromThree);
        assert.ok(d < 1e-3, `${name}: ${(d * 1000).toFixed(3)} mm apart at ${where}`);
        // Without a skin the anchors are the bone-based ones, far from these.
        const { skin: _skin, ...bonesOnly } = rest;
        const bare = contactModel(() => new HandRig(bonesOnly));
        const moved = anchorGap(bare, fromFile);
        assert.equal(bare.skin, null, "a rig without a skin says so");
        assert.ok(fromFile.skin && fromFile.skin.samples > 10000, "what the skin taught is reported");
        // The body and the eyes share one vertex buffer: both paths read each vertex once.
        assert.equal(fromThree.skin.samples, fromFile.skin.samples, "the same skin samples");
        for (const r of [...fromFile.skin.fingerRadius, ...fromFile.skin.palmHalfThickness]) {
          assert.ok(r > 0.003 && r < 0.03, `${name}: hand thickness ${r} m`);
        }
        assert.ok(moved > 0.005, `${name}: the skin moved the anchors ${(moved * 1000).toFixed(1)} mm only`);
        t.diagnostic(`${name}: ${(d * 1000).toExponential(2)} mm at most apart (${where}); anchors ${(moved * 1000).toFixed(1)} mm from the bone-based ones`);
      });
    }
    it(`${body}-mixamo.glb: fromGltf's contact model equals the VRM's (fromVrm) within 1 mm`, (t) => {
      const fromGltf = contactModel(() => HandRig.fromGltf(readBytes(file(`${body}-mixamo.glb`))));
      const fromVrm = contactModel(() => HandRig.fromVrm(readBytes(file(`${body}-vrm1.vrm`))));
      const [d, where] = largestDifference(fromGltf, fromVrm);
      assert.ok(d < 1e-3, `${body}: ${(d * 1000).toFixed(3)} mm apart at ${where}`);
      t.diagnostic(`${body}-mixamo.glb: ${(d * 1000).toExponential(2)} mm at most apart (${where})`);
    });
  }
});

describe("restPose.skin from JS", () => {
  it("a vertex on a non-humanoid bone under a humanoid one is marked (its bone index plus 128), as fromVrm reads it", async () => {
    const vrm = await loadVRM(file("woman-vrm1.vrm"));
    const plain = restPoseFromVRM(vrm).skin.bones;
    assert.ok(plain.every((b) => b < 128), "the whole woman is on humanoid bones");
    // Her eyes taken out of the humanoid (as hair or an accessory on bones of its own): their
    // vertices hang on the head.
    const raw = vrm.humanoid.getRawBoneNode.bind(vrm.humanoid);
    vrm.humanoid.getRawBoneNode = (name) => (name === "leftEye" || name === "rightEye" ? null : raw(name));
    const bones = restPoseFromVRM(vrm).skin.bones;
    const head = LAYOUT.bones.indexOf("head");
    const hanging = bones.filter((b) => b >= 128);
    assert.ok(hanging.length > 100, `${hanging.length} vertices hanging`);
    assert.ok(hanging.every((b) => b === (head | 128)), "all on the head");
    assert.equal(bones.length, plain.length);
  });

  it("bad skins get an Error naming the field, and the rig is not made", async () => {
    const rest = restPoseFromVRM(await loadVRM(file("woman-vrm1.vrm")));
    const { skin, ...bones } = rest;
    const cases = [
      [{ positions: [0, 0], bones: [0] }, "restPose.skin.positions"],
      [{ positions: "x", bones: [0] }, "restPose.skin.positions"],
      [{ positions: [0, 0, 0], bones: [99] }, "restPose.skin.bones"],
      [{ positions: [0, 0, 0, 1, 1, 1], bones: [0, 0], triangles: [0, 1, 5] }, "restPose.skin.triangles"],
      [{ positions: [0, NaN, 0], bones: [0] }, "restPose.skin.positions"],
      ["skin", "restPose.skin"],
    ];
    for (const [bad, field] of cases) {
      assert.throws(
        () => new HandRig({ ...bones, skin: bad }),
        (e) => e instanceof Error && e.message.includes(field),
        `${JSON.stringify(bad)} -> ${field}`,
      );
    }
    // Plain arrays work as well as typed arrays.
    const rig = new HandRig({ ...bones, skin: { positions: Array.from(skin.positions), bones: Array.from(skin.bones), triangles: Array.from(skin.triangles) } });
    assert.ok(rig.contactModel().skin.samples > 10000);
    rig.free();
  });
});
