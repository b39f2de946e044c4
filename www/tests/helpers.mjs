// Shared browser-test helpers: the static server on a free port and headless Debian Chromium
// through playwright-core (no browser download: executablePath is the system chromium).

import { execFileSync } from "node:child_process";
import { existsSync, mkdtempSync, mkdirSync, readFileSync, renameSync, rmSync, statSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { dirname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import { chromium } from "playwright-core";
import { findPackageDir, startServer } from "../serve.mjs";

export const WWW = resolve(dirname(fileURLToPath(import.meta.url)), "..");
export const REPO = resolve(WWW, "..");
export const SHARED = process.env.HANDRIG_SHARED ?? resolve(REPO, "..", "shared");
export const SCREENSHOTS = join(REPO, "artifacts", "screenshots");
mkdirSync(SCREENSHOTS, { recursive: true });

export const CHROMIUM = process.env.CHROMIUM ?? "/usr/bin/chromium";

/**
 * Starts the server on a free port and a fresh headless Chromium profile. `fakeCamera`: a
 * .y4m or .mjpeg file Chromium plays as the webcam (looped), with camera access granted; `args`
 * are extra Chromium switches.
 */
export async function launch({ fakeCamera, args = [] } = {}) {
  if (!findPackageDir()) {
    throw new Error("the handrig package is not built: run `make pkg` (node pkg-config/build.mjs) first");
  }
  if (!existsSync(CHROMIUM)) throw new Error(`${CHROMIUM} not found: install Debian's chromium or set CHROMIUM`);
  const srv = await startServer({ port: 0 });
  const profile = mkdtempSync(join(tmpdir(), "handrig-chromium-"));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: CHROMIUM,
    headless: true,
    viewport: { width: 1280, height: 800 },
    args: [
      "--headless",
      "--no-sandbox",
      "--disable-gpu",
      "--disable-quic",
      "--no-first-run",
      "--disable-background-networking",
      "--disable-component-update",
      "--disable-sync",
      // WebGL without a GPU: ANGLE on SwiftShader.
      "--use-angle=swiftshader",
      "--enable-unsafe-swiftshader",
      ...(fakeCamera
        ? [
            "--use-fake-device-for-media-stream",
            "--use-fake-ui-for-media-stream",
            `--use-file-for-fake-video-capture=${fakeCamera}`,
          ]
        : []),
      ...args,
    ],
    ...(fakeCamera ? { permissions: ["camera"] } : {}),
  });
  return {
    url: srv.url,
    context,
    async close() {
      await context.close().catch(() => {});
      await new Promise((r) => srv.server.close(r));
      rmSync(profile, { recursive: true, force: true });
    },
  };
}

/**
 * Opens the demo, collecting console errors and page errors. Waits until the page reports
 * ready (or failed). `query` is appended to the URL (e.g. "?paused").
 */
export async function openDemo(env, query = "?paused") {
  const page = await env.context.newPage();
  const errors = [];
  page.on("console", (m) => {
    if (m.type() === "error") errors.push(`console.error: ${m.text()}`);
  });
  page.on("pageerror", (e) => errors.push(`pageerror: ${e.message}`));
  page.on("requestfailed", (r) => errors.push(`request failed: ${r.url()} ${r.failure()?.errorText}`));
  page.on("response", (r) => {
    if (r.status() >= 400) errors.push(`HTTP ${r.status()}: ${r.url()}`);
  });
  await page.goto(env.url + query);
  await page.waitForFunction(() => window.__handrigDemo && window.__handrigDemo.state !== "loading", null, {
    timeout: 60_000,
  });
  return { page, errors };
}

/**
 * A page of `tests/contact-shots.html` (the avatar posed by a solve, for screenshots), 640 x 640,
 * ready to load an avatar; console errors, page errors and failed requests go into `errors`.
 */
export async function openContactShots(env, errors) {
  const page = await env.context.newPage();
  await page.setViewportSize({ width: 640, height: 640 });
  page.on("console", (m) => m.type() === "error" && errors.push(`console.error: ${m.text()}`));
  page.on("pageerror", (e) => errors.push(`pageerror: ${e.message}`));
  page.on("response", (r) => r.status() >= 400 && errors.push(`HTTP ${r.status()}: ${r.url()}`));
  await page.goto(`${env.url}tests/contact-shots.html`);
  await page.waitForFunction(() => window.__contactShots?.state === "ready", null, { timeout: 60_000 });
  return page;
}

export const shot = (name) => join(SCREENSHOTS, name);

/**
 * Installs (once per page) `globalThis.__handrigRectPixels(b64, rect)`: decodes a base64 PNG in
 * the page (no image library in Node) and returns the RGBA pixels inside `rect` (CSS pixels,
 * clamped to the image) with the clamped width and height.
 */
async function installRectPixels(page) {
  await page.evaluate(() => {
    if (globalThis.__handrigRectPixels) return;
    globalThis.__handrigRectPixels = async (b64, rect) => {
      const img = new Image();
      img.src = `data:image/png;base64,${b64}`;
      await img.decode();
      const c = document.createElement("canvas");
      c.width = img.width;
      c.height = img.height;
      const g = c.getContext("2d", { willReadFrequently: true });
      g.drawImage(img, 0, 0);
      const x = Math.max(0, Math.round(rect.x));
      const y = Math.max(0, Math.round(rect.y));
      const w = Math.min(img.width - x, Math.round(rect.w));
      const h = Math.min(img.height - y, Math.round(rect.h));
      return { data: g.getImageData(x, y, w, h).data, w, h };
    };
  });
}

/**
 * Pixel statistics of a PNG screenshot inside `rect` (CSS pixels, page coordinates): how many
 * pixels differ from the rect's most common colour (the background), how many are saturated
 * (the skeleton is drawn in saturated colours on a grey background), and a hue histogram of the
 * saturated ones in 12 buckets of 30 degrees.
 */
export async function pixelStats(page, png, rect) {
  await installRectPixels(page);
  return page.evaluate(
    async ({ b64, rect }) => {
      const { data: d, w, h } = await globalThis.__handrigRectPixels(b64, rect);
      const counts = new Map();
      for (let i = 0; i < d.length; i += 4) {
        const k = (d[i] << 16) | (d[i + 1] << 8) | d[i + 2];
        counts.set(k, (counts.get(k) ?? 0) + 1);
      }
      let bg = 0;
      let best = -1;
      for (const [k, n] of counts) if (n > best) (best = n), (bg = k);
      const br = bg >> 16, bgG = (bg >> 8) & 255, bb = bg & 255;
      let nonBg = 0;
      let saturated = 0;
      const hues = new Array(12).fill(0);
      for (let i = 0; i < d.length; i += 4) {
        const r = d[i], gg = d[i + 1], b = d[i + 2];
        if (Math.abs(r - br) + Math.abs(gg - bgG) + Math.abs(b - bb) > 24) nonBg++;
        const max = Math.max(r, gg, b), min = Math.min(r, gg, b);
        if (max < 70 || (max - min) / max < 0.4) continue;
        saturated++;
        let hue;
        if (max === r) hue = ((gg - b) / (max - min) + 6) % 6;
        else if (max === gg) hue = (b - r) / (max - min) + 2;
        else hue = (r - gg) / (max - min) + 4;
        hues[Math.floor(hue * 2) % 12]++;
      }
      return { pixels: w * h, distinctColors: counts.size, nonBg, saturated, hues };
    },
    { b64: png.toString("base64"), rect },
  );
}

/** How many pixels inside `rect` differ (sum of |dRGB| > 30) between two PNG screenshots. */
export async function diffPixels(page, pngA, pngB, rect) {
  await installRectPixels(page);
  return page.evaluate(
    async ({ a, b, rect }) => {
      const [pa, pb] = await Promise.all([
        globalThis.__handrigRectPixels(a, rect),
        globalThis.__handrigRectPixels(b, rect),
      ]);
      const da = pa.data, db = pb.data;
      let n = 0;
      for (let i = 0; i < da.length; i += 4) {
        if (Math.abs(da[i] - db[i]) + Math.abs(da[i + 1] - db[i + 1]) + Math.abs(da[i + 2] - db[i + 2]) > 30) n++;
      }
      return n;
    },
    { a: pngA.toString("base64"), b: pngB.toString("base64"), rect },
  );
}

/** Dispatches a DataTransfer drop of `bytes` as file `name` on the page's canvas. */
export async function dropFile(page, bytes, name) {
  await page.evaluate(
    ({ b64, name }) => {
      const bin = Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
      const dt = new DataTransfer();
      dt.items.add(new File([bin], name, { type: "model/gltf-binary" }));
      const target = document.getElementById("view");
      target.dispatchEvent(new DragEvent("dragover", { dataTransfer: dt, bubbles: true, cancelable: true }));
      target.dispatchEvent(new DragEvent("drop", { dataTransfer: dt, bubbles: true, cancelable: true }));
    },
    { b64: Buffer.from(bytes).toString("base64"), name },
  );
}

/** A square rect of half-size `r` around a point, clipped to `bounds`. */
export function around(p, r, bounds) {
  const x0 = Math.max(bounds.x, p.x - r);
  const y0 = Math.max(bounds.y, p.y - r);
  const x1 = Math.min(bounds.x + bounds.w, p.x + r);
  const y1 = Math.min(bounds.y + bounds.h, p.y + r);
  return { x: x0, y: y0, w: Math.max(1, x1 - x0), h: Math.max(1, y1 - y0) };
}

// ---------------------------------------------------------------- fake camera videos

export const FAKE_CAMERA_DIR = join(REPO, "artifacts", "fake-camera");

/** Bits of the frame code burnt into the top-left corner of fake camera videos (plus parity). */
export const CODE_BITS = 12;
/** Size of one code block in pixels of the fake camera video. */
export const CODE_BLOCK = 10;

/**
 * Makes (once; cached in artifacts/fake-camera/) a .y4m file for Chromium's fake camera from
 * segments of real videos, with Debian's ffmpeg: `clips` = [{ file, from, to }] (frame range,
 * `to` exclusive), each scaled to `width` (height keeps the aspect), concatenated, every
 * frame kept and played at `fps` (slower than the source: MediaPipe on software GL processes
 * a few frames a second, so a slower camera gives it more of the motion).
 * Every frame carries its code `clipIndex * 1024 + sourceFrame` in the top-left corner as
 * CODE_BITS + 1 black/white blocks of CODE_BLOCK px (least significant first, then even
 * parity), so a test can tell which source frame MediaPipe was given (decodeFrameCode).
 * Raw y4m is big (width x height x 1.5 bytes a frame): keep clips short.
 */
export function fakeCameraVideo(name, { clips, width = 640, fps = 15 }) {
  if (!clips.length) throw new Error("fakeCameraVideo: no clips");
  mkdirSync(FAKE_CAMERA_DIR, { recursive: true });
  const spec = clips.map((c) => `${c.file.split("/").pop()}:${c.from}-${c.to}`).join("+");
  const out = join(FAKE_CAMERA_DIR, `${name}-${width}w-${fps}fps.y4m`);
  const newest = Math.max(...clips.map((c) => statSync(c.file).mtimeMs));
  if (existsSync(out) && statSync(out).mtimeMs > newest && existsSync(`${out}.spec`) && readSpec(`${out}.spec`) === spec) return out;
  try {
    execFileSync("ffmpeg", ["-version"], { stdio: "ignore" });
  } catch {
    throw new Error("ffmpeg not found: the fake-camera tests convert videos with Debian's ffmpeg (`make setup` installs it)");
  }
  const B = CODE_BLOCK;
  const chains = clips.map((c, i) => {
    const boxes = [`drawbox=x=0:y=0:w=${(CODE_BITS + 1) * B}:h=${B}:color=black:t=fill`];
    // Bit k of the code (clip * 1024 + source frame); n counts frames after trim from 0.
    const code = `(${i * 1024 + c.from}+n)`;
    const bit = (k) => `mod(floor(${code}/${2 ** k}),2)`;
    for (let k = 0; k < CODE_BITS; k++) {
      boxes.push(`drawbox=x=${k * B}:y=0:w=${B}:h=${B}:color=white:t=fill:enable='eq(${bit(k)},1)'`);
    }
    const parity = Array.from({ length: CODE_BITS }, (_, k) => bit(k)).join("+");
    boxes.push(`drawbox=x=${CODE_BITS * B}:y=0:w=${B}:h=${B}:color=white:t=fill:enable='eq(mod(${parity},2),1)'`);
    return (
      `[${i}:v]trim=start_frame=${c.from}:end_frame=${c.to},setpts=PTS-STARTPTS,` +
      `scale=${width}:-2,setsar=1,${boxes.join(",")}[v${i}]`
    );
  });
  const graph = `${chains.join(";")};${clips.map((_, i) => `[v${i}]`).join("")}concat=n=${clips.length}:v=1:a=0,setpts=N/(${fps}*TB)[out]`;
  const tmp = `${out}.tmp`;
  execFileSync(
    "ffmpeg",
    ["-v", "error", "-y", ...clips.flatMap((c) => ["-i", c.file]), "-filter_complex", graph, "-map", "[out]", "-r", String(fps),
      "-pix_fmt", "yuv420p", "-f", "yuv4mpegpipe", tmp],
    { stdio: ["ignore", "ignore", "pipe"] },
  );
  renameSync(tmp, out);
  writeSpec(`${out}.spec`, spec);
  return out;
}

function readSpec(f) {
  return readFileSync(f, "utf8");
}

function writeSpec(f, spec) {
  writeFileSync(f, spec);
}
