// End to end on real pixels, hands only: Chromium's fake camera plays the shared hand video
// (../shared/data/video/right-hand.mp4, an un-mirrored right hand opening and closing), the
// demo's webcam mode runs MediaPipe Hands from npm on it for real, and handrig drives the
// avatar. Checked against the shared MediaPipe recording of the same video
// (data/hands/right-hand-video-mediapipe.json): every camera frame carries its source frame
// number (see fakeCameraVideo), so each live result is compared with the recorded landmarks of
// the very frame MediaPipe saw.
//
// Bounded: 104 source frames (196-299: open hand, a half-closed hand, a fist, open again) at
// 15 frames a second, 45 processed frames or 60 s, whichever comes first.

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { join } from "node:path";
import { REPO, SHARED, diffPixels, fakeCameraVideo, launch, openDemo, pixelStats, shot } from "./helpers.mjs";
import { installWebcamLog, landmarkCurl, mean, median, pearson, screenshotAtFrames, sharedFrames, startWebcam, waitForFrames } from "./webcam-support.mjs";
import { readRecording } from "../src/recording-format.js";
import { findPackageDir } from "../serve.mjs";

const FROM = 196;
const TO = 300;
const WIDTH = 640;
const FRAMES = 45;

let env;
let page;
let errors;
let log;
let startMs;
const ref = sharedFrames("data/hands/right-hand-video-mediapipe.json");
// The recorded curl of every source frame: the subject's right hand, labelled "Left".
const refCurl = ref.map((f) => landmarkCurl(f.hands.find((h) => h.handedness === "Left").worldLandmarks));

before(async () => {
  const camera = fakeCameraVideo("right-hand", {
    clips: [{ file: join(SHARED, "data/video/right-hand.mp4"), from: FROM, to: TO }],
    width: WIDTH,
    fps: 15,
  });
  env = await launch({ fakeCamera: camera });
  // On the robot: the page's results are compared with a Node rig on debug-robot.vrm.
  ({ page, errors } = await openDemo(env, "?paused&avatar=robot"));
  await installWebcamLog(page, { width: WIDTH });
  startMs = await startWebcam(page, "hands");
});

after(async () => {
  await env?.close();
});

test("hands mode: MediaPipe Hands from npm tracks the hand in the camera video, nothing in the console errors", async () => {
  const t0 = Date.now();
  log = await waitForFrames(page, FRAMES, 60_000);
  const seconds = (Date.now() - t0) / 1000;
  const w = await page.evaluate(() => window.__handrigDemo.webcam);
  assert.equal(w.mediapipe, "@mediapipe/hands 0.4.1675469240");
  assert.deepEqual(w.size, { width: WIDTH, height: 360 }, "MediaPipe sees the camera video at its own size");
  assert.ok(log.length >= 25, `frames processed in ${seconds.toFixed(0)} s: ${log.length}`);
  const tagged = log.filter((l) => l.tag != null);
  assert.ok(tagged.length >= 0.9 * log.length, `frame codes read on ${tagged.length}/${log.length} frames`);
  for (const l of tagged) assert.ok(l.tag >= FROM && l.tag < TO, `frame code ${l.tag} is a frame of the clip`);
  // The video plays: many distinct source frames were processed, across the clip.
  const distinct = new Set(tagged.map((l) => l.tag));
  assert.ok(distinct.size >= 0.6 * tagged.length, `${distinct.size} distinct source frames`);
  const tracked = log.filter((l) => l.handCount > 0).length;
  assert.ok(tracked >= 0.9 * log.length, `hand tracked on ${tracked}/${log.length} frames`);
  // ... and handrig puts it on the avatar's right hand (un-mirrored camera, default options).
  const right = log.filter((l) => l.right === "solved").length;
  assert.ok(right >= 0.9 * log.length, `avatar's right hand solved on ${right}/${log.length} frames`);
  assert.equal(log.filter((l) => l.left === "solved").length, 0, "the left hand is never driven");
  const mp = median(log.map((l) => l.mediapipeMs));
  const us = median(log.map((l) => l.solveUs));
  assert.ok(mp > 0 && mp < 2000, `MediaPipe ${mp} ms a frame`);
  assert.ok(us > 0 && us < 5000, `handrig ${us} µs a frame`);
  const status = await page.textContent("#webcam-status");
  assert.match(status, /running: @mediapipe\/hands .* frames\/s · MediaPipe \d+ ms · handrig \d+ µs · hands in \d+\/\d+ frames \(of \d+ from the camera\)/);
  // The camera delivered its 15 frames a second meanwhile; MediaPipe took what it could.
  const played = log.at(-1).cameraFrames;
  assert.ok(played >= log.length && played <= 20 * seconds + 30, `${played} camera frames in ${seconds.toFixed(1)} s`);
  console.log(
    `# hands mode: ${tracked} frames tracked / ${log.length} processed / ${played} played by the camera in ${seconds.toFixed(1)} s (start ${startMs} ms); ` +
      `MediaPipe median ${mp.toFixed(0)} ms, handrig median ${us.toFixed(0)} µs a frame`,
  );
  assert.deepEqual(errors, []);
});

test("hands mode: the avatar's fingers follow the video (closed-hand frames bend them, open ones do not)", async () => {
  const pairs = log.filter((l) => l.tag != null && l.right === "solved").map((l) => [refCurl[l.tag], l.curlRight]);
  assert.ok(pairs.length >= 20, `${pairs.length} solved frames with a frame code`);
  const r = pearson(
    pairs.map((p) => p[0]),
    pairs.map((p) => p[1]),
  );
  // Fist frames (the recording's mean finger-joint bend above 60 degrees: 254-281, about 83)
  // and open ones (below 20 degrees; the half-closed frames 207-223 are about 31).
  const fist = pairs.filter((p) => p[0] > 60).map((p) => p[1]);
  const open = pairs.filter((p) => p[0] < 20).map((p) => p[1]);
  console.log(
    `# fingers: r = ${r.toFixed(3)} over ${pairs.length} frames; avatar mean finger bend ${mean(fist).toFixed(1)} deg on ` +
      `${fist.length} fist frames, ${mean(open).toFixed(1)} deg on ${open.length} open frames`,
  );
  assert.ok(fist.length >= 3 && open.length >= 3, `fist ${fist.length} and open ${open.length} frames were processed`);
  assert.ok(r > 0.8, `avatar finger bend follows the recorded one: r = ${r.toFixed(3)}`);
  assert.ok(Math.min(...fist) > Math.max(...open), `every fist frame bends the fingers more than every open frame (${fist} vs ${open})`);
  assert.ok(mean(fist) - mean(open) > 30, `by ${(mean(fist) - mean(open)).toFixed(1)} degrees on average`);
});

test("hands mode: screenshots of an open hand and a fist differ around the avatar's hand", async () => {
  const open = await screenshotAtFrames(page, 226, 250, shot("webcam-hands-open.png"));
  assert.ok(open, "an open-hand frame was shown");
  const fist = await screenshotAtFrames(page, 258, 280, shot("webcam-hands-fist.png"));
  assert.ok(fist, "a fist frame was shown");
  const rects = await page.evaluate(() => window.__handrigDemo.viewRects());
  const changed = await diffPixels(page, open.png, fist.png, rects.with.close);
  assert.ok(changed > 1500, `the hand close-up changed between frames ${open.tag} and ${fist.tag} (${changed} pixels)`);
  // The fingers are drawn (ring: cyan, little: violet; nothing else on the page has those hues).
  const s = await pixelStats(page, fist.png, rects.with.close);
  assert.ok(s.hues[6] >= 10 && s.hues[9] >= 10, `finger pixels in the close-up: ${s.hues}`);
  assert.deepEqual(errors, []);
});

test("hands mode: the live session downloads as a recording in the shared format that handrig replays", async () => {
  await page.click("#record");
  const n0 = await page.evaluate(() => window.__webcamLog.length);
  await page.waitForFunction((n) => window.__webcamLog.length >= n + 12, n0, { timeout: 30_000 });
  await page.click("#record");
  assert.match(await page.textContent("#record-status"), /^recorded \d+ frames/);
  const [download] = await Promise.all([page.waitForEvent("download"), page.click("#download-recording")]);
  assert.match(download.suggestedFilename(), /^handrig-webcam-hands-.*\.json$/);
  const path = join(REPO, "artifacts", "webcam-hands-recording.json");
  await download.saveAs(path);
  const rec = JSON.parse(readFileSync(path, "utf8"));
  const sum = readRecording(rec);
  assert.ok(sum.frames >= 12, `${sum.frames} frames recorded`);
  assert.equal(rec.source, "webcam");
  assert.equal(rec.mode, "hands");
  assert.equal(rec.mediapipe, "@mediapipe/hands 0.4.1675469240");
  assert.equal(rec.width, WIDTH);
  assert.equal(rec.height, 360);
  assert.ok(rec.fps > 0.5 && rec.fps < 60, `fps ${rec.fps}`);
  assert.deepEqual(rec.frames.map((f) => f.frame), rec.frames.map((_, i) => i), "frames numbered from 0");
  assert.equal(rec.frames[0].timeMs, 0);
  assert.ok(sum.framesWithHands >= 0.9 * sum.frames, `hands in ${sum.framesWithHands}/${sum.frames} frames`);
  assert.equal(sum.withWorldHands, sum.hands, "Hands gives world landmarks for every hand");
  assert.equal(sum.framesWithPose, 0, "no pose in hands mode");
  for (const f of rec.frames) for (const h of f.hands) assert.equal(h.handedness, "Left", "the subject's right hand, as MediaPipe labels it");
  // The recorded hands look like the video's: each recorded hand's bend is one the shared
  // recording has somewhere in the clip.
  const clip = refCurl.slice(FROM, TO);
  for (const f of rec.frames) {
    for (const h of f.hands) {
      const c = landmarkCurl(h.worldLandmarks);
      assert.ok(c > Math.min(...clip) - 15 && c < Math.max(...clip) + 15, `frame ${f.frame}: bend ${c.toFixed(0)} deg`);
    }
  }
  // handrig (the built package, in Node) replays the frames as they are.
  const { HandRig } = createRequire(import.meta.url)(findPackageDir());
  const rig = HandRig.fromVrm(readFileSync(join(SHARED, "avatars/debug-robot.vrm")));
  let solved = 0;
  for (const f of rec.frames) if (rig.solve(f).hands.right?.status === "solved") solved++;
  rig.free();
  assert.equal(solved, sum.framesWithHands, "every recorded hand drives the avatar's right hand");
  // The avatar's motion in the same session (the "with" view's results in handrig's
  // MotionRecorder), saved as VRM Animation and BVH.
  const motionFrames = Number((await page.textContent("#record-status")).match(/motion \((\d+) frames\)/)?.[1]);
  assert.equal(motionFrames, sum.frames, "the motion of every recorded frame");
  const [vrmaDownload] = await Promise.all([page.waitForEvent("download"), page.click("#download-vrma")]);
  assert.match(vrmaDownload.suggestedFilename(), /^handrig-webcam-.*\.vrma$/);
  const vrma = readFileSync(await vrmaDownload.path());
  assert.equal(vrma.toString("latin1", 0, 4), "glTF");
  const gltf = JSON.parse(vrma.toString("utf8", 20, 20 + vrma.readUInt32LE(12)));
  assert.equal(gltf.extensions.VRMC_vrm_animation.specVersion, "1.0");
  assert.ok(gltf.extensions.VRMC_vrm_animation.humanoid.humanBones.rightIndexProximal, "the fingers are in the file");
  assert.equal(gltf.accessors[gltf.animations[0].samplers[0].input].count, sum.frames, "one key per recorded frame");
  const [bvhDownload] = await Promise.all([page.waitForEvent("download"), page.click("#download-bvh")]);
  assert.match(bvhDownload.suggestedFilename(), /^handrig-webcam-.*\.bvh$/);
  const bvh = readFileSync(await bvhDownload.path(), "utf8");
  assert.match(bvh, /^HIERARCHY\nROOT hips\n/);
  assert.match(bvh, /\nMOTION\nFrames: \d+\nFrame Time: /);
  await page.click("#webcam-stop");
  assert.equal(await page.evaluate(() => window.__handrigDemo.webcam.running), false);
  assert.deepEqual(errors, []);
});
