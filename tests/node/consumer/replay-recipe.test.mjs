// docs/guide/mediapipe-offline.md, "Replaying a recording as a tracker": its block runs as written (saved
// as a module in the consumer project), and what it plays solves as the recorded frames do.

import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";
import { after, describe, it } from "node:test";
import { pathToFileURL } from "node:url";

import { HandRig } from "handrig";
import { codeBlocks, docPage } from "./readme-blocks.mjs";
import { avatars, readBytes, readRecording, shared } from "./support.mjs";

const dir = fs.mkdtempSync(path.join(process.cwd(), "replay-"));
after(() => fs.rmSync(dir, { recursive: true, force: true }));

async function replayModule() {
  const blocks = codeBlocks(docPage("guide/mediapipe-offline.md"), "## Replaying a recording as a tracker");
  assert.equal(blocks.length, 1);
  assert.match(blocks[0], /^\/\/ replay\.mjs/);
  const file = path.join(dir, "replay.mjs");
  fs.writeFileSync(file, blocks[0]);
  return import(pathToFileURL(file).href);
}

describe("docs/guide/mediapipe-offline.md: a recording replayed as a tracker", () => {
  it("the hand recording as HandLandmarker results solves as its frames do", async () => {
    const { replay } = await replayModule();
    const frames = readRecording();
    const tracker = replay(frames);
    const played = HandRig.fromVrm(readBytes(avatars.robot), { mirror: true });
    const direct = HandRig.fromVrm(readBytes(avatars.robot), { mirror: true });
    let hands = 0;
    for (const f of frames) {
      const result = tracker.detectForVideo(null, f.timeMs);
      assert.equal(result.handedness.length, f.hands.length);
      const got = played.solve({ timeMs: f.timeMs, hands: result }, {});
      const want = direct.solve(f, {});
      assert.deepEqual(got.bones, want.bones, `frame ${f.frame}`);
      hands += Object.keys(got.hands).length;
    }
    assert.ok(hands > frames.length / 2, `${hands} hands solved`);
    // It loops: the next call is the first frame again.
    assert.equal(tracker.detectForVideo(null, 1e6).handedness.length, frames[0].hands.length);
    [played, direct].forEach((r) => r.free());
  });

  it("a sign-language clip as HolisticLandmarker results solves as its frames do (hands by the subject's side)", async () => {
    const { replay } = await replayModule();
    const clip = JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", "thanks.json"), "utf8"));
    const tracker = replay(clip, "holistic");
    const played = HandRig.fromVrm(readBytes(avatars.robot));
    const direct = HandRig.fromVrm(readBytes(avatars.robot));
    let compared = 0;
    for (const f of clip.frames) {
      const result = tracker.detectForVideo(null, f.timeMs);
      assert.equal(result.poseWorldLandmarks.length, 1);
      // Frames where Hands gave one label twice have no Holistic counterpart: neither rig sees them.
      if (["Left", "Right"].some((l) => f.hands.filter((h) => h.handedness === l).length > 1)) continue;
      const got = played.solve({ timeMs: f.timeMs, ...result }, {});
      const want = direct.solve({ timeMs: f.timeMs, hands: f.hands.map((h) => ({ ...h, score: 1 })), pose: f.pose }, {});
      assert.deepEqual(got.bones, want.bones, `frame ${f.frame}`);
      compared++;
    }
    assert.ok(compared > clip.frames.length / 2, `${compared} frames compared`);
    [played, direct].forEach((r) => r.free());
  });
});
