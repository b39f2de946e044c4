// Duplicate hands and swapped labels through the packed package (issue 27, docs/reference/results.md):
// `hands.<side>.resolved` says what the hand selection resolved on each side: "swapped" on
// the real `thanks` clip (a "Right" hand at the signer's right pose wrist), "duplicate" on the
// hand video (one hand found twice, the copy dropped), "jumped" on a label flipped on purpose
// without a pose; `LAYOUT.handResolved` names the flat codes.

import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";
import { describe, it } from "node:test";

import { HandRig, LAYOUT } from "handrig";
import { avatars, readBytes, readRecording, shared } from "./support.mjs";

const clip = (name) =>
  JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", `${name}.json`), "utf8")).frames;

/** Per frame, `{ left, right }`: each side's `resolved` (undefined: no hand on the side). */
function resolvedOf(frames) {
  const rig = HandRig.fromVrm(readBytes(avatars.robot));
  const got = frames.map((f) => {
    const r = rig.solve(f);
    return {
      left: r.hands.left?.resolved,
      right: r.hands.right?.resolved,
      use: [...r.handUse],
      reassigned: { left: r.hands.left?.reassigned, right: r.hands.right?.reassigned },
    };
  });
  rig.free();
  return got;
}

describe("hand selection", () => {
  it("LAYOUT names the resolutions", () => {
    assert.deepEqual(LAYOUT.handResolved, ["none", "swapped", "jumped", "duplicate"]);
    assert.ok(LAYOUT.version >= 7);
    assert.equal(typeof LAYOUT.output.side.handResolved, "number");
  });

  it("reports the swapped labels of thanks and nothing on clean frames", () => {
    const frames = clip("thanks").map((f) => ({ timeMs: f.timeMs, hands: f.hands, pose: f.pose }));
    const got = resolvedOf(frames);
    const swapped = [];
    got.forEach((g, i) => {
      for (const side of ["left", "right"]) {
        assert.ok(g[side] === undefined || g[side] === null || LAYOUT.handResolved.includes(g[side]), `${g[side]}`);
        if (g[side] === "swapped") {
          swapped.push(`${i}${side[0]}`);
          assert.equal(g.reassigned[side], true);
        }
      }
    });
    // Frames 10, 12 and 37: two "Right" hands, one at the signer's right pose wrist.
    assert.deepEqual(swapped, ["10r", "12r", "37r"]);
    assert.equal(got[20].right ?? got[20].left, null);
  });

  it("drops the hand video's second copy of one hand, keeping the continuous one", () => {
    const frames = readRecording().map((f, i) => ({ timeMs: (i * 1000) / 30, hands: f.hands }));
    const got = resolvedOf(frames);
    const dups = got.flatMap((g, i) => (g.right === "duplicate" ? [i] : []));
    assert.deepEqual(dups, [559, 561, 563, 566]);
    for (const i of dups) {
      assert.equal(got[i].left, undefined, `frame ${i}: the copy is not moved to the free side`);
      assert.ok(got[i].use.includes("duplicate"), `frame ${i}: ${got[i].use}`);
    }
  });

  it("keeps a label flipped for two frames, without a pose, on its side", () => {
    const frames = readRecording()
      .slice(0, 30)
      .map((f, i) => {
        const flip = i === 20 || i === 21;
        const hands = f.hands.map((h) => ({ ...h, handedness: flip ? "Right" : h.handedness }));
        return { timeMs: (i * 1000) / 30, hands };
      });
    const got = resolvedOf(frames);
    for (const i of [20, 21]) {
      assert.equal(got[i].right, "jumped", `frame ${i}`);
      assert.equal(got[i].reassigned.right, true);
      assert.equal(got[i].left, undefined);
    }
    assert.equal(got[22].right, null);
    const trust = HandRig.fromVrm(readBytes(avatars.robot), { handedness: "trust" });
    let r;
    for (const f of frames.slice(0, 21)) r = trust.solve(f);
    assert.equal(r.hands.left?.resolved, null);
    assert.equal(r.hands.right, undefined);
    trust.free();
  });
});
