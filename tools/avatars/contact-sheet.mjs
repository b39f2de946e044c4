#!/usr/bin/env node
// A contact sheet of every generated avatar (issue 52): the three human bodies, the stylized
// variants (target/avatars, made here when missing) and the figures (tests/fixtures/avatars/
// figures), each loaded by three + @pixiv/three-vrm in headless Chromium (www/node_modules:
// three, three-vrm, playwright-core; the system /usr/bin/chromium) and drawn at rest from the
// front and from its right side, with what three-vrm read (VRM version, humanoid bones,
// warnings) under each. Exits 1 when an avatar fails to load, has a warning or draws nothing.
//
//   node tools/avatars/contact-sheet.mjs [--out artifacts/screenshots/avatars-contact-sheet.png]
//   node tools/avatars/contact-sheet.mjs --touches
//
// Needs no handrig build. Takes about 30 s.
// --touches (needs pkg/, `make pkg`): the chibi (woman-head2-vrm1) and the figure of primitives
// driven by handrig with default options through its three-vrm adapter over the shared clips
// `eat` (fingertips at the mouth, frame 22: the middle of its labeled face run), `hungry`
// (a curved hand on the chest, frame 36) and `please-fist` (please's flat hand on the chest
// curled into a fist by eval/fist.mjs, frame 35), drawn front and side at that frame into
// artifacts/screenshots/touch-<avatar>-<clip>-<frame>-<front|side>.png.

import fs from "node:fs";
import http from "node:http";
import path from "node:path";
import { createRequire } from "node:module";
import { fileURLToPath, pathToFileURL } from "node:url";

import { DEFAULT_STYLIZED_OUT, FIGURES_OUT, DEFAULT_OUT, figureFileNames, generateStylized, stylizedFileNames } from "./generate.mjs";

const here = path.dirname(fileURLToPath(import.meta.url));
const repo = path.resolve(here, "..", "..");
const www = path.join(repo, "www");
const argv = process.argv.slice(2);
const outArg = argv.indexOf("--out");
const out = path.resolve(outArg >= 0 ? argv[outArg + 1] : path.join(repo, "artifacts", "screenshots", "avatars-contact-sheet.png"));

// Every avatar of issue 52's measurement, by file.
if (!stylizedFileNames().every((n) => fs.existsSync(path.join(DEFAULT_STYLIZED_OUT, n)))) {
  fs.mkdirSync(DEFAULT_STYLIZED_OUT, { recursive: true });
  for (const [n, b] of generateStylized()) fs.writeFileSync(path.join(DEFAULT_STYLIZED_OUT, n), b);
}
const avatars = [
  ...["woman", "man", "child"].map((b) => [`${b}-vrm1`, path.join(DEFAULT_OUT, `${b}-vrm1.vrm`)]),
  ...stylizedFileNames().map((n) => [n.replace(/\.vrm$/, ""), path.join(DEFAULT_STYLIZED_OUT, n)]),
  ...figureFileNames().map((n) => [n.replace(/\.vrm$/, ""), path.join(FIGURES_OUT, n)]),
];

const touches = argv.includes("--touches");
const TOUCHES = [["eat", 22], ["hungry", 36], ["please-fist", 35]];
const TOUCH_AVATARS = ["woman-head2-vrm1", "primitive-vrm1"];
const PAGE = `<!doctype html><html><head><meta charset="utf-8"><link rel="icon" href="data:,">
<script type="importmap">{"imports":{"three":"/m/three/build/three.module.js","three/addons/":"/m/three/examples/jsm/",
"@pixiv/three-vrm":"/m/@pixiv/three-vrm/lib/three-vrm.module.js","handrig":"/handrig/index.js","handrig/three-vrm":"/handrig/three-vrm.js"}}</script></head><body style="margin:0;background:#202329">
<canvas id="sheet"></canvas>
<script type="module">
import * as THREE from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";
import { VRMLoaderPlugin, VRMUtils } from "@pixiv/three-vrm";
const W = 220, H = 330, LABEL = 34;
const gl = document.createElement("canvas");
gl.width = W; gl.height = H;
const renderer = new THREE.WebGLRenderer({ canvas: gl, antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(1); renderer.setSize(W, H, false);
window.__sheet = async (avatars, cols) => {
  const rows = Math.ceil((2 * avatars.length) / cols);
  const sheet = document.getElementById("sheet");
  sheet.width = cols * W; sheet.height = rows * (H + LABEL);
  const g = sheet.getContext("2d");
  g.fillStyle = "#202329"; g.fillRect(0, 0, sheet.width, sheet.height);
  const report = [];
  let cell = 0;
  for (const [name, url] of avatars) {
    const warnings = [];
    const warn = console.warn;
    console.warn = (...a) => warnings.push(a.map(String).join(" "));
    let vrm;
    try {
      const loader = new GLTFLoader();
      loader.register((parser) => new VRMLoaderPlugin(parser));
      vrm = (await loader.loadAsync(url)).userData.vrm;
    } catch (e) {
      report.push({ name, error: String(e) });
      console.warn = warn;
      cell += 2;
      continue;
    }
    console.warn = warn;
    VRMUtils.rotateVRM0(vrm); // VRM 0.x faces -Z: turned to face +Z like VRM 1.0
    const scene = new THREE.Scene();
    scene.background = new THREE.Color(0x202329);
    scene.add(new THREE.HemisphereLight(0xffffff, 0x404050, 2.2));
    const key = new THREE.DirectionalLight(0xffffff, 2.0); key.position.set(1, 2, 3); scene.add(key);
    const fill = new THREE.DirectionalLight(0xffffff, 0.8); fill.position.set(-3, 1, 0.5); scene.add(fill);
    scene.add(vrm.scene);
    vrm.humanoid.resetNormalizedPose();
    vrm.update(0);
    vrm.scene.updateMatrixWorld(true);
    const box = new THREE.Box3().setFromObject(vrm.scene, true);
    const c = box.getCenter(new THREE.Vector3()), s = box.getSize(new THREE.Vector3());
    const bones = Object.keys(vrm.humanoid.humanBones).filter((b) => vrm.humanoid.getRawBoneNode(b));
    const head = vrm.humanoid.getRawBoneNode("head").getWorldPosition(new THREE.Vector3());
    for (const view of ["front", "side"]) {
      const span = view === "front" ? s.x : s.z;
      const half = Math.max(s.y / 2, (span / 2) * (H / W)) * 1.06;
      const cam = new THREE.OrthographicCamera((-half * W) / H, (half * W) / H, half, -half, 0.01, 20);
      if (view === "front") cam.position.set(c.x, c.y, c.z + 5);
      else cam.position.set(c.x - 5, c.y, c.z); // from the avatar's right
      cam.lookAt(c);
      renderer.render(scene, cam);
      const x = (cell % cols) * W, y = Math.floor(cell / cols) * (H + LABEL);
      g.drawImage(gl, x, y);
      const px = g.getImageData(x, y, W, H).data;
      let drawn = 0;
      for (let i = 0; i < px.length; i += 4) if (Math.abs(px[i] - 0x20) + Math.abs(px[i + 1] - 0x23) + Math.abs(px[i + 2] - 0x29) > 30) drawn++;
      g.fillStyle = "#e8e8e8"; g.font = "13px monospace";
      g.fillText(name + (view === "side" ? " (side)" : ""), x + 4, y + H + 14);
      g.fillStyle = "#9aa"; g.font = "11px monospace";
      g.fillText("VRM " + vrm.meta.metaVersion + ", " + bones.length + " bones, " + s.y.toFixed(2) + " m", x + 4, y + H + 28);
      report.push({ name, view, metaVersion: vrm.meta.metaVersion, bones: bones.length, height: s.y, width: s.x, depth: s.z, headY: head.y, drawnPixels: drawn, warnings });
      cell++;
    }
    scene.remove(vrm.scene);
    VRMUtils.deepDispose(vrm.scene);
  }
  return { report, png: sheet.toDataURL("image/png") };
};
// Issue 52's touch pictures: the avatar driven by handrig (defaults) up to \`frame\` of a clip.
window.__touch = async (url, frames, frame) => {
  const { default: init, HandRig } = await import("handrig");
  const { applyToVRM, restPoseFromVRM } = await import("handrig/three-vrm");
  if (typeof init === "function") await init();
  const loader = new GLTFLoader();
  loader.register((parser) => new VRMLoaderPlugin(parser));
  const vrm = (await loader.loadAsync(url)).userData.vrm;
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0x202329);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x404050, 2.2));
  const key = new THREE.DirectionalLight(0xffffff, 2.0); key.position.set(1, 2, 3); scene.add(key);
  const fill = new THREE.DirectionalLight(0xffffff, 0.8); fill.position.set(-3, 1, 0.5); scene.add(fill);
  scene.add(vrm.scene);
  const rig = new HandRig(restPoseFromVRM(vrm));
  let res;
  for (let i = 0; i <= frame; i++) res = rig.solve(frames[i]);
  applyToVRM(vrm, res);
  vrm.humanoid.update();
  vrm.scene.updateMatrixWorld(true);
  rig.free();
  const w = (n) => vrm.humanoid.getNormalizedBoneNode(n).getWorldPosition(new THREE.Vector3());
  const head = w("head"), hips = w("hips");
  const box = new THREE.Box3().setFromObject(vrm.scene, true);
  const top = box.max.y + 0.03, bottom = hips.y - 0.05;
  const c = new THREE.Vector3(head.x, (top + bottom) / 2, head.z + 0.05);
  const half = ((top - bottom) / 2) * 1.05;
  renderer.setSize(480, 480, false);
  const shots = {};
  for (const view of ["front", "side"]) {
    const cam = new THREE.OrthographicCamera(-half, half, half, -half, 0.01, 20);
    if (view === "front") cam.position.set(c.x, c.y, c.z + 5);
    else cam.position.set(c.x - 5, c.y, c.z);
    cam.lookAt(c);
    renderer.render(scene, cam);
    shots[view] = gl.toDataURL("image/png");
  }
  renderer.setSize(W, H, false);
  return { shots, solved: { left: Boolean(res.hands?.left), right: Boolean(res.hands?.right) } };
};
window.__ready = true;
</script></body></html>`;

const files = new Map(avatars.map(([n, f]) => [`/f/${n}.vrm`, f]));
const server = http.createServer((req, res) => {
  const url = decodeURIComponent(new URL(req.url, "http://x").pathname);
  let file = null;
  let type = "application/octet-stream";
  if (url === "/") {
    res.writeHead(200, { "content-type": "text/html" });
    return res.end(PAGE);
  }
  if (url.startsWith("/m/")) {
    file = path.join(www, "node_modules", path.normalize(url.slice(3)).replace(/^(\.\.[/\\])+/, ""));
    if (file.endsWith(".js")) type = "text/javascript";
  } else if (url.startsWith("/handrig/")) {
    file = path.join(repo, "pkg", path.normalize(url.slice(9)).replace(/^(\.\.[/\\])+/, ""));
    if (file.endsWith(".js")) type = "text/javascript";
    if (file.endsWith(".wasm")) type = "application/wasm";
  } else if (files.has(url)) file = files.get(url);
  if (!file || !fs.existsSync(file)) {
    res.writeHead(404);
    return res.end();
  }
  res.writeHead(200, { "content-type": type });
  fs.createReadStream(file).pipe(res);
});
await new Promise((r) => server.listen(0, "127.0.0.1", r));
const require = createRequire(path.join(www, "package.json"));
const { chromium } = require("playwright-core");
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
  headless: true,
  args: ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
    "--disable-sync", "--no-first-run", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"],
});
let failed = 0;
try {
  const page = await browser.newPage();
  const errors = [];
  page.on("pageerror", (e) => errors.push(e.message));
  await page.goto(`http://127.0.0.1:${server.address().port}/`);
  await page.waitForFunction(() => window.__ready === true, null, { timeout: 60_000 });
  if (touches) {
    const shared = path.resolve(process.env.HANDRIG_SHARED || path.join(repo, "..", "shared"));
    for (const [clip, frame] of TOUCHES) {
      const rec = JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", `${clip.replace(/-fist$/, "")}.json`), "utf8"));
      // please-fist: please's chest hand (the signer's right, MediaPipe's "Left") made a fist.
      const recorded = clip.endsWith("-fist") ? (await import("../../eval/fist.mjs")).fistFrames(rec, "Left") : rec.frames;
      const frames = recorded.map((f) => ({ timeMs: f.timeMs, hands: f.hands, pose: f.pose, imageAspect: rec.width / rec.height }));
      for (const a of TOUCH_AVATARS) {
        const r = await page.evaluate(([u, fr, i]) => window.__touch(u, fr, i), [`/f/${a}.vrm`, frames, frame]);
        for (const [view, data] of Object.entries(r.shots)) {
          const file = path.join(path.dirname(out), `touch-${a}-${clip}-${frame}-${view}.png`);
          fs.writeFileSync(file, Buffer.from(data.split(",")[1], "base64"));
          console.log(`${path.relative(repo, file)} (hands solved: ${JSON.stringify(r.solved)})`);
        }
      }
    }
    if (errors.length) (failed++, console.log("page errors:", errors));
    await browser.close();
    server.close();
    process.exit(failed ? 1 : 0);
  }
  const { report, png } = await page.evaluate(
    ([list]) => window.__sheet(list, 8),
    [avatars.map(([n]) => [n, `/f/${n}.vrm`])],
  );
  fs.mkdirSync(path.dirname(out), { recursive: true });
  fs.writeFileSync(out, Buffer.from(png.split(",")[1], "base64"));
  console.log("| avatar | view | VRM | humanoid bones | height m | width m | depth m | head bone y m | drawn px | three-vrm warnings |");
  console.log("| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | --- |");
  for (const r of report) {
    if (r.error) {
      failed++;
      console.log(`| ${r.name} | - | load failed: ${r.error} | | | | | | | |`);
      continue;
    }
    if (r.warnings.length || r.drawnPixels < 2000) failed++;
    console.log(
      `| ${r.name} | ${r.view} | ${r.metaVersion} | ${r.bones} | ${r.height.toFixed(2)} | ${r.width.toFixed(2)} | ${r.depth.toFixed(2)} | ${r.headY.toFixed(2)} | ${r.drawnPixels} | ${r.warnings.join("; ") || "none"} |`,
    );
  }
  if (errors.length) (failed++, console.log("page errors:", errors));
  console.log(`wrote ${path.relative(repo, out)}`);
} finally {
  await browser.close();
  server.close();
}
process.exit(failed ? 1 : 0);
