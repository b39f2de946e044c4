// The mirrored-hand checks through the packed package (issue 27, docs/how-it-works/hands-on-video.md): on
// the real `please` clip the flipped frame 16 is solved from the image landmarks, a hand
// mirrored on purpose without image landmarks is held, and `hands.<side>.confidence` says so
// (the handedness score times 1, 0.6, 0.3); the flat layout names the checks.

import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";
import { describe, it } from "node:test";

import { HandRig, LAYOUT } from "handrig";
import { avatars, readBytes, shared } from "./support.mjs";

const please = JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", "please.json"), "utf8")).frames;
// Un-mirrored video: MediaPipe's "Left" is the signer's right hand, the avatar's right.
const rightHand = (f) => f.hands.find((h) => h.handedness === "Left");

/** `frame` with its right hand's world depth mirrored about the wrist and its image landmarks dropped. */
function mirrored(f) {
  const hands = f.hands.map((h) => {
    if (h !== rightHand(f)) return h;
    const wz = h.worldLandmarks[0][2];
    return { handedness: h.handedness, score: h.score, worldLandmarks: h.worldLandmarks.map(([x, y, z]) => [x, y, 2 * wz - z]) };
  });
  return { timeMs: f.timeMs, hands, pose: f.pose };
}

describe("mirrored hands", () => {
  it("LAYOUT names the checks", () => {
    assert.deepEqual(LAYOUT.handCheck, ["good", "mirrored"]);
    assert.ok(LAYOUT.version >= 8);
  });

  it("holds please frame 16's mirrored hand, with less confidence", () => {
    const rig = HandRig.fromVrm(readBytes(avatars.robot));
    const seen = [];
    for (const f of please) {
      const r = rig.solve({ timeMs: f.timeMs, hands: f.hands, pose: f.pose });
      for (const side of ["left", "right"]) {
        const h = r.hands[side];
        if (!h) continue;
        assert.ok(LAYOUT.handCheck.includes(h.check), h.check);
        assert.ok(h.confidence >= 0 && h.confidence <= 1, `${h.confidence}`);
      }
      seen[f.frame] = r.hands.right && { ...r.hands.right };
    }
    const score = (i) => rightHand(please[i]).score;
    assert.equal(seen[16].check, "mirrored");
    assert.equal(seen[16].status, "held");
    assert.ok(Math.abs(seen[16].confidence - 0.3 * score(16)) < 1e-6, `${seen[16].confidence}`);
    for (const i of [15, 17]) {
      assert.equal(seen[i].check, "good");
      assert.ok(Math.abs(seen[i].confidence - score(i)) < 1e-6, `frame ${i}: ${seen[i].confidence}`);
    }
    rig.free();
  });

  it("holds a mirrored hand without image landmarks for 3 frames, then re-acquires it", () => {
    const rig = HandRig.fromVrm(readBytes(avatars.robot));
    const got = [];
    for (const f of please.slice(0, 30)) {
      const frame = f.frame >= 25 ? mirrored(f) : { timeMs: f.timeMs, hands: f.hands, pose: f.pose };
      const r = rig.solve(frame);
      got[f.frame] = { ...r.hands.right };
    }
    for (const i of [25, 26, 27]) {
      assert.equal(got[i].status, "held", `frame ${i}`);
      assert.equal(got[i].check, "mirrored", `frame ${i}`);
      assert.ok(Math.abs(got[i].confidence - 0.3 * rightHand(please[i]).score) < 1e-6, `frame ${i}`);
    }
    assert.equal(got[28].status, "solved");
    assert.equal(got[28].check, "good");
    assert.equal(got[29].check, "mirrored");
    rig.free();
  });
});
