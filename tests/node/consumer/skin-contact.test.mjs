// The skin-contact measurement of issue 26 (skin-measure.mjs, used by eval/skin-contact.mjs),
// checked on known cases: three's CPU skinning against a hand-written sum on a pose handrig
// solved, the body parts, the winding number inside/outside (and its fast form against the exact
// one), gaps of hands placed at a known distance from the face, chest and other hand, the depth
// of a point pushed 3 cm into the forehead, the scoring against labels, and the labels' files.
// Not the rig's scores: those are in docs/measurements/2026-12-06-contact.md ("Measured on the skin").

import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";
import { describe, it } from "node:test";

import * as THREE from "three";
import { HandRig } from "handrig";
import { applyToVRM, restPoseFromVRM } from "handrig/three-vrm";
import { repo, shared } from "./support.mjs";
import { SkinBody, figures, labeledClips, loadVrm, readLabels, runClip, score, skinByHand } from "./skin-measure.mjs";

const avatarPath = (n) => path.join(repo, "tests", "fixtures", "avatars", `${n}.vrm`);
const please = JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", "please.json"), "utf8")).frames;

// One avatar per VRM version (0.x faces -Z in three-vrm's scene, 1.0 faces +Z).
const cases = [
  ["woman-vrm1", 1],
  ["man-vrm0", -1],
];
const loaded = new Map();
async function avatar(name) {
  if (!loaded.has(name)) {
    const vrm = await loadVrm(avatarPath(name));
    loaded.set(name, { vrm, body: new SkinBody(vrm) });
  }
  const a = loaded.get(name);
  a.vrm.humanoid.resetNormalizedPose();
  a.vrm.humanoid.update();
  a.vrm.scene.updateMatrixWorld(true);
  a.body.update();
  return a;
}

/** Index of the part's vertex with the largest value of fn(point). */
function argmax(body, part, fn) {
  let best = -1;
  let bestV = -Infinity;
  for (const i of body.vertices[part]) {
    const v = fn(body.point(i));
    if (v > bestV) (bestV = v), (best = i);
  }
  return best;
}

/** Moves the whole hand so that its vertex `from` lands on point `to`. */
function moveHand(body, part, from, to) {
  const p = body.point(from);
  body.translatePart(part, to[0] - p[0], to[1] - p[1], to[2] - p[2]);
}

describe("skin measurement (issue 26)", () => {
  for (const [name, f] of cases) {
    it(`${name}: three's getVertexPosition equals a hand-written skinning sum on a solved pose`, async () => {
      const { vrm, body } = await avatar(name);
      const restRight = body.point(body.vertices.rightHand[0]);
      const rig = new HandRig(restPoseFromVRM(vrm));
      let result;
      for (const fr of please.slice(0, 31)) result = rig.solve({ timeMs: fr.timeMs, hands: fr.hands, pose: fr.pose });
      rig.free();
      assert.ok(applyToVRM(vrm, result) > 20, "bones written");
      vrm.humanoid.update();
      vrm.scene.updateMatrixWorld(true);
      body.update();
      const moved = Math.hypot(...body.point(body.vertices.rightHand[0]).map((x, k) => x - restRight[k]));
      assert.ok(moved > 0.2, `the right hand moved ${moved} m from the T-pose`);
      const v = new THREE.Vector3();
      let worst = 0;
      let checked = 0;
      const mesh = body.meshes[0];
      const skinned = new Set(body.skinned);
      const n = mesh.geometry.attributes.position.count;
      for (let i = 0; i < n; i += 37) {
        skinByHand(mesh, i, v).applyMatrix4(mesh.matrixWorld);
        const p = new THREE.Vector3();
        mesh.getVertexPosition(i, p).applyMatrix4(mesh.matrixWorld);
        worst = Math.max(worst, v.distanceTo(p));
        if (skinned.has(i)) {
          const q = body.point(body.offsets[0] + i);
          worst = Math.max(worst, v.distanceTo(new THREE.Vector3(...q)));
        }
        checked++;
      }
      assert.ok(checked > 300);
      assert.ok(worst < 1e-5, `largest difference ${worst} m`);
      // The skinned right hand's bone sits where handrig's forward kinematics puts it (both in the
      // model's own frame: three-vrm leaves a 0.x model facing -Z, and so does handrig).
      const wrist = vrm.humanoid.getRawBoneNode("rightHand").getWorldPosition(new THREE.Vector3());
      const expected = result.worldPositions.rightHand;
      assert.ok(wrist.distanceTo(new THREE.Vector3(...expected)) < 1e-4, `wrist ${wrist.toArray()} vs ${expected}`);
    });

    it(`${name}: parts by dominant bone: head above the neck, hands on their sides`, async () => {
      const { vrm, body } = await avatar(name);
      const y = (b) => vrm.humanoid.getRawBoneNode(b).getWorldPosition(new THREE.Vector3()).y;
      for (const p of ["head", "chest", "leftHand", "rightHand"]) assert.ok(body.triangles[p].length > 300, `${p} triangles`);
      // (a few head-weighted vertices of the man's jaw line sit just below the neck joint's height)
      const low = body.vertices.head.filter((i) => body.point(i)[1] < y("neck"));
      assert.ok(low.length <= 0.01 * body.vertices.head.length, `${low.length} head vertices below the neck bone`);
      for (const i of low) assert.ok(body.point(i)[1] > y("neck") - 0.05, "head vertex far below the neck bone");
      for (const i of body.vertices.leftHand) assert.ok(f * body.point(i)[0] > 0.5, "left hand vertex not on the left");
      for (const i of body.vertices.rightHand) assert.ok(f * body.point(i)[0] < -0.5, "right hand vertex not on the right");
    });

    it(`${name}: winding number ~1 inside the head and chest, ~0 outside; the fast form agrees`, async () => {
      const { vrm, body } = await avatar(name);
      const at = (b) => vrm.humanoid.getRawBoneNode(b).getWorldPosition(new THREE.Vector3());
      const head = at("head");
      // The surface is open where arms and legs are cut off: inside the torso the number is
      // below 1, still far above the 0.5 that the inside test uses.
      const chest = at("upperChest");
      for (const [p, min] of [[[head.x, head.y + 0.08, head.z + f * 0.04], 0.9], [[chest.x, chest.y, chest.z], 0.75]]) {
        const w = body.windingExact(...p);
        assert.ok(w > min && w < 1.1, `inside ${p}: ${w}`);
      }
      const outside = [
        [head.x, head.y + 0.08, head.z + f * 0.5],
        [head.x + 0.3, head.y, head.z],
        [head.x, head.y + 0.4, head.z],
      ];
      for (const p of outside) assert.ok(Math.abs(body.windingExact(...p)) < 0.05, `outside ${p}: ${body.windingExact(...p)}`);
      // Deterministic points around head and torso, some near the skin.
      let worst = 0;
      let s = 1;
      const rnd = () => ((s = (s * 16807) % 2147483647) / 2147483647) - 0.5;
      for (let k = 0; k < 60; k++) {
        const p = [head.x + 0.5 * rnd(), head.y - 0.3 + 0.7 * rnd(), head.z + 0.4 * rnd()];
        worst = Math.max(worst, Math.abs(body.winding(...p) - body.windingExact(...p)));
      }
      assert.ok(worst < 0.05, `fast vs exact winding number: ${worst}`);
    });

    it(`${name}: hands placed 5 mm from the face and chest and 4 mm from each other measure that gap`, async () => {
      const { body } = await avatar(name);
      // Frontmost face / chest vertex, hand's backmost vertex moved d in front of it: the hand is
      // entirely in front of the plane through that vertex, so the gap is exactly d.
      for (const [part, d] of [["head", 0.005], ["chest", 0.005]]) {
        body.update();
        const front = body.point(argmax(body, part, (p) => f * p[2]));
        const back = argmax(body, "rightHand", (p) => -f * p[2]);
        moveHand(body, "rightHand", back, [front[0], front[1], front[2] + f * d]);
        const m = body.measure();
        assert.ok(Math.abs(m.right[part === "head" ? "face" : "chest"] - d) < 1e-4, `${part}: ${JSON.stringify(m.right)}`);
        assert.equal(m.right.depth, 0, "a hand in front of the body is not inside it");
      }
      body.update();
      const rightMost = body.point(argmax(body, "rightHand", (p) => f * p[0]));
      const leftMost = argmax(body, "leftHand", (p) => -f * p[0]);
      moveHand(body, "leftHand", leftMost, [rightMost[0] + f * 0.004, rightMost[1], rightMost[2]]);
      const m = body.measure();
      assert.ok(Math.abs(m.left.hand - 0.004) < 1e-4 && Math.abs(m.right.hand - 0.004) < 1e-4, JSON.stringify(m));
      body.update();
      assert.ok(body.measure().right.face > 0.3, "at rest the hands are far from the face");
    });

    it(`${name}: a point 3 cm inside the forehead is 3 cm deep; a hand pushed there too`, async () => {
      const { vrm, body } = await avatar(name);
      const eyeY = vrm.humanoid.getRawBoneNode("leftEye").getWorldPosition(new THREE.Vector3()).y;
      const s = argmax(body, "head", (p) => (Math.abs(p[0]) < 0.01 && p[1] > eyeY + 0.035 && p[1] < eyeY + 0.05 ? f * p[2] : -Infinity));
      // Outward normal at s: area-weighted normals of its head triangles, oriented forward.
      const T = body.triangles.head;
      const n = new THREE.Vector3();
      const tri = new THREE.Triangle();
      const tn = new THREE.Vector3();
      for (let t = 0; t < T.length; t += 3) {
        if (T[t] !== s && T[t + 1] !== s && T[t + 2] !== s) continue;
        tri.set(...[0, 1, 2].map((k) => new THREE.Vector3(...body.point(T[t + k]))));
        n.addScaledVector(tri.getNormal(tn), tri.getArea());
      }
      n.normalize();
      if (f * n.z < 0) n.negate();
      assert.ok(f * n.z > 0.8, `forehead normal ${n.toArray()}`);
      const S = new THREE.Vector3(...body.point(s));
      const inner = S.clone().addScaledVector(n, -0.03);
      const outer = S.clone().addScaledVector(n, 0.03);
      assert.ok(Math.abs(body.depthAt(inner.x, inner.y, inner.z) - 0.03) < 0.003, `depth ${body.depthAt(inner.x, inner.y, inner.z)}`);
      assert.equal(body.depthAt(outer.x, outer.y, outer.z), 0);
      const tip = argmax(body, "rightHand", (p) => -f * p[0]); // the fingertip end of a T-pose hand
      moveHand(body, "rightHand", tip, inner.toArray());
      const m = body.measure();
      assert.ok(m.right.depth >= 0.027 && m.right.depth < 0.2, `hand depth ${m.right.depth}`);
      assert.ok(m.right.face < 0.005, `a hand crossing the head's skin has (almost) no gap to it: ${m.right.face}`);
      body.update();
      assert.equal(body.measure().right.depth, 0, "at rest no hand vertex is inside");
    });
  }

  it("runClip drives the avatar frame by frame; score counts labeled hand-frames", async () => {
    const { vrm, body } = await avatar("woman-vrm1");
    const rig = new HandRig(restPoseFromVRM(vrm));
    const frames = please.slice(28, 32);
    const m = runClip({ vrm, body, rig, applyToVRM, frames });
    rig.free();
    assert.equal(m.length, 4);
    for (const x of m) for (const side of ["left", "right"]) for (const k of ["face", "chest", "hand", "depth"]) assert.ok(Number.isFinite(x[side][k]));
    assert.ok(m.every((x) => x.right.tracked), "the right hand is tracked in these frames");
    // The vertex-based gaps against three-mesh-bvh's triangle-to-triangle distance on this pose
    // (the hand at the chest): never below it, at most a millimetre above.
    for (const [a, b] of [["chest", "rightHand"], ["head", "rightHand"], ["leftHand", "rightHand"]]) {
      const tri = body.bvh[a].closestPointToGeometry(body.geometry[b], new THREE.Matrix4(), {}, {}).distance;
      const g = body.gap(a, b);
      assert.ok(g >= tri - 1e-9 && g - tri < 0.001, `${a}-${b}: ${g} vs ${tri}`);
    }
    // Synthetic measures against synthetic labels: counts and shares are exact.
    const g = (face, chest, hand, depth) => ({ face, chest, hand, depth, alignmentError: 0.001, tracked: face < 0.04 });
    const measures = [
      { right: g(0.01, 0.3, 0.5, 0), left: g(0.5, 0.3, 0.5, 0) },
      { right: g(0.05, 0.3, 0.5, 0.02), left: g(0.5, 0.3, 0.5, 0) },
      { right: g(0.3, 0.015, 0.5, 0), left: g(0.5, 0.3, 0.5, 0.005) },
      { right: g(0.3, 0.3, 0.01, 0), left: g(0.01, 0.3, 0.01, 0) },
    ];
    const labels = { right: ["face", "face", "chest", "unsure"], left: ["none", "none", "none", "none"] };
    const fs_ = figures(score(measures, labels));
    assert.deepEqual([fs_.face.n, fs_.face.pct, fs_.chest.n, fs_.chest.pct, fs_.hand.n], [2, 50, 1, 100, 0]);
    assert.deepEqual([fs_.falseTouch.n, fs_.falseTouch.pct], [4, 25]);
    assert.deepEqual([fs_.deep.frames, fs_.deep.pct, fs_.deep.maxMm], [4, 25, 20]);
    assert.equal(fs_.alignmentMedianMm, 1);
    assert.equal(fs_.touchTracked, 100 / 3);
    // Issue 52's face figure: within 2 cm of the face AND the hand no more than 1 cm inside.
    assert.deepEqual([fs_.face.cleanPct, fs_.chest.cleanPct], [50, 100]);
    const sunk = figures(score([{ right: g(0.0, 0.3, 0.5, 0.03), left: g(0.5, 0.3, 0.5, 0) }, measures[0]], { right: ["face", "face"], left: ["none", "none"] }));
    assert.deepEqual([sunk.face.n, sunk.face.pct, sunk.face.cleanPct], [2, 100, 50]);
  });

  it("the visual labels cover every frame of their clips, with known labels", () => {
    const clips = labeledClips(repo);
    assert.deepEqual(clips, ["again", "brother", "eat", "hungry", "please", "sister", "thanks"]);
    const allowed = new Set(["face", "chest", "hand", "none", "unsure"]);
    const seen = new Set();
    for (const c of clips) {
      const l = readLabels(repo, c);
      const n = JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", `${c}.json`), "utf8")).frames.length;
      for (const side of ["left", "right"]) {
        assert.equal(l[side].length, n, `${c} ${side}: ${l[side].length} labels for ${n} frames`);
        for (const x of l[side]) assert.ok(allowed.has(x), `${c}: label ${x}`), seen.add(x);
      }
      // Hand-to-hand contact is labeled on both hands alike.
      l.right.forEach((x, i) => assert.equal(x === "hand", l.left[i] === "hand", `${c} frame ${i}`));
    }
    assert.deepEqual([...seen].sort(), ["chest", "face", "hand", "none", "unsure"]);
  });

  it("the face labels agree with the image landmarks: the right hand within 1/3 head breadth of the face exactly there", () => {
    // Image distance from the signer's right hand (MediaPipe "Left") to the pose's face points
    // (nose, eyes, ears, mouth), in ear-to-ear distances; frames without that hand are skipped.
    let face = 0;
    let none = 0;
    for (const c of labeledClips(repo)) {
      const l = readLabels(repo, c);
      const rec = JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", `${c}.json`), "utf8"));
      rec.frames.forEach((f, i) => {
        const hand = f.hands.find((h) => h.handedness === "Left");
        if (!hand || !f.pose || (l.right[i] !== "face" && l.right[i] !== "none")) return;
        const px = ([x, y]) => [x * rec.width, y * rec.height];
        const P = f.pose.landmarks.map(px);
        const breadth = Math.hypot(P[7][0] - P[8][0], P[7][1] - P[8][1]);
        let d = Infinity;
        for (const h of hand.landmarks.map(px)) for (const q of P.slice(0, 11)) d = Math.min(d, Math.hypot(h[0] - q[0], h[1] - q[1]));
        const near = d / breadth < 1 / 3;
        if (l.right[i] === "face") assert.ok(near, `${c} frame ${i}: labeled face, hand ${(d / breadth).toFixed(2)} head breadths away`), face++;
        else assert.ok(!near, `${c} frame ${i}: labeled none, hand ${(d / breadth).toFixed(2)} head breadths from the face`), none++;
      });
    }
    assert.ok(face >= 30 && none >= 50, `${face} face and ${none} none frames checked`);
  });
});

describe("the near-face frame set of issue 52 (eval/frames/hands-near-face.json)", () => {
  it("equals a fresh build from the shared clips; every frame has both hands within half a head breadth of each other and of the face", async () => {
    const { pathToFileURL } = await import("node:url");
    const nf = await import(pathToFileURL(path.join(repo, "eval", "near-face-frames.mjs")).href);
    const fresh = nf.build();
    const committed = JSON.parse(fs.readFileSync(nf.NEAR_FACE_FILE, "utf8"));
    assert.deepEqual(committed, JSON.parse(JSON.stringify(fresh)), "run node eval/near-face-frames.mjs and commit");
    assert.ok(committed.frames.length >= 20, `${committed.frames.length} frames`);
    for (const f of committed.frames) {
      assert.deepEqual(f.hands.map((h) => h.handedness).sort(), ["Left", "Right"]);
      const n = nf.nearness(f, committed.width, committed.height);
      assert.ok(n.between <= 0.5 && Math.max(...n.face) <= 0.5, JSON.stringify(n));
    }
    // The rig drives both hands on them.
    const rig = new HandRig(restPoseFromVRM(await loadVrm(path.join(repo, "tests", "fixtures", "avatars", "woman-vrm1.vrm"))));
    let both = 0;
    for (const f of committed.frames) {
      const r = rig.solve(f);
      if (r.hands?.left && r.hands?.right) both++;
    }
    rig.free();
    assert.ok(both >= 0.9 * committed.frames.length, `both hands solved on ${both} of ${committed.frames.length} frames`);
  });
});
