// The "Wrists from a body tracker" recipe of docs/guide/frames.md (linked from the README), run as written on the shared Azure Kinect
// session: its two code blocks are saved as wrists.mjs and main.mjs next to avatar.vrm and
// kinect-upper-body.json (copies), inside the consumer project so that "handrig" resolves to the
// installed package, and imported. The only addition is an export line at the end of main.mjs,
// so the test can see `rig`, `wristsOf` and `results`.
//
// Checked on the robot and the generated VRM 1.0 and 0.x fixtures: every wrist is finite and
// within the avatar arm's reach of its upperArm (the scale maps the user's arm onto the
// avatar's); the arms reach them (within the One Euro filter's lag) where they are clear of
// the avatar's body, and the hands stay out of its body colliders where they are not; the
// avatar's left hand comes to its face around frames
// 130-160 (the session's self-touch), nearer than the right hand and far nearer than in the
// first 100 frames; each hand stays on its own side of the body; with `mirror` it is the right
// hand that comes to the face.

import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";
import { pathToFileURL } from "node:url";
import { describe, it } from "node:test";

import { codeBlocks, docPage } from "./readme-blocks.mjs";
import { avatars, fixtureVrms, shared } from "./support.mjs";

const kinectPath = path.join(shared, "data", "pose", "kinect-upper-body.json");

const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
/** The point of segment a-b nearest p. */
function closestOnSegment(p, a, b) {
  const ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
  const len2 = ab[0] ** 2 + ab[1] ** 2 + ab[2] ** 2;
  const t = len2 > 0 ? Math.min(1, Math.max(0, ((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1] + (p[2] - a[2]) * ab[2]) / len2)) : 0;
  return [a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]];
}

/** Runs the recipe for `vrmFile` (with `mirror` edited into the call when asked). */
async function runRecipe(vrmFile, { mirror = false } = {}) {
  const [wristsJs, mainJs] = codeBlocks(docPage("guide/frames.md"), "## Wrists from a body tracker");
  assert.ok(wristsJs && mainJs, "two code blocks");
  assert.match(wristsJs, /^\/\/ wrists\.mjs/, "the first block is wrists.mjs");
  let main = mainJs;
  if (mirror) {
    // The option the recipe documents, passed the way a user would.
    const call = "calibration: kinect.frames,";
    assert.ok(main.includes(call));
    main = main.replace(call, `${call}\n  mirror: true,`);
  }
  const dir = fs.mkdtempSync(path.join(process.cwd(), "wrists-recipe-"));
  fs.writeFileSync(path.join(dir, "wrists.mjs"), wristsJs);
  fs.writeFileSync(path.join(dir, "main.mjs"), `${main}\nexport { rig, wristsOf, results, kinect };\n`);
  fs.copyFileSync(vrmFile, path.join(dir, "avatar.vrm"));
  fs.copyFileSync(kinectPath, path.join(dir, "kinect-upper-body.json"));
  const cwd = process.cwd();
  process.chdir(dir); // the recipe reads its files relative to the working directory
  try {
    return await import(pathToFileURL(path.join(dir, "main.mjs")).href);
  } finally {
    process.chdir(cwd);
    fs.rmSync(dir, { recursive: true, force: true });
  }
}

const avatarsToRun = [avatars.robot, ...fixtureVrms()];

describe("docs/guide/frames.md: wrists from a body tracker, on the Kinect session", () => {
  it("docs/guide/frames.md has the recipe's two blocks", () => {
    assert.equal(codeBlocks(docPage("guide/frames.md"), "## Wrists from a body tracker").length, 2);
  });

  for (const file of avatarsToRun) {
    it(`${path.basename(file)}: wrists within reach, the left hand at the face in frames 130-160`, async () => {
      const { rig, wristsOf, results, kinect } = await runRecipe(file);
      assert.equal(results.length, kinect.frames.length);
      const rest = rig.restWorldPositions();
      const arm = (s) => dist(rest[`${s}UpperArm`], rest[`${s}LowerArm`]) + dist(rest[`${s}LowerArm`], rest[`${s}Hand`]);
      for (const [i, f] of kinect.frames.entries()) {
        const wrists = wristsOf(f);
        for (const side of ["left", "right"]) {
          const p = wrists[side]?.position;
          assert.ok(p && p.every(Number.isFinite), `frame ${i} ${side}: ${JSON.stringify(p)}`);
          // The user's arm scaled onto the avatar's: within its reach (tracking noise in the
          // user's arm length allowed for).
          assert.ok(dist(p, rest[`${side}UpperArm`]) < 1.1 * arm(side), `frame ${i} ${side}: out of reach`);
        }
      }
      // The arms reach their wrists: the hand joint where the recipe put it, but for the One
      // Euro filter's lag on fast motion (default options) and for self-contact's body
      // colliders, which keep the hand out of the avatar's torso, neck and head (the avatar is
      // at rest here, so the colliders are where `contactModel()` puts them). Where the user's
      // wrist is clear of every collider by more than a hand, the hand reaches it; where it is
      // near or inside one (the user's hand on their belly, at their face), the avatar's hand
      // joint ends outside the colliders.
      const { colliders } = rig.contactModel();
      const shapes = Object.values(colliders);
      assert.ok(shapes.length > 0, "the avatar has body colliders");
      const clearance = (p) =>
        Math.min(
          ...shapes.map((c) => (c.center ? dist(p, c.center) : dist(p, closestOnSegment(p, c.a, c.b))) - c.radius),
        );
      const hand = 0.1 * arm("left");
      const misses = [];
      let near = 0;
      for (const [i, f] of kinect.frames.entries()) {
        const w = wristsOf(f);
        for (const side of ["left", "right"]) {
          const got = results[i].worldPositions[`${side}Hand`];
          if (clearance(w[side].position) > hand) misses.push(dist(got, w[side].position));
          else {
            near++;
            assert.ok(clearance(got) > -0.005, `frame ${i} ${side}: the hand is ${-clearance(got)} m inside a collider`);
          }
        }
      }
      // The session has both: hands away from the body, and hands on it (frames 120-170).
      assert.ok(near > 20 && misses.length > 0.5 * kinect.frames.length, `${near} near the body, ${misses.length} clear`);
      misses.sort((a, b) => a - b);
      const [median, p95] = [misses[misses.length >> 1], misses[Math.floor(0.95 * misses.length)]];
      assert.ok(median < 0.005 && p95 < 0.1 * arm("left"), `hand to wrist: median ${median} m, p95 ${p95} m`);

      const head = (r) => r.worldPositions.head;
      const toHead = (r, side) => dist(r.worldPositions[`${side}Hand`], head(r));
      const touch = results.slice(130, 161);
      const before = results.slice(0, 100);
      const nearest = Math.min(...touch.map((r) => toHead(r, "left")));
      const usual = Math.min(...before.map((r) => toHead(r, "left")));
      assert.ok(nearest < 0.5 * usual, `left hand to head: ${nearest} in 130-160, ${usual} before`);
      for (const r of results.slice(135, 156)) {
        assert.ok(toHead(r, "left") < toHead(r, "right"), "the left hand, not the right, is at the face");
        // At the face the hand is inside the shoulder line, toward the body's midline.
        const inward = Math.abs(r.worldPositions.leftHand[0] - head(r)[0]);
        assert.ok(inward < Math.abs(rest.leftUpperArm[0] - rest.head[0]), "the left hand at the face is inside the shoulder");
      }
      // Each hand on its own side of the body (x relative to the head, the model's own frame).
      const sideSign = (s) => Math.sign(rest[`${s}UpperArm`][0] - rest.head[0]);
      for (const r of before) {
        for (const side of ["left", "right"]) {
          assert.equal(Math.sign(r.worldPositions[`${side}Hand`][0] - head(r)[0]), sideSign(side), `${side} hand crossed over`);
        }
      }
      // The hands are in front of the body: +Z for VRM 1.0, -Z for VRM 0.x (the model's frame).
      const front = rig.vrmVersion === "0" ? -1 : 1;
      const forward = (r, side) => front * (r.worldPositions[`${side}Hand`][2] - rest.hips[2]);
      assert.ok(touch.every((r) => forward(r, "left") > 0), "the left hand at the face is in front of the body");
      rig.free();
    });
  }

  it("with mirror: true the avatar's right hand comes to the face", async () => {
    const { rig, results } = await runRecipe(avatars.robot, { mirror: true });
    const toHead = (r, side) => dist(r.worldPositions[`${side}Hand`], r.worldPositions.head);
    for (const r of results.slice(135, 156)) {
      assert.ok(toHead(r, "right") < toHead(r, "left"), "mirrored: the right hand is at the face");
    }
    rig.free();
  });
});
