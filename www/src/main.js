// handrig demo page: two views of the same avatar driven by the same frame, one rig without
// fingertip alignment (left) and one with the options from the panel (right).
//
// State for the browser tests is exposed as window.__handrigDemo (see the bottom of this file):
// tests read numbers from it instead of scraping the readouts.

import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";
import init, { HandRig, wasmBuild } from "handrig";

import { Avatar, parseVrm } from "./avatar.js";
import { loadRecordings } from "./recording.js";
import { buildOptionsPanel, getPath } from "./options-panel.js";
import { LOCAL_WASM_BASE, Webcam, WebcamStopped, modelSource } from "./webcam.js";
import { RecordingBuilder } from "./recording-format.js";
import { MotionCapture, VrmaPlayer, download } from "./motion-export.js";

const $ = (id) => document.getElementById(id);
const VIEW_KEYS = ["without", "with"];

/**
 * The avatars of the menu: the human bodies generated from MakeHuman's CC0 mesh
 * (tests/fixtures/avatars, made by tools/avatars/generate.mjs; serve.mjs serves them at
 * /avatars/) and the bones-only robot. `?avatar=<id>` picks the first one.
 */
export const AVATARS = [
  { id: "woman", url: "./avatars/woman-vrm1.vrm", label: "adult woman (VRM 1.0)" },
  { id: "man", url: "./avatars/man-vrm1.vrm", label: "adult man (VRM 1.0)" },
  { id: "child", url: "./avatars/child-vrm1.vrm", label: "child (VRM 1.0)" },
  { id: "woman-vrm0", url: "./avatars/woman-vrm0.vrm", label: "adult woman (VRM 0.x)" },
  { id: "man-vrm0", url: "./avatars/man-vrm0.vrm", label: "adult man (VRM 0.x)" },
  { id: "child-vrm0", url: "./avatars/child-vrm0.vrm", label: "child (VRM 0.x)" },
  { id: "robot", url: "./assets/debug-robot.vrm", label: "debug robot (VRM 1.0, bones only)" },
];
const DEFAULT_AVATAR = "woman";
const SOLVE_WINDOW = 60;

const demo = {
  state: "loading",
  error: null,
  // "simd128" or "baseline": the WebAssembly build the package loaded.
  wasmBuild: null,
  source: "recording",
  frame: 0,
  frameCount: 0,
  playing: false,
  renderCount: 0,
  avatarLoads: 0,
  avatar: null,
  options: null,
  optionDescriptions: null,
  results: { without: null, with: null },
  errorMm: { without: { left: null, right: null }, with: { left: null, right: null } },
  shownErrorMm: { without: { left: null, right: null }, with: { left: null, right: null } },
  solveUs: { without: null, with: null },
  jitter: { without: null, with: null },
  solveUsMedian: { without: null, with: null },
  solveErrors: 0,
  // Live webcam mode (see webcam.js): counters since Start, medians over the last 60 frames.
  webcam: {
    mode: null,
    running: false,
    mediapipe: "",
    size: null,
    frames: 0,
    cameraFrames: 0,
    framesWithHands: 0,
    framesWithPose: 0,
    mediapipeMs: null,
    /** Median over the last 60 frames (computed when read: nothing sorted per frame). */
    get mediapipeMsMedian() {
      return mediapipeTimes.length ? median(mediapipeTimes) : null;
    },
    fps: null,
    recordedFrames: 0,
    recording: false,
  },
  // Test and console hooks for the webcam mode (null when unused): `webcamProbe(video)` runs
  // just before each MediaPipe call and its value comes back as `info.tag`;
  // `onWebcamFrame(info, frame, result)` runs after each live frame is solved (`result`: the
  // right view's, reused by the next frame).
  webcamProbe: null,
  onWebcamFrame: null,
};
window.__handrigDemo = demo;

const status = (text, isError = false) => {
  const el = $("status");
  el.textContent = text;
  el.classList.toggle("error", isError);
};

// ---------------------------------------------------------------- rendering

const canvas = $("view");
const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
renderer.setScissorTest(true);

const bodyCamera = new THREE.PerspectiveCamera(30, 1, 0.01, 50);
const controls = new OrbitControls(bodyCamera, canvas);
controls.enableDamping = false;

function makeScene(bg) {
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(bg);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x404050, 2.2));
  const key = new THREE.DirectionalLight(0xffffff, 2.0);
  key.position.set(1, 2, 3);
  scene.add(key);
  const grid = new THREE.GridHelper(4, 40, 0x3a3f4a, 0x2a2e36);
  scene.add(grid);
  return { scene, grid };
}

/** Per view: scene, avatar, rig, close-up camera, last result and timings. */
const views = Object.fromEntries(
  VIEW_KEYS.map((key, i) => [
    key,
    {
      key,
      ...makeScene(i === 0 ? 0x1b1e25 : 0x1d2229),
      closeCamera: new THREE.PerspectiveCamera(35, 1, 0.005, 20),
      avatar: null,
      rig: null,
      result: null,
      times: [],
      jitter: null, // a JitterMeter, made on first use
    },
  ]),
);

let dirty = true;
let renderWaiters = [];
controls.addEventListener("change", () => (dirty = true));

/** Viewport rectangles in CSS pixels (origin top-left): body view on top, hand close-up below. */
function layout() {
  const w = canvas.clientWidth;
  const h = canvas.clientHeight;
  const half = Math.floor(w / 2);
  const bodyH = Math.round(h * 0.56);
  const rects = {};
  VIEW_KEYS.forEach((key, i) => {
    const x = i * half;
    rects[key] = {
      body: { x, y: 0, w: i ? w - half : half, h: bodyH },
      close: { x, y: bodyH, w: i ? w - half : half, h: h - bodyH },
    };
  });
  return rects;
}

function resize() {
  const w = canvas.clientWidth;
  const h = canvas.clientHeight;
  if (canvas.width !== Math.round(w * renderer.getPixelRatio()) || canvas.height !== Math.round(h * renderer.getPixelRatio())) {
    renderer.setSize(w, h, false);
    if (views.with.avatar) frameCamera(views.with.avatar);
  }
  dirty = true;
}
new ResizeObserver(resize).observe(canvas);

/** "front" or "side": where the body camera looks from (the close-ups follow the hand). */
let bodyView = "front";
/** Frame the whole body, feet to head (for legs in view), instead of the upper body. */
let wholeBody = false;

function frameCamera(avatar) {
  const b = avatar.rest.bones;
  const L = avatar.armLength;
  const r = layout().with.body;
  const aspect = r.w > 0 && r.h > 0 ? r.w / r.h : 1;
  const t = Math.tan(THREE.MathUtils.degToRad(bodyCamera.fov / 2));
  // Rest positions in the view's world frame (VRM 0.x models are turned to face the viewer).
  const pts = Object.keys(b).map((n) => avatar.restWorld(n));
  const box = new THREE.Box3().setFromPoints(pts);
  for (const key of VIEW_KEYS) views[key].grid.position.y = box.min.y;
  const lu = b.leftUpperArm && avatar.restWorld("leftUpperArm");
  const ru = b.rightUpperArm && avatar.restWorld("rightUpperArm");
  const upright =
    lu && ru && b.head && b.hips && b.head[1] - b.hips[1] > 0.5 * L && Math.abs(lu.y - ru.y) < 0.1 * L && lu.x > ru.x;
  let cx, cy, halfW, halfH;
  if (wholeBody) {
    // Feet to head, a margin for the head above its joint, a raised foot and the hips moving.
    const c = box.getCenter(new THREE.Vector3());
    const size = box.getSize(new THREE.Vector3());
    cx = c.x;
    cy = c.y + 0.1 * L;
    halfW = size.x / 2 + 0.6 * L;
    halfH = size.y / 2 + 0.45 * L;
  } else if (upright) {
    // Upper body and both arms in the T-pose: centred a bit below the shoulders.
    cx = (lu.x + ru.x) / 2;
    cy = (lu.y + ru.y) / 2 - 0.3 * L;
    halfW = (lu.x - ru.x) / 2 + 1.35 * L;
    halfH = 1.25 * L;
  } else {
    // Anything else (e.g. an armature off the T-pose): the whole rest skeleton.
    const c = box.getCenter(new THREE.Vector3());
    const size = box.getSize(new THREE.Vector3());
    cx = c.x;
    cy = c.y;
    halfW = size.x / 2 + 0.5 * L;
    halfH = size.y / 2 + 0.5 * L;
  }
  if (bodyView === "side") {
    // From the avatar's right (-X; every avatar faces +Z here): the signing hand's side. Wide
    // enough for a hand reaching forward; far enough that the arm pointing at the camera in
    // the T-pose stays in front of the near plane.
    const c = box.getCenter(new THREE.Vector3());
    const depthHalf = box.getSize(new THREE.Vector3()).z / 2 + 0.9 * L;
    const reach = upright && !wholeBody ? cx - ru.x + 1.3 * L : box.getSize(new THREE.Vector3()).x / 2;
    const dist = Math.max(halfH / t, depthHalf / (t * aspect)) + reach;
    bodyCamera.position.set(cx - dist, cy + 0.15 * L, c.z);
    controls.target.set(cx, cy, c.z);
    controls.update();
    return;
  }
  const dist = Math.max(halfH / t, halfW / (t * aspect));
  bodyCamera.position.set(cx, cy + 0.15 * L, dist);
  controls.target.set(cx, cy, 0);
  controls.update();
}

const tmpA = new THREE.Vector3();
const tmpB = new THREE.Vector3();
const tmpC = new THREE.Vector3();

/** Aims a view's close-up camera at the aligned hand (or the right hand). */
function aimCloseUp(view) {
  const av = view.avatar;
  const res = view.result;
  const { finger, point, side } = alignedFocus(res);
  const L = av.armLength;
  // Centre on the hand: between the wrist joint, the avatar's aligned point and the target.
  const center = av.boneWorld(`${side}Hand`, tmpA) ?? av.boneWorld("head", tmpA) ?? tmpA.set(0, 1, 0);
  let spread = 0;
  const shown = av.alignedPointModel(side, finger, point, tmpB);
  if (shown && res?.alignment?.[side]) {
    const target = tmpC.fromArray(res.alignment[side].targetDip);
    spread = shown.distanceTo(target);
    av.vrm.scene.localToWorld(shown);
    av.vrm.scene.localToWorld(target);
    center.multiplyScalar(0.5).addScaledVector(shown, 0.25).addScaledVector(target, 0.25);
  }
  const d = Math.max(0.75 * L, 3 * spread);
  view.closeCamera.position.set(center.x + 0.25 * d, center.y + 0.2 * d, center.z + d);
  view.closeCamera.lookAt(center);
}

function render() {
  const rects = layout();
  const H = canvas.clientHeight;
  for (const key of VIEW_KEYS) {
    const v = views[key];
    if (!v.avatar) continue;
    for (const part of ["body", "close"]) {
      const r = rects[key][part];
      if (r.w <= 0 || r.h <= 0) continue;
      const cam = part === "body" ? bodyCamera : v.closeCamera;
      cam.aspect = r.w / r.h;
      cam.updateProjectionMatrix();
      if (part === "close") aimCloseUp(v);
      // WebGL viewports count from the bottom.
      renderer.setViewport(r.x, H - r.y - r.h, r.w, r.h);
      renderer.setScissor(r.x, H - r.y - r.h, r.w, r.h);
      renderer.render(v.scene, cam);
    }
  }
  demo.renderCount++;
  const waiters = renderWaiters;
  renderWaiters = [];
  for (const w of waiters) w();
}

// ---------------------------------------------------------------- rigs and solving

let panel = null;
let recording = null;
let placement = null;
// With `torso: "pose"`, a rig solving the Kinect body alone: where the torso puts the shoulders
// this frame, to place the Kinect wrists from (see src/recording.js).
let torsoRig = null;
let webcam = null;
let avatarBytes = null;
let avatarName = "";

/** Which side/finger/point the markers and close-up follow. */
function alignedFocus(result) {
  const opts = demo.options ?? {};
  const finger = getPath(opts, "alignment.finger") ?? "index";
  const point = getPath(opts, "alignment.point") ?? "dip";
  let side = "right";
  if (result?.alignment && !result.alignment.right && result.alignment.left) side = "left";
  return { finger, point, side };
}

function optionsFor(key) {
  const o = structuredClone(demo.options ?? {});
  if (key === "without") {
    // The plain view: no fingertip alignment and no self-contact.
    o.alignment = { ...(o.alignment ?? {}), enabled: false };
    o.contact = { ...(o.contact ?? {}), enabled: false };
  }
  return o;
}

function createRigs() {
  for (const key of VIEW_KEYS) {
    const v = views[key];
    v.rig?.free();
    v.rig = null;
    v.times = [];
    v.result = null;
  }
  torsoRig?.free();
  torsoRig = null;
  if (!views.with.avatar) return;
  const rest = views.with.avatar.rest;
  for (const key of VIEW_KEYS) {
    views[key].rig = new HandRig(rest, optionsFor(key));
    // The face anchors self-contact maps onto (with contact.faceAnchors where given).
    views[key].avatar.showContactModel(views[key].rig.contactModel());
  }
  if (getPath(demo.options ?? {}, "torso") === "pose") torsoRig = new HandRig(rest, optionsFor("with"));
  demo.contactModel = views.with.rig.contactModel();
  placement = recording?.placementFor(rest) ?? null;
}

function currentFrame() {
  if (demo.source === "recording") {
    if (!recording) return null;
    const mirror = getPath(demo.options ?? {}, "mirror") === true;
    let shoulders = null;
    if (torsoRig) {
      const p = torsoRig.solve(recording.torsoFrameAt(demo.frame, placement, mirror)).worldPositions;
      shoulders = { left: p.leftUpperArm, right: p.rightUpperArm };
    }
    return recording.frameAt(demo.frame, placement, mirror, shoulders);
  }
  return null;
}

const median = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  return s.length ? s[s.length >> 1] : null;
};

let solveCount = 0;

function solveAndShow(frame) {
  demo.lastFrame = frame; // what the views solved (tests compare the arms with its wrists)
  // Alternate which rig solves first: the first wasm call after a render can be slowed by
  // whatever the renderer left running (software GL on a busy machine), and both timings
  // should see the same conditions.
  const order = solveCount++ % 2 ? [...VIEW_KEYS].reverse() : VIEW_KEYS;
  for (const key of order) {
    const v = views[key];
    if (!v.rig || !v.avatar) continue;
    let result = null;
    const t0 = performance.now();
    try {
      result = v.rig.solve(frame);
    } catch (e) {
      demo.solveErrors++;
      status(`solve failed: ${e.message}`, true);
      console.warn("handrig solve failed:", e);
    }
    const us = (performance.now() - t0) * 1000;
    v.result = result;
    v.times.push(us);
    if (v.times.length > SOLVE_WINDOW) v.times.shift();
    demo.results[key] = result;
    demo.solveUs[key] = us;
    demo.solveUsMedian[key] = median(v.times);
    v.avatar.apply(result);
    v.avatar.updateSkeleton();
    v.jitter ??= new JitterMeter();
    demo.jitter[key] = v.jitter.push(result);
    const { finger, point } = alignedFocus(result);
    const shown = v.avatar.updateMarkers(result, finger, point);
    for (const side of ["left", "right"]) {
      const al = result?.alignment?.[side];
      // error is null when nothing was aligned (e.g. the avatar has no such finger).
      demo.errorMm[key][side] = al && Number.isFinite(al.error) ? al.error * 1000 : null;
      demo.shownErrorMm[key][side] = shown[side] == null ? null : shown[side] * 1000;
    }
  }
  demo.result = demo.results.with;
  updateReadouts();
}

/**
 * Jitter readout: mean angular acceleration of the right hand's bones (degrees per frame²,
 * the angle of the change of each bone's frame-to-frame rotation) over the last 60 frames.
 * Toggle `filter.enabled` in the panel to see the One Euro filter's effect.
 */
class JitterMeter {
  constructor() {
    this.prev = new Map(); // bone -> [q0, q1]
    this.values = [];
    this.d1 = new THREE.Quaternion();
    this.d2 = new THREE.Quaternion();
    this.q = new THREE.Quaternion();
  }

  push(result) {
    const bones = result?.bones;
    if (!bones || !result.hands?.right) return this.mean();
    let sum = 0;
    let n = 0;
    for (const name of JITTER_BONES) {
      const q = bones[name];
      if (!q) continue;
      let hist = this.prev.get(name);
      if (!hist) this.prev.set(name, (hist = [new THREE.Quaternion(), new THREE.Quaternion(), 0]));
      const [q0, q1] = hist;
      if (hist[2] >= 2) {
        this.d1.copy(q0).invert().multiply(q1);
        this.q.set(q[0], q[1], q[2], q[3]);
        this.d2.copy(q1).invert().multiply(this.q);
        sum += (this.d1.invert().multiply(this.d2).angleTo(IDENTITY) * 180) / Math.PI;
        n++;
      }
      q0.copy(q1);
      q1.set(q[0], q[1], q[2], q[3]);
      hist[2] = Math.min(hist[2] + 1, 2);
    }
    if (n > 0) {
      this.values.push(sum / n);
      if (this.values.length > SOLVE_WINDOW) this.values.shift();
    }
    return this.mean();
  }

  mean() {
    return this.values.length ? this.values.reduce((a, b) => a + b, 0) / this.values.length : null;
  }
}
const IDENTITY = new THREE.Quaternion();
const JITTER_BONES = ["rightHand", ...["Thumb", "Index", "Middle", "Ring", "Little"].flatMap((f) =>
  (f === "Thumb" ? ["Metacarpal", "Proximal", "Distal"] : ["Proximal", "Intermediate", "Distal"]).map((j) => `right${f}${j}`))];

const fmtMm = (x) => (x == null ? "–" : x.toFixed(x < 10 ? 2 : 1));
const fmtUs = (x) => (x == null ? "–" : x.toFixed(0));

function updateReadouts() {
  for (const key of VIEW_KEYS) {
    $(`ro-right-${key}`).textContent = fmtMm(demo.errorMm[key].right);
    $(`ro-left-${key}`).textContent = fmtMm(demo.errorMm[key].left);
    $(`ro-us-${key}`).textContent = fmtUs(demo.solveUs[key]);
    $(`ro-usmed-${key}`).textContent = fmtUs(demo.solveUsMedian[key]);
    $(`ro-jitter-${key}`).textContent = demo.jitter[key] == null ? "–" : demo.jitter[key].toFixed(2);
    const e = demo.errorMm[key];
    const side = e.right != null ? "right" : e.left != null ? "left" : null;
    $(`err-${key}`).textContent = side
      ? `${side} error ${fmtMm(e[side])} mm · solve ${fmtUs(demo.solveUs[key])} µs`
      : `solve ${fmtUs(demo.solveUs[key])} µs`;
  }
  const alignOn = getPath(demo.options ?? {}, "alignment.enabled") !== false;
  $("label-with").querySelector("b").textContent = alignOn ? "with alignment" : "alignment off (panel)";
  $("frame-label").textContent = demo.source === "recording" ? `frame ${demo.frame} / ${demo.frameCount - 1}` : "live";
  $("scrub").value = String(demo.frame);
}

// ---------------------------------------------------------------- avatar loading

async function loadAvatar(bytes, name) {
  status(`loading ${name}…`);
  // Two independent copies: each view poses its own.
  const vrms = await Promise.all(VIEW_KEYS.map(() => parseVrm(bytes)));
  const next = {};
  try {
    VIEW_KEYS.forEach((key, i) => (next[key] = new Avatar(vrms[i], views[key].scene, name)));
  } catch (e) {
    for (const a of Object.values(next)) a.dispose();
    throw e;
  }
  const old = VIEW_KEYS.map((k) => views[k].avatar);
  VIEW_KEYS.forEach((key) => (views[key].avatar = next[key]));
  try {
    createRigs();
  } catch (e) {
    // The new avatar cannot be rigged (e.g. required bones missing): put the old one back.
    for (const a of Object.values(next)) a.dispose();
    VIEW_KEYS.forEach((key, i) => {
      views[key].avatar = old[i];
      views[key].rig = null;
    });
    if (old[0]) createRigs();
    throw e;
  }
  for (const a of old) a?.dispose();
  avatarBytes = bytes;
  avatarName = name;
  const a = views.with.avatar;
  // A skinned body (the generated humans) is shown lit instead of the drawn skeleton; the
  // robot and skeleton-only files keep the drawing. Both can be switched in the panel.
  $("show-meshes").checked = a.hasBody;
  $("show-skeleton").checked = !a.hasBody;
  for (const k of VIEW_KEYS) {
    views[k].avatar.setMeshesVisible(a.hasBody);
    views[k].avatar.setSkeletonVisible(!a.hasBody);
  }
  const parser = compareWithParser(bytes, a.rest, isVrmFile(bytes));
  demo.avatar = { name, vrmVersion: a.version, boneCount: a.boneCount, armLength: a.armLength, hasBody: a.hasBody, parser };
  demo.avatarLoads++;
  // A .vrma playing goes on playing on the new avatar.
  if (vrmaPlayer) vrmaPlayer.bind(VIEW_KEYS.map((k) => views[k].avatar.vrm));
  $("avatar-info").textContent =
    `${name}: VRM ${a.version === "0" ? "0.x" : "1.0"}, ${a.boneCount} humanoid bones, arm ${(a.armLength * 100).toFixed(1)} cm ` +
    `(handrig's ${demo.wasmBuild} WebAssembly build). ` +
    (parser.error
      ? `handrig's own parser (HandRig.${parser.reader}) refused it: ${parser.error}`
      : `HandRig.${parser.reader} reads the same rest pose as three-vrm to ${(parser.maxDiff * 1e6).toFixed(1)} µm (${parser.bones} bones).`);
  frameCamera(a);
  dirty = true;
  status(`${name} loaded`);
}

/** Whether a GLB's JSON chunk names a VRM extension (a plain glTF humanoid goes through fromGltf). */
function isVrmFile(bytes) {
  const len = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength).getUint32(12, true);
  const json = new TextDecoder().decode(bytes.subarray(20, 20 + Math.min(len, bytes.byteLength - 20)));
  return /"(VRMC_vrm|VRM)"\s*:/.test(json);
}

/**
 * Cross-check: handrig's own .vrm parser (HandRig.fromVrm, no three.js) against the rest pose
 * the page gives the rigs (three-vrm's normalized bones via restPoseFromVRM). Both are in the
 * model's own frame. Returns { bones, maxDiff (m), missing, version } or { error }.
 */
function compareWithParser(bytes, rest, vrmFile) {
  let rig;
  const reader = vrmFile ? "fromVrm" : "fromGltf";
  try {
    rig = vrmFile ? HandRig.fromVrm(bytes) : HandRig.fromGltf(bytes);
    const parsed = rig.restWorldPositions();
    let maxDiff = 0;
    const missing = [];
    for (const [name, p] of Object.entries(rest.bones)) {
      const q = parsed[name];
      if (!q) {
        missing.push(name);
        continue;
      }
      maxDiff = Math.max(maxDiff, Math.hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]));
    }
    const extra = Object.keys(parsed).filter((n) => !rest.bones[n]);
    return { bones: Object.keys(parsed).length, maxDiff, missing, extra, version: rig.vrmVersion, reader };
  } catch (e) {
    return { error: String(e?.message ?? e), reader };
  } finally {
    rig?.free();
  }
}

/** Loads an avatar of the menu (AVATARS) by id. */
async function selectAvatar(id) {
  const entry = AVATARS.find((a) => a.id === id);
  if (!entry) throw new Error(`no avatar "${id}" (the menu has ${AVATARS.map((a) => a.id).join(", ")})`);
  const r = await fetch(entry.url);
  if (!r.ok) throw new Error(`cannot load ${entry.url}: HTTP ${r.status}${entry.url.includes("/avatars/") ? " (make avatars writes tests/fixtures/avatars)" : ""}`);
  await loadAvatar(new Uint8Array(await r.arrayBuffer()), entry.url.split("/").pop());
  demo.avatar.id = id;
  $("avatar-select").value = id;
}

async function loadAvatarFile(file) {
  try {
    const bytes = new Uint8Array(await file.arrayBuffer());
    await loadAvatar(bytes, file.name);
    $("avatar-select").value = "";
  } catch (e) {
    status(`could not load ${file.name}: ${e.message}`, true);
    console.warn("avatar load failed:", e);
  }
}

// ---------------------------------------------------------------- UI wiring

function setFrame(i) {
  const n = demo.frameCount;
  if (!n) return;
  demo.frame = ((Math.round(i) % n) + n) % n;
  dirty = true;
}

let lastTick = 0;
let playClock = 0;

function setPlaying(on) {
  demo.playing = on && demo.source === "recording";
  $("play").textContent = demo.playing ? "Pause" : "Play";
  playClock = demo.frame;
  lastTick = performance.now();
}

function wireUi() {
  $("play").addEventListener("click", () => setPlaying(!demo.playing));
  $("step-back").addEventListener("click", () => (setPlaying(false), setFrame(demo.frame - 1)));
  $("step-fwd").addEventListener("click", () => (setPlaying(false), setFrame(demo.frame + 1)));
  $("scrub").addEventListener("input", (e) => {
    setPlaying(false);
    setFrame(Number(e.target.value));
  });
  canvas.addEventListener("keydown", (e) => {
    if (e.key === " ") setPlaying(!demo.playing);
    if (e.key === "ArrowLeft") setFrame(demo.frame - 1);
    if (e.key === "ArrowRight") setFrame(demo.frame + 1);
  });

  for (const r of document.querySelectorAll('input[name="source"]')) {
    r.addEventListener("change", () => setSource(r.value));
  }

  // Drag and drop anywhere on the page.
  const stage = $("stage");
  window.addEventListener("dragover", (e) => {
    e.preventDefault();
    stage.classList.add("dragging");
  });
  window.addEventListener("dragleave", () => stage.classList.remove("dragging"));
  window.addEventListener("drop", (e) => {
    e.preventDefault();
    stage.classList.remove("dragging");
    const files = [...(e.dataTransfer?.files ?? [])];
    const vrma = files.find((f) => /\.vrma$/i.test(f.name));
    if (vrma) return void playVrmaFile(vrma);
    const file = files.find((f) => /\.(vrm|glb)$/i.test(f.name)) ?? files[0];
    if (file) loadAvatarFile(file);
  });
  $("vrm-file").addEventListener("change", (e) => {
    const f = e.target.files?.[0];
    if (f) loadAvatarFile(f);
  });
  $("show-meshes").addEventListener("change", (e) => {
    for (const k of VIEW_KEYS) views[k].avatar?.setMeshesVisible(e.target.checked);
    dirty = true;
  });
  $("show-skeleton").addEventListener("change", (e) => {
    for (const k of VIEW_KEYS) views[k].avatar?.setSkeletonVisible(e.target.checked);
    dirty = true;
  });
  const select = $("avatar-select");
  for (const a of AVATARS) select.add(new Option(a.label, a.id));
  select.add(new Option("(a dropped or picked file)", ""));
  select.options[select.options.length - 1].disabled = true;
  select.addEventListener("change", async () => {
    if (!select.value) return;
    try {
      await selectAvatar(select.value);
    } catch (e) {
      status(e.message, true);
    }
  });
  for (const r of document.querySelectorAll('input[name="body-view"]')) {
    r.addEventListener("change", () => setBodyView(r.value));
  }
  $("whole-body").addEventListener("change", () => setWholeBody($("whole-body").checked));

  $("wasm-base").value = LOCAL_WASM_BASE;
  $("webcam-mode").addEventListener("change", showWebcamMode);
  showWebcamMode();
  $("webcam-start").addEventListener("click", startWebcam);
  $("webcam-stop").addEventListener("click", stopWebcam);
  $("record").addEventListener("click", toggleRecording);
  $("download-recording").addEventListener("click", downloadRecording);
  $("download-vrma").addEventListener("click", () => downloadMotion("vrma"));
  $("download-bvh").addEventListener("click", () => downloadMotion("bvh"));
}

function setWholeBody(on) {
  wholeBody = !!on;
  $("whole-body").checked = wholeBody;
  if (views.with.avatar) frameCamera(views.with.avatar);
  dirty = true;
}

function setBodyView(v) {
  bodyView = v === "side" ? "side" : "front";
  for (const r of document.querySelectorAll('input[name="body-view"]')) r.checked = r.value === bodyView;
  if (views.with.avatar) frameCamera(views.with.avatar);
  dirty = true;
}

function showWebcamMode() {
  const tasks = $("webcam-mode").value === "tasks";
  $("tasks-fields").hidden = !tasks;
  $("webcam-inference-field").hidden = tasks;
}

function setSource(src) {
  if (src !== "vrma" && vrmaPlayer) {
    vrmaPlayer.stop();
    vrmaPlayer = null;
  }
  demo.source = src;
  $("recording-controls").hidden = src !== "recording";
  $("webcam-controls").hidden = src !== "webcam";
  if (src !== "webcam") stopWebcam();
  setPlaying(false);
  // A new source is a new session for the rigs (calibration, kept rotations).
  try {
    createRigs();
  } catch (e) {
    status(`rig: ${e.message}`, true);
  }
  dirty = true;
}

// ---------------------------------------------------------------- webcam

const mediapipeTimes = [];
let webcamStartMs = 0;
let recorder = null;
let recordT0 = 0;
/** Longest recording kept in memory: 10 minutes at 30 frames a second. */
const MAX_RECORDED_FRAMES = 18000;

async function startWebcam() {
  const ws = $("webcam-status");
  const mode = $("webcam-mode").value;
  let hand = null;
  let pose = null;
  ws.textContent = "starting…";
  try {
    if (mode === "tasks") {
      hand = await modelSource($("hand-model-url").value, $("hand-model-file").files?.[0]);
      pose = await modelSource($("pose-model-url").value, $("pose-model-file").files?.[0]);
      if (!hand) {
        ws.textContent = "Give the hand landmarker model (.task) as a URL or a local file first.";
        return;
      }
    }
    stopWebcam();
    $("webcam-start").disabled = true;
    ws.textContent = mode === "tasks" ? "loading MediaPipe tasks-vision…" : "opening the camera…";
    const inference = $("webcam-inference").value;
    webcam = new Webcam($("webcam-video"), {
      onFrame: onWebcamFrame,
      onError: onWebcamError,
      onProgress: (text) => (ws.textContent = text),
    });
    webcam.probe = demo.webcamProbe;
    await webcam.start({ mode, hand, pose, wasmBase: $("wasm-base").value.trim(), cpu: inference === "auto" ? undefined : inference === "cpu" });
    // A new live session: fresh rigs (calibration, held hands) and counters.
    createRigs();
    mediapipeTimes.length = 0;
    webcamStartMs = performance.now();
    Object.assign(demo.webcam, {
      mode,
      running: true,
      mediapipe: webcam.mediapipeLabel,
      size: webcam.size,
      frames: 0,
      cameraFrames: 0,
      framesWithHands: 0,
      framesWithPose: 0,
      mediapipeMs: null,
      fps: null,
    });
    $("webcam-stop").disabled = false;
    $("record").disabled = false;
    ws.textContent = `running: ${webcam.mediapipeLabel}${mode === "tasks" && !pose ? " (hands only: arms stay at rest)" : ""}`;
  } catch (e) {
    if (e instanceof WebcamStopped) {
      ws.textContent = "stopped";
      return;
    }
    webcam?.stop();
    webcam = null;
    $("webcam-start").disabled = false;
    // MediaPipe's messages carry a source-location trace: the first line says what failed.
    ws.textContent = `webcam failed: ${String(e?.message ?? e).split("\n")[0]}`;
    console.warn("webcam failed:", e);
  }
}

function onWebcamFrame(frame, info) {
  solveAndShow(frame);
  dirty = true;
  const w = demo.webcam;
  w.frames++;
  w.cameraFrames = info.cameraFrames;
  if (info.handCount > 0) w.framesWithHands++;
  if (frame.pose) w.framesWithPose++;
  w.mediapipeMs = info.mediapipeMs;
  mediapipeTimes.push(info.mediapipeMs);
  if (mediapipeTimes.length > SOLVE_WINDOW) mediapipeTimes.shift();
  const elapsed = performance.now() - webcamStartMs;
  w.fps = elapsed > 0 ? (w.frames * 1000) / elapsed : null;
  if (recorder) {
    const { hands, pose } = webcam.recordParts();
    if (recorder.length === 0) recordT0 = info.timeMs;
    recorder.add(recorder.length, info.timeMs - recordT0, hands, pose);
    motion?.add(info.timeMs - recordT0, views.with.rig, demo.results.with);
    w.recordedFrames = recorder.length;
    if (recorder.length >= MAX_RECORDED_FRAMES) stopRecording(`stopped at ${MAX_RECORDED_FRAMES} frames (the in-memory limit)`);
  }
  if (w.frames % 10 === 1) {
    $("webcam-status").textContent =
      `running: ${w.mediapipe} · ${w.fps.toFixed(1)} frames/s · MediaPipe ${w.mediapipeMsMedian.toFixed(0)} ms · ` +
      `handrig ${fmtUs(demo.solveUsMedian.with)} µs · hands in ${w.framesWithHands}/${w.frames} frames ` +
      `(of ${w.cameraFrames} from the camera)`;
    if (recorder) $("record-status").textContent = `recording: ${recorder.length} frames`;
  }
  demo.onWebcamFrame?.(info, frame, demo.results.with);
}

function onWebcamError(e) {
  webcam = null;
  demo.webcam.running = false;
  $("webcam-start").disabled = false;
  $("webcam-stop").disabled = true;
  if (recorder) stopRecording("stopped: the webcam failed");
  $("webcam-status").textContent = `webcam failed: ${String(e?.message ?? e).split("\n")[0]}`;
  console.warn("webcam failed:", e);
}

function stopWebcam() {
  if (recorder) stopRecording();
  webcam?.stop();
  webcam = null;
  demo.webcam.running = false;
  $("webcam-start").disabled = false;
  $("webcam-stop").disabled = true;
  $("record").disabled = true;
}

function toggleRecording() {
  if (recorder) return stopRecording();
  if (!webcam) return;
  const { width, height } = webcam.size;
  // The solved motion of the "with" view, for .vrma and .bvh (handrig's MotionRecorder).
  motion = views.with.rig ? new MotionCapture(views.with.rig) : null;
  recorder = new RecordingBuilder({
    source: "webcam",
    width,
    height,
    fps: null,
    mediapipe: webcam.mediapipeLabel,
    mode: demo.webcam.mode,
    recordedAt: new Date().toISOString(),
    handrigOptions: demo.options,
  });
  demo.webcam.recording = true;
  demo.webcam.recordedFrames = 0;
  $("record").textContent = "Stop recording";
  $("download-recording").disabled = true;
  $("download-vrma").disabled = true;
  $("download-bvh").disabled = true;
  $("record-status").textContent = "recording: 0 frames";
}

let lastRecording = null;
let motion = null;
let lastMotion = null;

function stopRecording(why = "") {
  if (!recorder) return;
  lastRecording = recorder;
  recorder = null;
  lastMotion = motion;
  motion = null;
  const motionFrames = lastMotion?.recorder.frameCount ?? 0;
  $("download-vrma").disabled = motionFrames === 0;
  $("download-bvh").disabled = motionFrames === 0;
  demo.webcam.recording = false;
  $("record").textContent = "Record";
  $("download-recording").disabled = lastRecording.length === 0;
  $("record-status").textContent =
    `recorded ${lastRecording.length} frames${why ? ` (${why})` : ""}: download the landmarks as JSON, ` +
    `or the avatar's motion (${motionFrames} frames) as .vrma or .bvh${lastMotion?.error ? ` (${lastMotion.error})` : ""}`;
}

function downloadRecording() {
  if (recorder) stopRecording();
  if (!lastRecording) return;
  const blob = new Blob([lastRecording.toJSON()], { type: "application/json" });
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob);
  const stamp = new Date().toISOString().replace(/[:.]/g, "-").slice(0, 19);
  a.download = `handrig-webcam-${lastRecording.meta.mode}-${stamp}.json`;
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 10_000);
}

/** The "with" view's motion of the last recording as a .vrma (VRM Animation) or .bvh file. */
function downloadMotion(format) {
  if (recorder) stopRecording();
  if (!lastMotion || lastMotion.recorder.frameCount === 0) return;
  const r = lastMotion.recorder;
  const stamp = new Date().toISOString().replace(/[:.]/g, "-").slice(0, 19);
  if (format === "vrma") download(r.toVRMA(), `handrig-webcam-${stamp}.vrma`, "model/gltf-binary");
  else download(r.toBVH(), `handrig-webcam-${stamp}.bvh`, "text/plain");
}

// ---------------------------------------------------------------- .vrma playback

let vrmaPlayer = null;

/** Plays a dropped .vrma on the loaded avatar (both views), through three-vrm-animation. */
async function playVrmaFile(file) {
  try {
    const player = await VrmaPlayer.load(new Uint8Array(await file.arrayBuffer()), file.name);
    if (!views.with.avatar) throw new Error("load an avatar first");
    setSource("vrma");
    vrmaPlayer = player;
    player.bind(VIEW_KEYS.map((k) => views[k].avatar.vrm));
    for (const r of document.querySelectorAll('input[name="source"]')) r.checked = false;
    demo.vrmaPlaying = true;
    lastTick = performance.now();
    // The readouts are handrig's; nothing is solved while the file plays.
    for (const key of VIEW_KEYS) $(`err-${key}`).textContent = `playing ${file.name} (VRM Animation)`;
    status(`playing ${file.name} (${player.duration.toFixed(2)} s, VRM Animation) on the avatar; pick a source to stop`);
  } catch (e) {
    status(`could not play ${file.name}: ${e.message}`, true);
    console.warn("vrma failed:", e);
  }
}

/** Poses both views from the .vrma player's mixers (already set to its time). */
function showVrma() {
  for (const key of VIEW_KEYS) {
    const a = views[key].avatar;
    if (!a) continue;
    a.vrm.update(0);
    a.vrm.scene.updateMatrixWorld(true);
    a.updateSkeleton();
    a.updateMarkers(null);
  }
}

function onOptionsChanged(opts, path) {
  demo.options = opts;
  try {
    createRigs();
    const v = getPath(opts, path);
    status(`${path} = ${v === undefined ? "auto" : v}: rigs re-created`);
  } catch (e) {
    status(`options rejected: ${e.message}`, true);
  }
  dirty = true;
}

// ---------------------------------------------------------------- main loop

let solvedFrame = -1;
let solvedRigs = null;

function tick(now) {
  requestAnimationFrame(tick);
  if (demo.state !== "ready") return;
  if (demo.source === "recording") {
    if (demo.playing && demo.frameCount) {
      playClock += ((now - lastTick) / 1000) * recording.fps;
      const f = Math.floor(playClock) % demo.frameCount;
      if (f !== demo.frame) setFrame(f);
    }
    lastTick = now;
    const rigs = views.with.rig;
    if (dirty || demo.frame !== solvedFrame || rigs !== solvedRigs) {
      solveAndShow(currentFrame());
      solvedFrame = demo.frame;
      solvedRigs = rigs;
      render();
      dirty = false;
    }
  } else if (demo.source === "vrma" && vrmaPlayer) {
    if (demo.vrmaPlaying) {
      const t = vrmaPlayer.time + (now - lastTick) / 1000;
      vrmaPlayer.seek(t > vrmaPlayer.duration ? 0 : t);
      dirty = true;
    }
    lastTick = now;
    if (dirty) {
      showVrma();
      render();
      dirty = false;
    }
  } else {
    // Live frames are solved as MediaPipe delivers them (onWebcamFrame); draw the last one.
    if (dirty) {
      render();
      dirty = false;
    }
  }
}

/** Resolves after the next render (after pending changes are drawn). */
function nextRender() {
  dirty = true;
  return new Promise((resolve) => renderWaiters.push(resolve));
}

// ---------------------------------------------------------------- start

async function main() {
  wireUi();
  await init();
  // Which WebAssembly build the loader picked: "simd128" where the browser has WebAssembly SIMD.
  demo.wasmBuild = wasmBuild();
  demo.optionDescriptions = HandRig.optionDescriptions();
  panel = buildOptionsPanel($("options"), demo.optionDescriptions, onOptionsChanged);
  demo.options = panel.values();

  recording = await loadRecordings();
  demo.frameCount = recording.length;
  $("scrub").max = String(recording.length - 1);

  const params = new URLSearchParams(location.search);
  const wanted = params.get("avatar") ?? DEFAULT_AVATAR;
  await selectAvatar(AVATARS.some((a) => a.id === wanted) ? wanted : DEFAULT_AVATAR);
  if (params.get("view") === "side") setBodyView("side");
  if (params.get("body") === "whole") setWholeBody(true);

  resize();
  demo.state = "ready";
  setPlaying(!new URLSearchParams(location.search).has("paused"));
  requestAnimationFrame(tick);
}

// Test and console hooks. Everything async resolves once the change is on screen.
Object.assign(demo, {
  ready: null,
  setFrame: (i) => {
    if (demo.source === "frames") setSource("recording");
    setPlaying(false);
    setFrame(i);
    return nextRender();
  },
  /** Loads an avatar of the menu by id (AVATARS: "woman", "man-vrm0", "robot", ...). */
  selectAvatar: (id) => selectAvatar(id).then(nextRender),
  /** Frames the whole body (true) or the upper body (false) in the body view. */
  setWholeBody: (on) => {
    setWholeBody(on);
    return nextRender();
  },
  /** The body camera: "front" or "side". */
  setBodyView: (v) => {
    setBodyView(v);
    return nextRender();
  },
  /**
   * Solves `frames` (rig.solve inputs, e.g. a shared ASL recording's frames with its
   * imageAspect) in order on fresh rigs, as a session would, and shows the last one; the
   * recording stays off until setFrame. For screenshots of chosen moments.
   */
  showFrames: (frames) => {
    if (demo.source === "webcam") stopWebcam();
    setPlaying(false);
    demo.source = "frames";
    createRigs();
    for (const f of frames) solveAndShow(f);
    return nextRender();
  },
  /** The .vrma playing (dropped), or null: { name, duration, time }. */
  vrma: () => (vrmaPlayer ? { name: vrmaPlayer.name, duration: vrmaPlayer.duration, time: vrmaPlayer.time } : null),
  /** Pauses the .vrma at `t` seconds and shows it. */
  seekVrma: (t) => {
    demo.vrmaPlaying = false;
    vrmaPlayer?.seek(t);
    return nextRender();
  },
  /** The normalized bones' rotations of a view's avatar, [x, y, z, w] by bone name. */
  normalizedRotations: (key = "with") => {
    const h = views[key].avatar?.vrm.humanoid;
    const out = {};
    for (const name of Object.keys(h?.normalizedRestPose ?? {})) out[name] = h.getNormalizedBoneNode(name).quaternion.toArray();
    return out;
  },
  play: () => setPlaying(true),
  pause: () => setPlaying(false),
  setOption: (path, value) => {
    panel.set(path, value);
    return nextRender();
  },
  nextRender,
  /** Freezes (true) or resumes the live webcam processing; the avatar keeps the last frame. */
  pauseWebcam: (on) => {
    if (webcam) webcam.paused = on;
  },
  /** How many retargeting fingertip markers the "with" view shows (right side). */
  retargetMarkersShown: () => views.with.avatar?.marks.right.tips.filter(([, m]) => m.visible).length ?? 0,
  /** Reloads the current avatar bytes (e.g. after a test changed it). */
  reloadAvatar: () => (avatarBytes ? loadAvatar(avatarBytes, avatarName) : Promise.resolve()),
  /**
   * Where a bone of a view's avatar is on the page, in CSS pixels relative to the canvas's
   * top-left corner, in the body view (part "body") or the close-up ("close").
   */
  screenPoint(key, bone, part = "body") {
    const v = views[key];
    const p = v?.avatar?.boneWorld(bone);
    if (!p) return null;
    const r = layout()[key][part];
    const cam = part === "body" ? bodyCamera : v.closeCamera;
    cam.aspect = r.w / r.h;
    cam.updateProjectionMatrix();
    p.project(cam);
    const rect = canvas.getBoundingClientRect();
    return {
      x: rect.left + r.x + ((p.x + 1) / 2) * r.w,
      y: rect.top + r.y + ((1 - p.y) / 2) * r.h,
    };
  },
  viewRects: () => {
    const rect = canvas.getBoundingClientRect();
    const out = {};
    for (const [k, parts] of Object.entries(layout())) {
      out[k] = {};
      for (const [p, r] of Object.entries(parts)) out[k][p] = { x: rect.left + r.x, y: rect.top + r.y, w: r.w, h: r.h };
    }
    return out;
  },
});

demo.ready = main().catch((e) => {
  demo.state = "error";
  demo.error = String(e?.message ?? e);
  status(`failed to start: ${demo.error}`, true);
  console.error(e);
});
