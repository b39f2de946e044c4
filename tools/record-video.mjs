#!/usr/bin/env node
// Turns a video into a recording in the shared JSON format (../shared/data, see
// tools/README.md): MediaPipe from npm (@mediapipe/hands or @mediapipe/holistic, models
// included) on every frame, in headless Debian Chromium, through the demo's record page
// (www/record.html, served by www/serve.mjs).
//
//   node tools/record-video.mjs VIDEO [--mode hands|holistic|pose] [--out FILE]
//        [--from N] [--to N] [--fps N] [--cpu | --gpu] [--quiet]
//
// Needs `npm ci --prefix www` (MediaPipe, playwright-core), /usr/bin/chromium (or $CHROMIUM)
// and ffprobe (Debian's ffmpeg): `make setup` installs them.

import { execFileSync } from "node:child_process";
import { mkdtempSync, rmSync, writeFileSync } from "node:fs";
import { createRequire } from "node:module";
import { tmpdir } from "node:os";
import { basename, dirname, extname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import { parseArgs } from "node:util";

const REPO = resolve(dirname(fileURLToPath(import.meta.url)), "..");
const WWW = join(REPO, "www");

const USAGE = `usage: node tools/record-video.mjs VIDEO [options]

  --mode hands|holistic|pose   MediaPipe Hands (hands with world landmarks), Holistic (pose and
                               hands, image landmarks only), or Holistic's pose alone (default hands)
  --out FILE                   where to write the JSON (default: VIDEO's name + "-MODE.json")
  --from N, --to N             frame range [from, to) (default: every frame)
  --fps N                      frame rate (default: the video's, from ffprobe)
  --cpu | --gpu                MediaPipe inference (default: CPU when WebGL is software, as here)
  --quiet                      no progress on stderr`;

function fail(message) {
  console.error(`record-video: ${message}`);
  process.exit(2);
}

/** Frame rate, size and frame count of the first video stream (ffprobe). */
export function probeVideo(file) {
  let out;
  try {
    out = execFileSync(
      "ffprobe",
      ["-v", "error", "-select_streams", "v:0", "-count_frames", "-show_entries",
        "stream=width,height,avg_frame_rate,r_frame_rate,nb_read_frames", "-of", "json", file],
      { encoding: "utf8", stdio: ["ignore", "pipe", "pipe"] },
    );
  } catch (e) {
    if (e.code === "ENOENT") throw new Error("ffprobe not found: install Debian's ffmpeg (`make setup`)");
    throw new Error(`ffprobe cannot read ${file}: ${String(e.stderr || e.message).trim()}`);
  }
  const s = JSON.parse(out).streams?.[0];
  if (!s) throw new Error(`${file} has no video stream`);
  const rate = (r) => {
    const [a, b] = String(r).split("/").map(Number);
    return b ? a / b : a;
  };
  const fps = rate(s.avg_frame_rate) || rate(s.r_frame_rate);
  return { width: s.width, height: s.height, fps, frames: Number(s.nb_read_frames) };
}

/** Re-encodes to H.264 MP4 (for codecs or containers Chromium does not play). */
function transcode(file, dir) {
  const out = join(dir, `${basename(file, extname(file))}.mp4`);
  execFileSync("ffmpeg", ["-v", "error", "-y", "-i", file, "-an", "-c:v", "libx264", "-crf", "12", "-pix_fmt", "yuv420p", out], {
    stdio: ["ignore", "ignore", "pipe"],
  });
  return out;
}

async function record(page, file, options, quiet) {
  await page.setInputFiles("#file", file);
  const timer = quiet
    ? null
    : setInterval(async () => {
        const s = await page.textContent("#status").catch(() => "");
        process.stderr.write(`\r${s}          `);
      }, 2000);
  try {
    return await page.evaluate((o) => window.__recordVideo(o), options);
  } finally {
    if (timer) clearInterval(timer);
    if (!quiet) process.stderr.write("\n");
  }
}

async function main() {
  let args;
  try {
    args = parseArgs({
      allowPositionals: true,
      options: {
        mode: { type: "string", default: "hands" },
        out: { type: "string" },
        from: { type: "string" },
        to: { type: "string" },
        fps: { type: "string" },
        cpu: { type: "boolean" },
        gpu: { type: "boolean" },
        quiet: { type: "boolean" },
        help: { type: "boolean", short: "h" },
      },
    });
  } catch (e) {
    fail(`${e.message}\n${USAGE}`);
  }
  const { values: o, positionals } = args;
  if (o.help) {
    console.log(USAGE);
    return;
  }
  if (positionals.length !== 1) fail(`give one video file\n${USAGE}`);
  const video = resolve(positionals[0]);
  if (!["hands", "holistic", "pose"].includes(o.mode)) fail(`--mode must be hands, holistic or pose, got "${o.mode}"`);
  if (o.cpu && o.gpu) fail("--cpu and --gpu exclude each other");
  const int = (v, name) => {
    if (v === undefined) return undefined;
    const n = Number(v);
    if (!Number.isInteger(n) || n < 0) fail(`${name} must be a frame number (integer >= 0), got "${v}"`);
    return n;
  };
  let info;
  try {
    info = probeVideo(video);
  } catch (e) {
    fail(e.message);
  }
  const fps = o.fps === undefined ? info.fps : Number(o.fps);
  if (!(fps > 0)) fail(`no frame rate: give --fps (ffprobe said ${info.fps})`);
  const from = int(o.from, "--from") ?? 0;
  const to = int(o.to, "--to") ?? info.frames;
  if (!(to > from)) fail(`empty frame range [${from}, ${to}) (the video has ${info.frames} frames)`);
  const out = resolve(o.out ?? `${basename(video, extname(video))}-${o.mode}.json`);

  const { startServer } = await import(join(WWW, "serve.mjs"));
  let chromium;
  try {
    ({ chromium } = createRequire(join(WWW, "package.json"))("playwright-core"));
  } catch {
    fail("playwright-core not installed: run `npm ci --prefix www` (or `make setup`)");
  }
  const srv = await startServer({ port: 0, packageDir: null });
  const profile = mkdtempSync(join(tmpdir(), "handrig-record-"));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
    headless: true,
    args: ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
      "--disable-background-networking", "--disable-component-update", "--disable-sync",
      "--use-angle=swiftshader", "--enable-unsafe-swiftshader"],
  });
  const t0 = Date.now();
  try {
    const page = await context.newPage();
    page.on("pageerror", (e) => console.error(`record-video: page error: ${e.message}`));
    await page.goto(`${srv.url}record.html`);
    const options = { mode: o.mode, fps, from, to, cpu: o.cpu ? true : o.gpu ? false : undefined, source: basename(video) };
    let json;
    try {
      json = await record(page, video, options, o.quiet);
    } catch (e) {
      if (!/cannot be decoded/.test(e.message)) throw e;
      // Chromium does not play this codec or container: H.264 MP4 it plays.
      const tmp = mkdtempSync(join(tmpdir(), "handrig-transcode-"));
      try {
        if (!o.quiet) console.error(`record-video: Chromium cannot decode ${basename(video)}; re-encoding to H.264 with ffmpeg`);
        json = await record(page, transcode(video, tmp), options, o.quiet);
      } finally {
        rmSync(tmp, { recursive: true, force: true });
      }
    }
    writeFileSync(out, json);
    const rec = JSON.parse(json);
    const n = rec.frames.length;
    const hands = rec.frames.filter((f) => f.hands?.length).length;
    const pose = rec.frames.filter((f) => f.pose).length;
    console.log(
      `${out}: ${n} frames (${rec.width}x${rec.height}, ${fps} fps, ${rec.mediapipe}, ${rec.inference}), hands in ${hands}, ` +
        `pose in ${pose}; ${((Date.now() - t0) / 1000).toFixed(1)} s, MediaPipe ${rec.mediapipeMsMedian} ms a frame`,
    );
  } finally {
    await context.close().catch(() => {});
    await new Promise((r) => srv.server.close(r));
    rmSync(profile, { recursive: true, force: true });
  }
}

if (process.argv[1] && resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  main().catch((e) => {
    console.error(`record-video: ${e.message.split("\n")[0]}`);
    process.exit(1);
  });
}
