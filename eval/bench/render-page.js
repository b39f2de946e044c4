// The bench's renderer page (issue 47), driven by render.mjs through playwright-core in headless
// Chromium (SwiftShader WebGL): loads a VRM 1.0 avatar with three-vrm, dresses it by vertex
// colour (shirt, trousers, shoes, skin; the eyes keep their material), poses its normalized
// humanoid with the truth of motions.mjs and returns each frame's RGBA pixels, top row first.

import * as THREE from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";
import { VRMLoaderPlugin } from "@pixiv/three-vrm";
import { LEG_REST_BONES, anyClipById, clipPose, legClipPose, setNormalizedPose } from "/bench/motions.mjs";
import { FACE_ARMS, faceClipById, faceFrame } from "/bench/face-motions.mjs";

export const WIDTH = 640;
export const HEIGHT = 480;

// Linear colours by body region (skin bones after the region tables below).
const COLOURS = {
  skin: [0.72, 0.45, 0.33],
  shirt: [0.08, 0.2, 0.45],
  trousers: [0.09, 0.09, 0.1],
  shoes: [0.25, 0.12, 0.05],
  hair: [0.05, 0.03, 0.02],
};
const REGION = {
  hips: "trousers", leftUpperLeg: "trousers", rightUpperLeg: "trousers", leftLowerLeg: "trousers", rightLowerLeg: "trousers",
  leftFoot: "shoes", rightFoot: "shoes", leftToes: "shoes", rightToes: "shoes",
  spine: "shirt", chest: "shirt", upperChest: "shirt", leftShoulder: "shirt", rightShoulder: "shirt",
  leftUpperArm: "shirt", rightUpperArm: "shirt",
};

const canvas = document.createElement("canvas");
canvas.width = WIDTH;
canvas.height = HEIGHT;
document.body.append(canvas);
const renderer = new THREE.WebGLRenderer({ canvas, antialias: false, preserveDrawingBuffer: true, alpha: false });
renderer.setPixelRatio(1);
renderer.setSize(WIDTH, HEIGHT, false);
renderer.outputColorSpace = THREE.SRGBColorSpace;
const gl = renderer.getContext();

const scene = new THREE.Scene();
scene.background = new THREE.Color(0.42, 0.45, 0.48);
scene.add(new THREE.HemisphereLight(0xffffff, 0x445566, 1.4));
const key = new THREE.DirectionalLight(0xffffff, 2.0);
key.position.set(0.6, 2.5, 3);
scene.add(key);
const fill = new THREE.DirectionalLight(0xffffff, 0.6);
fill.position.set(-2, 1, 1);
scene.add(fill);
const camera = new THREE.PerspectiveCamera(40, WIDTH / HEIGHT, 0.05, 20);

let vrm = null;
let dressedOwn = false;
/** World positions of the hips, legs, feet and toes at rest (leg clips), and the hips' rest position. */
let legRest = null;
let hipsRestPosition = null;

/**
 * Vertex colours from each vertex's dominant skin bone (its nearest humanoid ancestor). The
 * generated avatars carry their own colours since issue 50 (tools/avatars/face.mjs: the same
 * regions, and a mouth and irises): the face clips show them (`own`); the body and hand clips
 * keep this dress and the eyes' former plain colour, so their frames (frames.json) and the
 * committed recordings made from them stay as they were.
 */
const EYES = [0.12, 0.09, 0.07];
function dress(v, own) {
  if (own) {
    v.scene.traverse((o) => {
      if (!o.isSkinnedMesh) return;
      const g = o.geometry;
      if (g.userData.ownColour) g.setAttribute("color", g.userData.ownColour);
      // The mouth's own material (the faces across the lips' slit) back to its dark colour.
      for (const m of Array.isArray(o.material) ? o.material : [o.material]) {
        if (m.userData.ownColour) m.color.copy(m.userData.ownColour);
      }
    });
    return;
  }
  const humanOf = new Map();
  for (const [name, bone] of Object.entries(v.humanoid.humanBones)) if (bone?.node) humanOf.set(bone.node, name);
  const head = v.humanoid.getRawBoneNode("head");
  head.updateWorldMatrix(true, false);
  const eyeY = v.humanoid.getRawBoneNode("leftEye")?.getWorldPosition(new THREE.Vector3()).y ?? Infinity;
  v.scene.traverse((o) => {
    if (!o.isSkinnedMesh) return;
    const g = o.geometry;
    const mats = Array.isArray(o.material) ? o.material : [o.material];
    if (g.attributes.color && !g.userData.ownColour) g.userData.ownColour = g.attributes.color;
    if (mats.some((m) => m.name === "eyes") && g.userData.ownColour) {
      const n = g.attributes.position.count;
      const col = new Float32Array(n * 3);
      for (let i = 0; i < n; i++) col.set(EYES, i * 3);
      g.setAttribute("color", new THREE.BufferAttribute(col, 3));
      for (const m of mats) m.color.setRGB(1, 1, 1);
      return;
    }
    // The faces across the lips' slit have a material of their own ("mouth", dark, since
    // 2026-12-07): dressed as skin here, as they were when they were part of it.
    if (!mats.some((m) => m.name === "skin" || m.name === "mouth")) return;
    const n = g.attributes.position.count;
    const col = new Float32Array(n * 3);
    const p = new THREE.Vector3();
    for (let i = 0; i < n; i++) {
      let best = 0;
      let bw = -1;
      for (let k = 0; k < g.attributes.skinIndex.itemSize; k++) {
        const w = g.attributes.skinWeight.getComponent(i, k);
        if (w > bw) {
          bw = w;
          best = g.attributes.skinIndex.getComponent(i, k);
        }
      }
      let node = o.skeleton.bones[best];
      while (node && !humanOf.has(node)) node = node.parent;
      let region = REGION[humanOf.get(node)] ?? "skin";
      if (humanOf.get(node) === "head") {
        // Hair: the skull above the eyes and the back of the head.
        p.fromBufferAttribute(g.attributes.position, i).applyMatrix4(o.matrixWorld);
        if (p.y > eyeY + 0.045 || (p.z < -0.01 && p.y > eyeY - 0.06)) region = "hair";
      }
      col.set(COLOURS[region], i * 3);
    }
    g.setAttribute("color", new THREE.BufferAttribute(col, 3));
    for (const m of mats) {
      if (m.name === "mouth") m.userData.ownColour ??= m.color.clone();
      else if (m.name !== "skin") continue;
      m.vertexColors = true;
      m.color.setRGB(1, 1, 1);
      m.needsUpdate = true;
    }
  });
}

async function load(url) {
  if (vrm) scene.remove(vrm.scene);
  const loader = new GLTFLoader();
  loader.register((parser) => new VRMLoaderPlugin(parser, { autoUpdateHumanBones: true }));
  const gltf = await loader.loadAsync(url);
  vrm = gltf.userData.vrm;
  if (vrm.meta?.metaVersion !== "1") throw new Error(`${url}: the bench poses VRM 1.0 avatars only`);
  vrm.scene.traverse((o) => (o.frustumCulled = false));
  vrm.scene.updateMatrixWorld(true);
  dress(vrm, false);
  dressedOwn = false;
  scene.add(vrm.scene);
  hipsRestPosition = vrm.humanoid.getNormalizedBoneNode("hips").position.clone();
  vrm.scene.updateMatrixWorld(true);
  legRest = {};
  for (const b of LEG_REST_BONES) {
    const node = vrm.humanoid.getNormalizedBoneNode(b);
    if (node) legRest[b] = node.getWorldPosition(new THREE.Vector3()).toArray();
  }
  return { name: url.split("/").pop() };
}

function pose(clip, i) {
  if (clip.kind === "face") {
    vrm.humanoid.getNormalizedBoneNode("hips").position.copy(hipsRestPosition);
    return poseFace(clip, i);
  }
  let q;
  if (clip.kind === "legs") {
    const t = legClipPose(clip, i, legRest);
    q = t.bones;
    const hips = vrm.humanoid.getNormalizedBoneNode("hips");
    hips.position.set(hipsRestPosition.x + t.hipsOffset[0], hipsRestPosition.y + t.hipsOffset[1], hipsRestPosition.z + t.hipsOffset[2]);
  } else {
    q = clipPose(clip, i);
    vrm.humanoid.getNormalizedBoneNode("hips").position.copy(hipsRestPosition);
  }
  setNormalizedPose(vrm, q);
  vrm.update(0);
  vrm.scene.updateMatrixWorld(true);
}

/** A face clip's frame (face-motions.mjs): arms down, the head turned, expressions, look-at. */
function poseFace(clip, i) {
  const f = faceFrame(clip, i);
  const q = { ...FACE_ARMS, ...f.bones };
  setNormalizedPose(vrm, q);
  const em = vrm.expressionManager;
  for (const e of em?.expressions ?? []) em.setValue(e.expressionName, f.expressions[e.expressionName] ?? 0);
  if (vrm.lookAt) {
    vrm.lookAt.autoUpdate = false;
    vrm.lookAt.yaw = f.lookAt[0];
    vrm.lookAt.pitch = f.lookAt[1];
  }
  vrm.update(0);
  vrm.scene.updateMatrixWorld(true);
}

const world = (name) => vrm.humanoid.getNormalizedBoneNode(name).getWorldPosition(new THREE.Vector3());

/** Camera of a clip: body clips before the chest at about 1.35 x the head's height; hand clips 0.5 m before the right hand at the clip's first frame. */
function placeCamera(clip) {
  if (clip.kind === "face") {
    // Face clips: 0.5 m before the eyes at rest, looking at them.
    pose({ ...clip, tracks: {} }, 0);
    const c = world("leftEye").add(world("rightEye")).multiplyScalar(0.5);
    camera.position.set(c.x, c.y, c.z + 0.5);
    camera.lookAt(c.x, c.y, c.z);
    return { distance: 0.5, target: c.toArray() };
  }
  if (clip.kind === "hand") {
    pose(clip, 0);
    const c = world("rightHand").add(world("rightMiddleProximal")).multiplyScalar(0.5);
    camera.position.set(c.x, c.y, c.z + 0.5);
    camera.lookAt(c.x, c.y, c.z);
    return { distance: 0.5, target: c.toArray() };
  }
  if (clip.kind === "legs") {
    // The whole body: the camera level with the middle of the standing avatar, far enough that
    // its height (the bounding box at rest) fills 1 / 1.2 of the view's height.
    pose(clip, 0);
    const top = new THREE.Box3().setFromObject(vrm.scene).max.y;
    const y = 0.5 * top;
    const d = (0.6 * top) / Math.tan((camera.fov * Math.PI) / 360);
    // A pitched clip (PITCHED_LEG_CLIPS): the same distance, raised to look `pitch` degrees down.
    const p = ((clip.pitch ?? 0) * Math.PI) / 180;
    camera.position.set(0, y + d * Math.sin(p), d * Math.cos(p));
    camera.lookAt(0, y, 0);
    return { distance: d, target: [0, y, 0], ...(clip.pitch ? { pitch: clip.pitch } : {}) };
  }
  const headY = world("head").y;
  const y = world("upperChest").y + 0.1 * headY;
  const d = 1.35 * headY;
  camera.position.set(0, y, d);
  camera.lookAt(0, y, 0);
  return { distance: d, target: [0, y, 0] };
}

let current = null;
window.__bench = {
  load,
  /** Selects a clip: poses frame 0 and places the camera; returns the camera. */
  clip(id) {
    current = id.startsWith("face-") ? { ...faceClipById(id), kind: "face" } : anyClipById(id);
    const own = current.kind === "face";
    if (own !== dressedOwn) {
      dress(vrm, own);
      dressedOwn = own;
    }
    return { ...placeCamera(current), fov: camera.fov, position: camera.position.toArray() };
  },
  /** World positions at rest of the hips, legs, feet and toes (legClipPose's `rest`). */
  legRest() {
    return legRest;
  },
  /**
   * Renders the avatar posed by `bones` ({ name: [x, y, z, w] } normalized rotations; others
   * identity) with the normalized hips at `hips` ([x, y, z]), from the current clip's camera
   * ("front") or as far from the avatar's right ("side"): base64 RGBA as frame() (the leg
   * screenshots of a solved pose, eval/bench/legs-shots.mjs).
   */
  show(bones, hips, view = "front") {
    for (const name of Object.keys(vrm.humanoid.humanBones)) {
      const node = vrm.humanoid.getNormalizedBoneNode(name);
      const r = bones[name];
      if (node) r ? node.quaternion.set(r[0], r[1], r[2], r[3]) : node.quaternion.identity();
    }
    vrm.humanoid.getNormalizedBoneNode("hips").position.set(hips[0], hips[1], hips[2]);
    vrm.update(0);
    vrm.scene.updateMatrixWorld(true);
    const saved = camera.position.clone();
    if (view === "side") {
      camera.position.set(-saved.z, saved.y, 0);
      camera.lookAt(0, saved.y, 0);
    }
    renderer.render(scene, camera);
    camera.position.copy(saved);
    camera.lookAt(0, saved.y, 0);
    return pixels();
  },
  /**
   * A close-up of the face at rest with `expressions` set ({ name: weight }, VRM presets or the
   * ARKit custom names; others 0), from `distance` m before the point `target` ([x, y, z], world)
   * ("front") or from the avatar's right ("side"): base64 RGBA as frame() (the mouth's shots,
   * eval/bench/face-mouth-shots.mjs). Select a face clip first (its own colours).
   */
  faceShot(expressions, target, view = "front", distance = 0.2) {
    setNormalizedPose(vrm, FACE_ARMS);
    const em = vrm.expressionManager;
    for (const e of em?.expressions ?? []) em.setValue(e.expressionName, expressions[e.expressionName] ?? 0);
    if (vrm.lookAt) {
      vrm.lookAt.autoUpdate = false;
      vrm.lookAt.yaw = 0;
      vrm.lookAt.pitch = 0;
    }
    vrm.update(0);
    vrm.scene.updateMatrixWorld(true);
    const saved = camera.position.clone();
    const savedQ = camera.quaternion.clone();
    const [x, y, z] = target;
    if (view === "side") camera.position.set(x - distance, y, z);
    else camera.position.set(x, y, z + distance);
    camera.lookAt(x, y, z);
    renderer.render(scene, camera);
    camera.position.copy(saved);
    camera.quaternion.copy(savedQ);
    return pixels();
  },
  /** World position of the middle between the eyes (as posed). */
  eyesMiddle() {
    return world("leftEye").add(world("rightEye")).multiplyScalar(0.5).toArray();
  },
  /** Renders frame `i` of the current clip: base64 RGBA, WIDTH x HEIGHT, top row first. */
  frame(i) {
    pose(current, i);
    renderer.render(scene, camera);
    return pixels();
  },
};

/** The canvas' RGBA pixels, base64, top row first. */
function pixels() {
  const px = new Uint8Array(WIDTH * HEIGHT * 4);
  gl.readPixels(0, 0, WIDTH, HEIGHT, gl.RGBA, gl.UNSIGNED_BYTE, px);
  const flipped = new Uint8Array(px.length);
  const row = WIDTH * 4;
  for (let y = 0; y < HEIGHT; y++) flipped.set(px.subarray((HEIGHT - 1 - y) * row, (HEIGHT - y) * row), y * row);
  let s = "";
  for (let k = 0; k < flipped.length; k += 0x8000) s += String.fromCharCode.apply(null, flipped.subarray(k, k + 0x8000));
  return btoa(s);
}
window.__benchReady = true;
