// Screenshots of self-contact (issue 26): the generated adult (tests/fixtures/avatars/woman-vrm1.vrm)
// loaded with three + three-vrm (www/tests/contact-shots.html), driven by each labeled shared ASL
// clip through the package's three-vrm adapter (restPoseFromVRM, rig.solve on every frame from
// the start, applyToVRM), and rendered from the front and from the avatar's right at each clip's
// touch frames: per label (face, chest, hand) the middle frame of the clip's longest run of it
// in eval/labels/contact-<clip>.json. Saves
// artifacts/screenshots/contact-<clip>-<frame>-<front|side>.png and prints, per touch, the gap
// between the touching hand's skin and the touched skin (CPU skinning, three's getVertexPosition).

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync, readdirSync } from "node:fs";
import { join } from "node:path";
import { REPO, SHARED, launch, openContactShots, shot } from "./helpers.mjs";

const LABELS = join(REPO, "eval", "labels");
const TOUCHES = ["face", "chest", "hand"];

/** Whether MediaPipe found the signer's `side` hand in a recording frame (not mirrored: "Left" is the signer's right). */
const tracked = (frame, side) => (frame.hands ?? []).some((h) => h.handedness === (side === "right" ? "Left" : "Right"));

/**
 * The touch frames of a labeled clip: per touch label, the middle frame of its longest run on
 * either of the signer's hands, with the sides labeled so at that frame. Where MediaPipe lost
 * one of those hands at the middle frame, the run's frame nearest to it that has them all.
 */
export function touchFrames(labels, rec) {
  const out = [];
  for (const label of TOUCHES) {
    let best = null;
    for (const side of ["right", "left"]) {
      for (const [from, to, l] of labels.segments[side]) {
        if (l === label && (!best || to - from > best.to - best.from)) best = { from, to };
      }
    }
    if (!best) continue;
    const mid = Math.floor((best.from + best.to) / 2);
    const sidesAt = (i) => ["right", "left"].filter((s) => labels[s][i] === label);
    const complete = (i) => sidesAt(i).every((s) => tracked(rec.frames[i], s));
    let frame = mid;
    for (let d = 0; d <= best.to - best.from && !complete(frame); d++) {
      if (mid - d >= best.from && complete(mid - d)) frame = mid - d;
      else if (mid + d <= best.to && complete(mid + d)) frame = mid + d;
    }
    out.push({ label, frame, sides: sidesAt(frame).filter((s) => tracked(rec.frames[frame], s)), run: [best.from, best.to] });
  }
  return out.sort((a, b) => a.frame - b.frame);
}

const clips = readdirSync(LABELS)
  .map((f) => f.match(/^contact-(.+)\.json$/)?.[1])
  .filter(Boolean)
  .sort();

let env;
let page;
const errors = [];

before(async () => {
  env = await launch();
  page = await openContactShots(env, errors);
  const info = await page.evaluate(() => window.__contactShots.load("/avatars/woman-vrm1.vrm"));
  assert.equal(String(info.metaVersion), "1");
  assert.ok(info.meshes > 0, "the generated adult has a skinned body");
});

after(async () => {
  await env?.close();
});

test("the labeled clips have touch frames (face, chest, hand)", () => {
  assert.deepEqual(clips, ["again", "brother", "eat", "hungry", "please", "sister", "thanks"]);
  const all = clips.flatMap((c) =>
    touchFrames(
      JSON.parse(readFileSync(join(LABELS, `contact-${c}.json`), "utf8")),
      JSON.parse(readFileSync(join(SHARED, "data", "asl", `${c}.json`), "utf8")),
    ),
  );
  assert.deepEqual([...new Set(all.map((t) => t.label))].sort(), ["chest", "face", "hand"]);
  for (const t of all) assert.ok(t.sides.length > 0, `a side labeled ${t.label} at frame ${t.frame}`);
});

for (const clip of clips) {
  test(`${clip}: the adult at its touch frames, front and side`, async (t) => {
    const labels = JSON.parse(readFileSync(join(LABELS, `contact-${clip}.json`), "utf8"));
    const rec = JSON.parse(readFileSync(join(SHARED, "data", "asl", `${clip}.json`), "utf8"));
    const imageAspect = rec.width / rec.height;
    const frames = rec.frames.map((f) => ({ timeMs: f.timeMs, hands: f.hands, pose: f.pose, imageAspect }));
    await page.evaluate((frames) => window.__contactShots.start(frames), frames);
    for (const touch of touchFrames(labels, rec)) {
      const r = await page.evaluate((i) => window.__contactShots.advanceTo(i), touch.frame);
      for (const side of touch.sides) {
        const h = r.hands[side];
        assert.ok(h.solved, `${clip} frame ${touch.frame}: the ${side} hand (labeled ${touch.label}) is solved`);
        // What three-vrm shows (its raw bones, which skin the mesh) is what the rig solved.
        assert.ok(h.maxBoneError < 0.005, `${clip} frame ${touch.frame} ${side}: posed bones ${h.maxBoneError} m from the rig's worldPositions`);
      }
      for (const view of ["front", "side"]) {
        await page.evaluate((v) => window.__contactShots.setView(v), view);
        await page.locator("#view").screenshot({ path: shot(`contact-${clip}-${touch.frame}-${view}.png`) });
        for (const side of touch.sides) {
          // The hand is in the picture and drawn: around its projected bone points the pixels
          // are not the background.
          const px = await page.evaluate((s) => window.__contactShots.handPixels(s), side);
          assert.ok(px.points.length >= 16, `${side} hand bones found`);
          assert.ok(
            px.covered >= 0.8 * px.points.length,
            `${clip} frame ${touch.frame} ${view}: ${px.covered} of ${px.points.length} ${side} hand bone points drawn over`,
          );
        }
      }
      for (const side of touch.sides) {
        const g = await page.evaluate(([s, region]) => window.__contactShots.skinGap(s, region), [side, touch.label]);
        assert.ok(g.handVertices > 100 && g.regionVertices > 100, `skin found: ${JSON.stringify(g)}`);
        t.diagnostic(
          `${clip} frame ${touch.frame} (${touch.label}, run ${touch.run.join("-")}) ${side} hand: ` +
            `skin gap to the ${touch.label} ${(g.gap * 1000).toFixed(0)} mm`,
        );
      }
    }
    assert.deepEqual(errors, []);
  });
}
