// Issue 25's checks of the generated human avatars (tests/fixtures/avatars, made by
// tools/avatars/generate.mjs from MakeHuman's CC0 body): a fresh generation equals the committed
// files; three-vrm loads every .vrm without a warning, with 54 humanoid bones, facing and T-pose
// as VRM asks; the skinned mesh at rest is the bind pose; the Mixamo and Unreal glTF files carry
// their naming, pose and bone rest rotations; docs/guide/avatars.md holds the proportions table.
// (Rest positions against handrig's reader: rest-positions.test.mjs.)

import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";
import { pathToFileURL } from "node:url";
import { describe, it } from "node:test";

import { avatarFiles, loadGltf, loadVRM, repo, threeNormalizedWorldPositions } from "./support.mjs";

const tools = path.join(repo, "tools", "avatars");
const gen = await import(pathToFileURL(path.join(tools, "generate.mjs")));
const { table } = await import(pathToFileURL(path.join(tools, "proportions.mjs")));
const { readGlbJson } = await import(pathToFileURL(path.join(tools, "gltf.mjs")));

const TOLERANCE_M = 1e-5;
const files = avatarFiles();
const vrms = files.filter((f) => f.endsWith(".vrm"));
const base = (f) => path.basename(f);
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const len = (v) => Math.hypot(v[0], v[1], v[2]);
const unit = (v) => v.map((x) => x / len(v));

/** Runs `fn` with console.warn captured; resolves to [result, warnings]. */
async function withWarnings(fn) {
  const warnings = [];
  const saved = console.warn;
  console.warn = (...a) => warnings.push(a.map(String).join(" "));
  try {
    return [await fn(), warnings];
  } finally {
    console.warn = saved;
  }
}

/**
 * Largest distance between each skinned vertex as three.js skins it (SkinnedMesh
 * .getVertexPosition, the bones as they are now) and its stored position; every SkinnedMesh.
 */
async function skinDeviation(root) {
  const THREE = await import("three");
  root.updateMatrixWorld(true);
  const v = new THREE.Vector3();
  let worst = 0;
  let count = 0;
  root.traverse((o) => {
    if (!o.isSkinnedMesh) return;
    const pos = o.geometry.attributes.position;
    for (let i = 0; i < pos.count; i++) {
      o.getVertexPosition(i, v);
      o.localToWorld(v);
      worst = Math.max(worst, Math.hypot(v.x - pos.getX(i), v.y - pos.getY(i), v.z - pos.getZ(i)));
      count++;
    }
  });
  return { worst, count };
}

describe("generated human avatars (tests/fixtures/avatars)", () => {
  it("holds every body in every variant, the whole folder under 25 MB", () => {
    assert.deepEqual(files.map(base).sort(), gen.fileNames().sort());
    const total = files.reduce((s, f) => s + fs.statSync(f).size, 0);
    assert.ok(total < 25e6, `${(total / 1e6).toFixed(1)} MB`);
    for (const f of files) assert.ok(fs.statSync(f).size < 3e6, `${base(f)}: ${fs.statSync(f).size} bytes`);
  });

  it("a fresh generation (tools/avatars/generate.mjs) equals the committed files byte for byte", (t) => {
    const started = performance.now();
    const fresh = gen.generate();
    t.diagnostic(`generated ${fresh.size} files in ${((performance.now() - started) / 1000).toFixed(1)} s`);
    assert.deepEqual([...fresh.keys()].sort(), files.map(base).sort());
    for (const f of files) {
      const same = Buffer.compare(fresh.get(base(f)), fs.readFileSync(f)) === 0;
      assert.ok(same, `${base(f)} differs from a fresh generation: run \`make avatars\` and commit`);
    }
  });

  it("docs/guide/avatars.md holds the proportions table that tools/avatars/proportions.mjs prints", () => {
    const doc = fs.readFileSync(path.join(repo, "docs", "guide", "avatars.md"), "utf8");
    assert.ok(doc.includes(table()), "docs/guide/avatars.md: table out of date: paste `node tools/avatars/proportions.mjs`");
  });

  for (const file of vrms) {
    const vrm0 = base(file).includes("-vrm0");
    it(`${base(file)}: three-vrm loads it without warnings, 54 bones, faces ${vrm0 ? "-Z" : "+Z"}, T-pose, look-at at the eyes`, async () => {
      const [vrm, warnings] = await withWarnings(() => loadVRM(file));
      assert.deepEqual(warnings, [], "three-vrm warnings");
      assert.equal(vrm.meta.metaVersion, vrm0 ? "0" : "1");
      const p = await threeNormalizedWorldPositions(vrm);
      const names = Object.keys(p);
      assert.equal(names.length, 54, `humanoid bones: ${names.length}`);
      const fingers = names.filter((n) => /(Thumb|Index|Middle|Ring|Little)/.test(n));
      assert.equal(fingers.length, 30, "finger bones");
      for (const n of ["leftEye", "rightEye", "upperChest", "leftToes", "rightToes"]) assert.ok(p[n], n);

      // Facing: +Z (VRM 1.0) puts the avatar's left at +X and the eyes in front of the head.
      const f = vrm0 ? -1 : 1;
      assert.ok(f * p.leftHand[0] > 0.3 && f * p.rightHand[0] < -0.3, `hands at x ${p.leftHand[0]}, ${p.rightHand[0]}`);
      assert.ok(f * (p.leftEye[2] - p.head[2]) > 0.03, `eyes in front of the head: ${p.leftEye[2] - p.head[2]}`);
      assert.ok(f * p.leftEye[0] > 0, "left eye on the left");

      // T-pose: each arm straight and level along its side, legs straight down.
      for (const [s, sign] of [["left", f], ["right", -f]]) {
        const upper = unit(sub(p[`${s}LowerArm`], p[`${s}UpperArm`]));
        const lower = unit(sub(p[`${s}Hand`], p[`${s}LowerArm`]));
        const hand = unit(sub(p[`${s}MiddleProximal`], p[`${s}Hand`]));
        for (const [what, d] of [["upper arm", upper], ["forearm", lower], ["hand", hand]]) {
          assert.ok(sign * d[0] > 0.9999, `${s} ${what} along ${sign > 0 ? "+" : "-"}X: ${d.map((x) => x.toFixed(4))}`);
        }
        const leg = unit(sub(p[`${s}Foot`], p[`${s}UpperLeg`]));
        assert.ok(leg[1] < -0.9999, `${s} leg straight down: ${leg.map((x) => x.toFixed(4))}`);
        // Palms down: seen along the arm, the knuckles' line (index minus little) runs forward,
        // level (the knuckles are staggered along the arm, so only its y and z count).
        const across = sub(p[`${s}IndexProximal`], p[`${s}LittleProximal`]);
        const roll = (Math.atan2(across[1], f * across[2]) * 180) / Math.PI;
        assert.ok(Math.abs(roll) < 5, `${s} palm down: knuckle line turned ${roll.toFixed(1)} degrees about the arm`);
      }

      // The look-at offset is the eyes' midpoint relative to the head bone.
      const mid = [0, 1, 2].map((k) => (p.leftEye[k] + p.rightEye[k]) / 2);
      const want = sub(mid, p.head);
      const got = vrm.lookAt.offsetFromHeadBone.toArray();
      assert.ok(len(sub(got, want)) < TOLERANCE_M, `lookAt offset ${got} vs eyes ${want}`);
    });
  }

  for (const file of files) {
    it(`${base(file)}: the skinned mesh at rest is the bind pose (every vertex within 1e-5 m)`, async (t) => {
      let root;
      let turn;
      if (file.endsWith(".vrm")) {
        const vrm = await loadVRM(file);
        vrm.humanoid.resetNormalizedPose();
        vrm.humanoid.update();
        root = vrm.scene;
        turn = () => {
          vrm.humanoid.getNormalizedBoneNode("leftUpperArm").rotation.set(0, 0, -1);
          vrm.humanoid.update();
        };
      } else {
        root = (await loadGltf(file)).scene;
        turn = () => {
          let arm;
          root.traverse((o) => o.isBone && /^(mixamorigLeftArm|upperarm_l)$/.test(o.name) && (arm = o));
          arm.rotateZ(-1);
        };
      }
      const rest = await skinDeviation(root);
      t.diagnostic(`${rest.count} skinned vertices, largest deviation ${rest.worst.toExponential(2)} m`);
      assert.ok(rest.count >= 13000, `skinned vertices: ${rest.count}`);
      assert.ok(rest.worst < TOLERANCE_M, `a vertex moves ${rest.worst} m at rest`);
      // The same measure sees a pose: one turned upper arm moves the arm's vertices.
      turn();
      const moved = await skinDeviation(root);
      assert.ok(moved.worst > 0.2, `turning the left upper arm moved vertices by ${moved.worst} m only`);
    });
  }

  const glbs = files.filter((f) => f.endsWith(".glb"));
  for (const file of glbs) {
    const mixamo = base(file).includes("-mixamo");
    it(`${base(file)}: ${mixamo ? "Mixamo names, T-pose" : "Unreal mannequin names, A-pose"}, no VRM extension, bone rest rotations not identity`, async () => {
      const json = readGlbJson(fs.readFileSync(file));
      assert.equal(json.extensionsUsed, undefined);
      assert.equal(json.extensions, undefined);
      const joints = json.skins[0].joints.map((j) => json.nodes[j]);
      const expected = mixamo
        ? ["mixamorig:Hips", "mixamorig:Spine2", "mixamorig:Neck", "mixamorig:Head", "mixamorig:LeftShoulder", "mixamorig:LeftArm",
           "mixamorig:LeftForeArm", "mixamorig:LeftHand", "mixamorig:LeftHandThumb1", "mixamorig:LeftHandIndex1", "mixamorig:RightHandPinky3",
           "mixamorig:LeftUpLeg", "mixamorig:RightToeBase"]
        : ["root", "pelvis", "spine_03", "neck_01", "head", "clavicle_l", "upperarm_l", "lowerarm_l", "hand_l", "thumb_01_l", "index_01_l",
           "pinky_03_r", "thigh_l", "ball_r"];
      const names = new Set(joints.map((n) => n.name));
      for (const n of expected) assert.ok(names.has(n), `joint ${n}`);
      const fingerJoints = [...names].filter((n) => (mixamo ? /Hand(Thumb|Index|Middle|Ring|Pinky)[123]$/ : /^(thumb|index|middle|ring|pinky)_0[123]_[lr]$/).test(n));
      assert.equal(fingerJoints.length, 30, "finger joints");
      const turned = joints.filter((n) => n.rotation && Math.abs(Math.abs(n.rotation[3]) - 1) > 1e-3).length;
      // As in exports from Blender: bones carry their bone frames (+Y along the bone, a roll);
      // only a bone lined up with its parent (spine segments) may have none.
      assert.ok(turned >= 0.9 * joints.length, `${turned} of ${joints.length} joints have a rest rotation`);

      const gltf = await loadGltf(file);
      gltf.scene.updateMatrixWorld(true);
      const THREE = await import("three");
      const at = (n) => gltf.scene.getObjectByName(n.replace(":", "")).getWorldPosition(new THREE.Vector3()).toArray();
      const [sh, el, wr] = mixamo ? ["mixamorig:LeftArm", "mixamorig:LeftForeArm", "mixamorig:LeftHand"] : ["upperarm_l", "lowerarm_l", "hand_l"];
      const arm = unit(sub(at(wr), at(sh)));
      assert.ok(at(wr)[0] > at(sh)[0], "left arm at +X (faces +Z)");
      const head = at(mixamo ? "mixamorig:Head" : "head");
      assert.ok(head[1] > 1.4 || base(file).startsWith("child"), `head at ${head[1]} m: meters in the scene`);
      if (mixamo) assert.ok(Math.abs(arm[1]) < 1e-4, `T-pose: arm level, ${arm.map((x) => x.toFixed(4))}`);
      else assert.ok(arm[1] < -0.6 && arm[1] > -0.9, `A-pose: arm down about 45 degrees, ${arm.map((x) => x.toFixed(4))}`);
    });
  }
});

// Issue 52: the stylized variants (made at eval time into target/avatars, not committed) and the
// figures of primitives and voxels (committed in tests/fixtures/avatars/figures).
const { readGlb, measure } = await import(pathToFileURL(path.join(tools, "proportions.mjs")));

/** Extents (m) of the rest mesh's vertices whose largest weight is one of `boneNames` (VRM 1.0 humanoid names). */
function partExtent(file, boneNames) {
  const g = readGlb(fs.readFileSync(file));
  const bones = g.json.extensions.VRMC_vrm.humanoid.humanBones;
  const nodes = new Set(boneNames.filter((b) => bones[b]).map((b) => bones[b].node));
  const joints = g.json.skins[0].joints;
  const min = [Infinity, Infinity, Infinity];
  const max = [-Infinity, -Infinity, -Infinity];
  let oneBone = true;
  for (const prim of g.json.meshes[0].primitives) {
    const pos = g.accessor(prim.attributes.POSITION);
    const jt = g.accessor(prim.attributes.JOINTS_0);
    const wt = g.accessor(prim.attributes.WEIGHTS_0);
    for (let i = 0; i < pos.length / 3; i++) {
      if (wt[4 * i] !== 1) oneBone = false;
      if (!nodes.has(joints[jt[4 * i]])) continue;
      for (let k = 0; k < 3; k++) (min[k] = Math.min(min[k], pos[3 * i + k])), (max[k] = Math.max(max[k], pos[3 * i + k]));
    }
  }
  return { size: [0, 1, 2].map((k) => max[k] - min[k]), oneBone };
}
const CHEST = ["chest", "upperChest"];

describe("stylized variants and figures (issue 52)", () => {
  const woman = path.join(repo, "tests", "fixtures", "avatars", "woman-vrm1.vrm");
  const ref = measure(woman);
  const refHead = partExtent(woman, ["head"]).size;
  const refChest = partExtent(woman, CHEST).size;

  it("a fresh generation of the figures equals the committed files", () => {
    const fresh = gen.generateFigures();
    assert.deepEqual([...fresh.keys()], gen.figureFileNames());
    for (const [name, bytes] of fresh) {
      const file = path.join(gen.FIGURES_OUT, name);
      assert.ok(fs.existsSync(file) && Buffer.compare(bytes, fs.readFileSync(file)) === 0, `${name} differs: run make avatars`);
      assert.ok(bytes.length < 300e3, `${name}: ${bytes.length} bytes`);
    }
  });

  it("the figures load in three-vrm without warnings; rigid skin; a sphere head twice the human's, a 1.5x box head without thumbs and distal bones", async (t) => {
    for (const [name, bones, headScale] of [["primitive-vrm1.vrm", 54, 2], ["voxel-vrm1.vrm", 40, 1.5]]) {
      const file = path.join(gen.FIGURES_OUT, name);
      const [vrm, warnings] = await withWarnings(() => loadVRM(file));
      assert.deepEqual(warnings, [], `${name}: three-vrm warnings`);
      const p = await threeNormalizedWorldPositions(vrm);
      assert.equal(Object.keys(p).length, bones, `${name}: humanoid bones`);
      const head = partExtent(file, ["head"]);
      assert.ok(head.oneBone, `${name}: every vertex weighted 1 to one bone`);
      // The head's height against the human's (chin to crown); the grid may round by a cell.
      const ratio = head.size[1] / refHead[1];
      t.diagnostic(`${name}: head height ${ratio.toFixed(3)}x the woman's`);
      assert.ok(Math.abs(ratio - headScale) < 0.1, `${name}: head ${ratio.toFixed(2)}x the woman's`);
      if (bones === 40) {
        assert.ok(!p.leftThumbProximal && !p.rightThumbMetacarpal && !p.leftIndexDistal, "no thumbs, no distal bones");
        assert.ok(p.leftIndexIntermediate && p.rightLittleIntermediate, "intermediate bones kept");
      }
    }
  });

  it("the stylized variants: deterministic, load in three-vrm without warnings (54 bones, T-pose), and change their defining proportion only", async (t) => {
    const a = gen.generateStylized();
    const b = gen.generateStylized({ styles: gen.STYLES.slice(0, 1) });
    assert.deepEqual([...a.keys()], gen.stylizedFileNames());
    assert.equal(Buffer.compare(a.get("woman-head15-vrm1.vrm"), b.get("woman-head15-vrm1.vrm")), 0, "two generations differ");
    const dir = fs.mkdtempSync(path.join((await import("node:os")).tmpdir(), "handrig-stylized-"));
    try {
      for (const [name, bytes] of a) {
        const file = path.join(dir, name);
        fs.writeFileSync(file, bytes);
        const [vrm, warnings] = await withWarnings(() => loadVRM(file));
        assert.deepEqual(warnings, [], `${name}: three-vrm warnings`);
        assert.equal(vrm.meta.metaVersion, name.includes("-vrm0") ? "0" : "1");
        const p = await threeNormalizedWorldPositions(vrm);
        assert.equal(Object.keys(p).length, 54, `${name}: humanoid bones`);
        const f = name.includes("-vrm0") ? -1 : 1;
        const arm = unit(sub(p.leftHand, p.leftUpperArm));
        assert.ok(f * arm[0] > 0.9999, `${name}: T-pose left arm ${arm}`);
        if (name.includes("-vrm0")) continue;
        const m = measure(file);
        const head = partExtent(file, ["head"]).size;
        const chest = partExtent(file, CHEST).size;
        const r = {
          head: head[1] / refHead[1],
          arm: m.arm / ref.arm,
          hand: m.hand / ref.hand,
          chestDepth: chest[2] / refChest[2],
          chestWidth: chest[0] / refChest[0],
        };
        const style = gen.STYLES.find((s) => name.startsWith(`${s.id}-`)).style;
        t.diagnostic(`${name}: ${Object.entries(r).map(([k, x]) => `${k} ${x.toFixed(3)}`).join(", ")} (x the woman's)`);
        const key = { head: "head", arms: "arm", hands: "hand", chestDepth: "chestDepth", chestWidth: "chestWidth" };
        for (const [k, measured] of Object.entries(r)) {
          const styleKey = Object.keys(key).find((s) => key[s] === k);
          const want = style[styleKey] ?? 1;
          // Skin weights blend the change near the joints, so a part's extent follows it
          // within 10%; the other proportions stay within 3%.
          const tol = style[styleKey] ? 0.1 * want : 0.03;
          assert.ok(Math.abs(measured - want) < tol, `${name}: ${k} ${measured.toFixed(3)}x the woman's, want ${want}`);
        }
      }
    } finally {
      fs.rmSync(dir, { recursive: true, force: true });
    }
  });
});
