#!/usr/bin/env node
// Renders the bench clips (issue 47): each clip of motions.mjs on each avatar, frame by frame in
// headless Chromium (three.js + three-vrm on SwiftShader, render-page.js), 640x480 at 30 fps,
// piped as raw RGBA into ffmpeg (libx264, one thread, -bitexact, fixed settings) to
// eval/bench/clips/AVATAR-CLIP.mp4. Writes each frame's SHA-256 (of its RGBA pixels) to
// eval/bench/clips/frames.json, which the determinism test (www/tests/bench-render.test.mjs)
// compares with a fresh rendering.
//
//   node eval/bench/render.mjs [--avatars woman,child] [--clips reach,fist,...] [--png DIR] [--no-video]
//   node eval/bench/render.mjs --legs [--avatars woman,man,child,primitive] [--clips walk,squat,...]
//   node eval/bench/render.mjs --contact [--avatars woman,man,child]
//
// --legs renders the leg clips (LEG_CLIPS: whole body, hips moving) on LEG_AVATARS instead;
// --contact the contact clips (CONTACT_CLIPS: a hand on and before the chest) on CONTACT_AVATARS.
//
// --png DIR also writes every frame as DIR/AVATAR-CLIP-NNN.png (through ffmpeg), --no-video
// renders and hashes only (frames.json is updated either way).

import { spawn } from "node:child_process";
import { createHash } from "node:crypto";
import { existsSync, mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { createRequire } from "node:module";
import { tmpdir } from "node:os";
import { extname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import { parseArgs } from "node:util";
import { CLIPS, CONTACT_CLIPS, FPS, LEG_CLIPS, PITCHED_LEG_CLIPS } from "./motions.mjs";

import { AVATARS, CLIP_DIR, CONTACT_AVATARS, HERE, LEG_AVATARS, REPO, avatarPath, videoFile } from "./common.mjs";

export const WIDTH = 640;
export const HEIGHT = 480;

const TYPES = { ".html": "text/html", ".js": "text/javascript", ".mjs": "text/javascript", ".vrm": "model/gltf-binary", ".wasm": "application/wasm" };

/**
 * Headless Chromium on one of the bench's pages (`/bench/NAME.html`), with the files served from
 * disk through page.route (no server): /bench/ = eval/bench, /node_modules/ = www/node_modules,
 * /avatars/ = tests/fixtures/avatars, /www/ = www, /models/ = ../shared/data/models.
 * Waits until the page sets `window.__benchReady`.
 */
export async function openBenchPage(html) {
  const { chromium } = createRequire(join(REPO, "www", "package.json"))("playwright-core");
  const profile = mkdtempSync(join(tmpdir(), "handrig-bench-"));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
    headless: true,
    viewport: { width: WIDTH, height: HEIGHT },
    args: ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
      "--disable-sync", "--no-first-run", "--disable-quic", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"],
  });
  const page = await context.newPage();
  const errors = [];
  page.on("pageerror", (e) => errors.push(e.message));
  const roots = {
    "/bench/": HERE,
    "/node_modules/": join(REPO, "www", "node_modules"),
    "/avatars/": join(REPO, "tests", "fixtures", "avatars"),
    "/www/": join(REPO, "www"),
    "/models/": resolve(process.env.HANDRIG_SHARED ?? join(REPO, "..", "shared"), "data", "models"),
  };
  await page.route("http://bench.invalid/**", async (route) => {
    const path = new URL(route.request().url()).pathname;
    const prefix = Object.keys(roots).find((p) => path.startsWith(p));
    const file = prefix ? resolve(roots[prefix], `.${decodeURIComponent(path.slice(prefix.length - 1))}`) : null;
    if (!file || !file.startsWith(roots[prefix]) || !existsSync(file)) return route.fulfill({ status: 404, body: "not found" });
    return route.fulfill({ status: 200, contentType: TYPES[extname(file)] ?? "application/octet-stream", body: readFileSync(file) });
  });
  await page.goto(`http://bench.invalid/bench/${html}`);
  await page.waitForFunction(() => window.__benchReady || null, null, { timeout: 120_000 }).catch((e) => {
    throw new Error(`${html} did not start: ${errors.join("; ") || e.message}`);
  });
  const close = async () => {
    await context.close().catch(() => {});
    rmSync(profile, { recursive: true, force: true });
  };
  return { page, errors, close };
}

/** The renderer page (render-page.js). */
export async function openRenderer() {
  const { page, errors, close } = await openBenchPage("render-page.html");
  const userAgent = await page.evaluate(() => navigator.userAgent);
  return {
    page,
    errors,
    /** The Chromium build (its user agent): the frame hashes are those of one build on one machine. */
    browser: /Chrome\/[0-9.]+/.exec(userAgent)?.[0] ?? userAgent,
    async load(avatar) {
      return page.evaluate((u) => window.__bench.load(u), `/avatars/${avatarPath(avatar)}`);
    },
    /** The loaded avatar's rest skeleton for legClipPose. */
    async legRest() {
      return page.evaluate(() => window.__bench.legRest());
    },
    async clip(id) {
      return page.evaluate((c) => window.__bench.clip(c), id);
    },
    /** RGBA pixels of frame i (Buffer, top row first). */
    async frame(i) {
      return Buffer.from(await page.evaluate((k) => window.__bench.frame(k), i), "base64");
    },
    close,
  };
}

export const sha256 = (buf) => createHash("sha256").update(buf).digest("hex");

/** The fixed encoder settings: H.264 (x264, one thread for bit-exact output), yuv420p, CRF 20. */
export const FFMPEG_ENCODE = ["-c:v", "libx264", "-preset", "medium", "-crf", "20", "-pix_fmt", "yuv420p", "-threads", "1",
  "-x264-params", "threads=1:lookahead-threads=1", "-g", "30", "-bitexact", "-flags", "+bitexact", "-fflags", "+bitexact",
  "-map_metadata", "-1", "-movflags", "+faststart"];

function ffmpeg(args) {
  const p = spawn("ffmpeg", ["-v", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgba", "-s", `${WIDTH}x${HEIGHT}`, "-r", String(FPS), "-i", "-", ...args], {
    stdio: ["pipe", "inherit", "inherit"],
  });
  const done = new Promise((res, rej) => p.on("close", (c) => (c === 0 ? res() : rej(new Error(`ffmpeg exited with ${c}`)))));
  return { p, done };
}

async function main() {
  const { values: o } = parseArgs({
    options: { avatars: { type: "string" }, clips: { type: "string" }, png: { type: "string" }, "no-video": { type: "boolean" }, legs: { type: "boolean" }, pitched: { type: "boolean" }, contact: { type: "boolean" } },
  });
  const avatars = (o.avatars ?? (o.legs ? LEG_AVATARS : o.contact ? CONTACT_AVATARS : AVATARS).join(",")).split(",");
  const all = o.legs ? (o.pitched ? PITCHED_LEG_CLIPS : LEG_CLIPS) : o.contact ? CONTACT_CLIPS : CLIPS;
  const clips = o.clips ? o.clips.split(",").map((id) => all.find((c) => c.id === id) ?? (() => { throw new Error(`no clip ${id}`); })()) : all;
  mkdirSync(CLIP_DIR, { recursive: true });
  const hashFile = join(CLIP_DIR, "frames.json");
  const hashes = existsSync(hashFile) ? JSON.parse(readFileSync(hashFile, "utf8")) : { clips: {} };
  const r = await openRenderer();
  const t0 = Date.now();
  try {
    for (const avatar of avatars) {
      await r.load(avatar);
      for (const clip of clips) {
        if (clip.avatar && clip.avatar !== avatar) continue; // a contact clip is its avatar's own
        const name = `${avatar}-${clip.id}`;
        const cam = await r.clip(clip.id);
        const sinks = [];
        if (!o["no-video"]) sinks.push(ffmpeg([...FFMPEG_ENCODE, videoFile(avatar, clip)]));
        if (o.png) {
          mkdirSync(o.png, { recursive: true });
          sinks.push(ffmpeg(["-start_number", "0", join(resolve(o.png), `${name}-%03d.png`)]));
        }
        const frameHashes = [];
        const t1 = Date.now();
        for (let i = 0; i < clip.frames; i++) {
          const px = await r.frame(i);
          frameHashes.push(sha256(px).slice(0, 16));
          for (const s of sinks) if (!s.p.stdin.write(px)) await new Promise((res) => s.p.stdin.once("drain", res));
        }
        for (const s of sinks) s.p.stdin.end();
        await Promise.all(sinks.map((s) => s.done));
        hashes.clips[name] = { avatar, clip: clip.id, kind: clip.kind, frames: clip.frames, fps: FPS, width: WIDTH, height: HEIGHT, camera: cam, rgbaSha256: frameHashes };
        console.log(`${name}: ${clip.frames} frames, ${((Date.now() - t1) / 1000).toFixed(1)} s`);
      }
    }
  } finally {
    await r.close();
  }
  if (r.errors.length) throw new Error(`page errors: ${r.errors.join("; ")}`);
  hashes.note = "SHA-256 (first 16 hex digits) of each rendered frame's RGBA pixels, by eval/bench/render.mjs";
  hashes.browser = r.browser;
  hashes.clips = Object.fromEntries(Object.entries(hashes.clips).sort(([a], [b]) => a.localeCompare(b)));
  writeFileSync(hashFile, `${JSON.stringify(hashes, null, 1)}\n`);
  console.log(`rendered in ${((Date.now() - t0) / 1000).toFixed(1)} s; hashes in ${hashFile}`);
}

if (process.argv[1] && resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  main().catch((e) => {
    console.error(`bench render: ${e.stack ?? e.message}`);
    process.exit(1);
  });
}
