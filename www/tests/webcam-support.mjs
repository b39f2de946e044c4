// Support for the fake-camera tests (webcam-*.test.mjs): which source frame MediaPipe was
// given (the frame code burnt in by fakeCameraVideo), what the avatar did with it, and the
// reference numbers from the shared recordings.

import { readFileSync } from "node:fs";
import { join } from "node:path";
import { CODE_BITS, CODE_BLOCK, SHARED } from "./helpers.mjs";

export const FINGERS = ["Index", "Middle", "Ring", "Little"];
const SEGMENTS = ["Proximal", "Intermediate", "Distal"];

/**
 * Installs in the page: the demo's `webcamProbe` (reads the frame code off the camera video
 * just before MediaPipe gets it) and `onWebcamFrame` (keeps one compact record per solved
 * live frame in `window.__webcamLog`). The fake camera video is `width` pixels wide.
 */
export async function installWebcamLog(page, { width }) {
  await page.evaluate(
    ({ bits, block, fingers, segments, width }) => {
      const c = document.createElement("canvas");
      const g = c.getContext("2d", { willReadFrequently: true });
      window.__webcamLog = [];
      const d = window.__handrigDemo;
      // Frame code: CODE_BITS blocks then an even-parity block, top-left, least significant first.
      d.webcamProbe = (video) => {
        const k = video.videoWidth / width; // the camera may deliver another size than the file
        const w = Math.round((bits + 1) * block * k);
        const h = Math.max(1, Math.round(block * k));
        if (c.width !== w || c.height !== h) {
          c.width = w;
          c.height = h;
        }
        g.drawImage(video, 0, 0, w, h, 0, 0, w, h);
        const px = g.getImageData(0, 0, w, h).data;
        let code = 0;
        let parity = 0;
        for (let b = 0; b <= bits; b++) {
          const x = Math.floor((b + 0.5) * block * k);
          const i = (Math.floor(h / 2) * w + x) * 4;
          const on = px[i] + px[i + 1] + px[i + 2] > 384 ? 1 : 0;
          if (b < bits) code |= on << b;
          parity ^= on;
        }
        return parity === 0 ? code : null;
      };
      const angle = (q) => (q ? (2 * Math.acos(Math.min(1, Math.abs(q[3]))) * 180) / Math.PI : null);
      const curl = (bones, side) => {
        let s = 0;
        for (const f of fingers) for (const seg of segments) s += angle(bones[`${side}${f}${seg}`]);
        return s / (fingers.length * segments.length);
      };
      const pos = (r, bone) => (r.worldPositions[bone] ? [...r.worldPositions[bone]] : null);
      // The bend of the input hand that drove `side` (image landmarks, x and z in the image's
      // height units), as landmarkCurl measures it: what the avatar's fingers should follow.
      const inputCurl = (frame, result, side) => {
        const i = result?.hands?.[side]?.index;
        const lm = Array.isArray(frame.hands) && i != null && i >= 0 ? frame.hands[i]?.landmarks : null;
        if (!lm || lm.length !== 21) return null;
        const a = frame.imageAspect ?? 1;
        const p = (k) => (Array.isArray(lm[k]) ? [lm[k][0] * a, lm[k][1], lm[k][2] * a] : [lm[k].x * a, lm[k].y, lm[k].z * a]);
        const sub = (u, v) => [u[0] - v[0], u[1] - v[1], u[2] - v[2]];
        const between = (u, v) => {
          const c = (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) / (Math.hypot(...u) * Math.hypot(...v));
          return (Math.acos(Math.max(-1, Math.min(1, c))) * 180) / Math.PI;
        };
        let s = 0;
        for (const base of [5, 9, 13, 17]) {
          const chain = [p(0), p(base), p(base + 1), p(base + 2), p(base + 3)];
          for (let j = 1; j < 4; j++) s += between(sub(chain[j], chain[j - 1]), sub(chain[j + 1], chain[j]));
        }
        return s / 12;
      };
      window.__freezeAt = null;
      window.__frozenTag = null;
      d.onWebcamFrame = (info, frame, result) => {
        const z = window.__freezeAt;
        if (z && info.tag != null && info.tag >= z[0] && info.tag < z[1]) {
          d.pauseWebcam(true);
          window.__frozenTag = info.tag;
          window.__freezeAt = null;
        }
        window.__webcamLog.push({
          tag: info.tag,
          mediapipeMs: info.mediapipeMs,
          solveUs: d.solveUs.with,
          handCount: info.handCount,
          cameraFrames: info.cameraFrames,
          pose: !!frame.pose,
          right: result?.hands?.right?.status ?? null,
          left: result?.hands?.left?.status ?? null,
          curlRight: result ? curl(result.bones, "right") : null,
          curlLeft: result ? curl(result.bones, "left") : null,
          inputCurlRight: inputCurl(frame, result, "right"),
          rightHand: result ? pos(result, "rightHand") : null,
          rightIndexDistal: result ? pos(result, "rightIndexDistal") : null,
          leftHand: result ? pos(result, "leftHand") : null,
          head: result ? pos(result, "head") : null,
          rightUpperArm: result?.bones?.rightUpperArm ? [...result.bones.rightUpperArm] : null,
        });
      };
    },
    { bits: CODE_BITS, block: CODE_BLOCK, fingers: FINGERS, segments: SEGMENTS, width },
  );
}

/** Switches the page to webcam mode `mode` and starts it; resolves once it runs. */
export async function startWebcam(page, mode) {
  await page.check('input[name="source"][value="webcam"]');
  await page.selectOption("#webcam-mode", mode);
  const t0 = Date.now();
  await page.click("#webcam-start");
  await page.waitForFunction(
    () => window.__handrigDemo.webcam.running || /failed/.test(document.getElementById("webcam-status").textContent),
    null,
    { timeout: 60_000 },
  );
  const status = await page.textContent("#webcam-status");
  if (!(await page.evaluate(() => window.__handrigDemo.webcam.running))) throw new Error(`webcam did not start: ${status}`);
  return Date.now() - t0;
}

/** Waits until `n` live frames were solved (or `timeoutMs`), returns the log. */
export async function waitForFrames(page, n, timeoutMs) {
  await page
    .waitForFunction((n) => window.__webcamLog.length >= n, n, { timeout: timeoutMs, polling: 250 })
    .catch(() => {});
  return page.evaluate(() => window.__webcamLog);
}

/**
 * Freezes the live processing right after a frame whose code is in [from, to) is solved (in
 * the page's onWebcamFrame, so no later frame replaces it), takes a screenshot of it and
 * resumes. Returns { png, tag }, or null when no such frame came within `timeoutMs`.
 */
export async function screenshotAtFrames(page, from, to, path, timeoutMs = 30_000) {
  await page.evaluate(
    ([a, b]) => {
      window.__freezeAt = [a, b];
      window.__frozenTag = null;
    },
    [from, to],
  );
  const ok = await page
    .waitForFunction(() => window.__frozenTag != null, null, { timeout: timeoutMs, polling: 50 })
    .then(() => true, () => false);
  await page.evaluate(() => (window.__freezeAt = null));
  if (!ok) {
    await page.evaluate(() => window.__handrigDemo.pauseWebcam(false));
    return null;
  }
  await page.evaluate(() => window.__handrigDemo.nextRender());
  const png = await page.screenshot({ path });
  const tag = await page.evaluate(() => {
    const t = window.__webcamLog.at(-1).tag;
    window.__frozenTag = null;
    window.__handrigDemo.pauseWebcam(false);
    return t;
  });
  return { png, tag };
}

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const angleBetween = (u, v) => {
  const c = (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) / (Math.hypot(...u) * Math.hypot(...v));
  return (Math.acos(Math.max(-1, Math.min(1, c))) * 180) / Math.PI;
};

/**
 * Mean bend of the four fingers' three joints (MCP, PIP, DIP), degrees, from 21 MediaPipe hand
 * landmarks: the angle between consecutive segments (wrist->MCP, MCP->PIP, PIP->DIP, DIP->tip).
 * The same measure as the avatar's mean finger-bone rotation angle: 0 straight, larger bent.
 */
export function landmarkCurl(points) {
  let s = 0;
  for (const base of [5, 9, 13, 17]) {
    const chain = [points[0], points[base], points[base + 1], points[base + 2], points[base + 3]];
    for (let j = 1; j < 4; j++) s += angleBetween(sub(chain[j], chain[j - 1]), sub(chain[j + 1], chain[j]));
  }
  return s / 12;
}

/** A shared recording: the bare frame array (data/hands) or the object form (data/asl). */
export function sharedFrames(rel) {
  const rec = JSON.parse(readFileSync(join(SHARED, rel), "utf8"));
  return Array.isArray(rec) ? rec : rec.frames;
}

export function pearson(xs, ys) {
  const n = xs.length;
  const mx = xs.reduce((a, b) => a + b, 0) / n;
  const my = ys.reduce((a, b) => a + b, 0) / n;
  let sxy = 0;
  let sxx = 0;
  let syy = 0;
  for (let i = 0; i < n; i++) {
    sxy += (xs[i] - mx) * (ys[i] - my);
    sxx += (xs[i] - mx) ** 2;
    syy += (ys[i] - my) ** 2;
  }
  return sxy / Math.sqrt(sxx * syy);
}

export const median = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  return s.length ? s[s.length >> 1] : null;
};

export const mean = (xs) => xs.reduce((a, b) => a + b, 0) / xs.length;
