// The plain three.js recipe of docs/guide/three.md, run as written on the generated Mixamo-named glTF
// avatars (tests/fixtures/avatars/*-mixamo.glb: no VRM extension, bones with rest rotations that
// are not the identity, an `Armature` node turned +90 degrees about X and scaled 0.01): its code
// block is saved as recipe.mjs inside the consumer project (so "three" and "handrig" resolve to
// the installed packages) and imported. On the shared `thanks` clip (pose and both hands), every
// mapped bone of the model must land where handrig's own forward kinematics puts it
// (result.worldPositions), which holds only if the rotations were converted right.

import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";
import { pathToFileURL } from "node:url";
import { describe, it } from "node:test";

import { codeBlocks, docPage } from "./readme-blocks.mjs";
import { avatarFiles, loadGltf, shared } from "./support.mjs";

/** VRM 1.0 humanoid names -> Mixamo bone names (three.js drops the ":" of "mixamorig:"). */
function mixamoNames() {
  const m = { hips: "Hips", spine: "Spine", chest: "Spine1", upperChest: "Spine2", neck: "Neck", head: "Head" };
  for (const s of ["Left", "Right"]) {
    const l = s.toLowerCase();
    Object.assign(m, {
      [`${l}Shoulder`]: `${s}Shoulder`, [`${l}UpperArm`]: `${s}Arm`, [`${l}LowerArm`]: `${s}ForeArm`, [`${l}Hand`]: `${s}Hand`,
      [`${l}UpperLeg`]: `${s}UpLeg`, [`${l}LowerLeg`]: `${s}Leg`, [`${l}Foot`]: `${s}Foot`, [`${l}Toes`]: `${s}ToeBase`,
    });
    const parts = { Thumb: ["Metacarpal", "Proximal", "Distal"], Index: ["Proximal", "Intermediate", "Distal"] };
    parts.Middle = parts.Ring = parts.Little = parts.Index;
    for (const [f, ps] of Object.entries(parts)) {
      ps.forEach((p, i) => (m[`${l}${f}${p}`] = `${s}Hand${f === "Little" ? "Pinky" : f}${i + 1}`));
    }
  }
  return m;
}

const files = avatarFiles(".glb").filter((f) => f.includes("-mixamo"));

describe("docs/guide/three.md: the plain three.js recipe on Mixamo-named glTF avatars", () => {
  it("has the recipe block", () => {
    assert.equal(codeBlocks(docPage("guide/three.md"), "## Plain three.js (a glTF without VRM)").length, 1);
  });

  for (const file of files) {
    it(`${path.basename(file)}: every bone where handrig's forward kinematics puts it`, async () => {
      const [block] = codeBlocks(docPage("guide/three.md"), "## Plain three.js (a glTF without VRM)");
      const dir = fs.mkdtempSync(path.join(process.cwd(), "three-recipe-"));
      try {
        fs.writeFileSync(path.join(dir, "recipe.mjs"), block);
        const { plainRig } = await import(pathToFileURL(path.join(dir, "recipe.mjs")).href);
        const THREE = await import("three");
        const scene = (await loadGltf(file)).scene;
        scene.updateMatrixWorld(true);
        const boneMap = {};
        for (const [name, mixamo] of Object.entries(mixamoNames())) {
          const node = scene.getObjectByName(`mixamorig${mixamo}`);
          if (node) boneMap[name] = node;
        }
        assert.ok(Object.keys(boneMap).length >= 50, `${Object.keys(boneMap).length} bones mapped`);
        const turned = Object.values(boneMap).filter((n) => Math.abs(n.quaternion.w) < 0.9999).length;
        assert.ok(turned > 40, `${turned} bones with a rest rotation: the recipe's conversion is exercised`);
        const { rig, apply } = plainRig(boneMap, { mirror: true });
        const clip = JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", "thanks.json"), "utf8"));
        const at = new THREE.Vector3();
        let worst = 0;
        let moved = 0;
        for (const f of clip.frames) {
          const result = rig.solve({ timeMs: f.timeMs, hands: f.hands, pose: f.pose });
          apply(result);
          scene.updateMatrixWorld(true);
          for (const [name, p] of Object.entries(result.worldPositions)) {
            if (!boneMap[name]) continue;
            boneMap[name].getWorldPosition(at);
            worst = Math.max(worst, Math.hypot(at.x - p[0], at.y - p[1], at.z - p[2]));
          }
          if (result.hands.left || result.hands.right) moved++;
        }
        rig.free();
        assert.ok(moved > clip.frames.length / 2, `${moved} frames with a hand`);
        assert.ok(worst < 1e-5, `largest distance ${worst} m`);
      } finally {
        fs.rmSync(dir, { recursive: true, force: true });
      }
    });
  }
});
