// A VRM avatar for one view: loading with three-vrm, the rest pose handrig needs, applying
// handrig results to the normalized bones, and drawing the skeleton (the robot has no body
// mesh, and a drawn skeleton shows fingers clearly on any avatar). Avatars with a skinned body
// (the generated humans) show it, lit, and hide the drawn skeleton by default.
//
// Frames: handrig's inputs and outputs are in the model's own frame (VRM 0.x models face -Z,
// 1.0 models face +Z) and apply directly to three-vrm's normalized bones. Everything here that
// talks to handrig therefore works in vrm.scene's local space; only the display turns VRM 0.x
// models around (VRMUtils.rotateVRM0) so every avatar faces the viewer.

import * as THREE from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";
import { VRM, VRMHumanoid, VRMLoaderPlugin, VRMUtils } from "@pixiv/three-vrm";
import { HandRig } from "handrig";
import { sanitizeNodeName } from "handrig/three";
// The package's three-vrm adapter: the rest pose handrig wants, and writing results back.
import { applyToVRM, restPoseFromVRM } from "handrig/three-vrm";

/** The 55 VRM 1.0 humanoid bone names, parent first (three-vrm's order). */
export const HUMAN_BONES = [
  "hips", "spine", "chest", "upperChest", "neck", "head", "leftEye", "rightEye", "jaw",
  "leftUpperLeg", "leftLowerLeg", "leftFoot", "leftToes",
  "rightUpperLeg", "rightLowerLeg", "rightFoot", "rightToes",
  "leftShoulder", "leftUpperArm", "leftLowerArm", "leftHand",
  "rightShoulder", "rightUpperArm", "rightLowerArm", "rightHand",
  "leftThumbMetacarpal", "leftThumbProximal", "leftThumbDistal",
  "leftIndexProximal", "leftIndexIntermediate", "leftIndexDistal",
  "leftMiddleProximal", "leftMiddleIntermediate", "leftMiddleDistal",
  "leftRingProximal", "leftRingIntermediate", "leftRingDistal",
  "leftLittleProximal", "leftLittleIntermediate", "leftLittleDistal",
  "rightThumbMetacarpal", "rightThumbProximal", "rightThumbDistal",
  "rightIndexProximal", "rightIndexIntermediate", "rightIndexDistal",
  "rightMiddleProximal", "rightMiddleIntermediate", "rightMiddleDistal",
  "rightRingProximal", "rightRingIntermediate", "rightRingDistal",
  "rightLittleProximal", "rightLittleIntermediate", "rightLittleDistal",
];

export const FINGERS = ["thumb", "index", "middle", "ring", "little"];

/**
 * Distal over previous phalanx length per finger (thumb..little), the same table handrig's
 * alignment uses for its "tip" point (src/align.rs TIP_RATIO, Buryanov & Kotiuk 2010). Used
 * to draw fingertips past the distal joint and to place the avatar marker for point = "tip".
 */
export const TIP_RATIO = { thumb: 0.7, index: 0.71, middle: 0.66, ring: 0.67, little: 0.88 };

/** The distal bone name of `finger` on `side` ("left" | "right"). */
export function distalBone(side, finger) {
  const cap = finger[0].toUpperCase() + finger.slice(1);
  return `${side}${cap}Distal`;
}

/** Parses `.vrm` bytes into a three-vrm VRM. Throws with a readable message on bad files. */
export async function parseVrm(bytes) {
  const loader = new GLTFLoader();
  loader.register((parser) => new VRMLoaderPlugin(parser));
  const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
  const gltf = await new Promise((resolve, reject) => loader.parse(buffer, "", resolve, reject));
  const vrm = gltf.userData.vrm;
  if (vrm && vrm.humanoid) return vrm;
  return vrmFromPlainGltf(gltf.scene, bytes);
}

/**
 * A plain glTF humanoid (Mixamo, Unreal-mannequin names: no VRM extension) as a three-vrm VRM:
 * handrig binds its bones (`HandRig.fromGltf(bytes).boneMap()`, file node names, which three
 * sanitizes) and finds its facing; three-vrm's `VRMHumanoid` then builds the normalized rig over
 * the model's own bones (rest rotations carried through, as for a VRM), so the rest of the demo
 * drives it like any VRM. A model facing -Z is marked VRM 0.x, as handrig treats it.
 */
function vrmFromPlainGltf(scene, bytes) {
  let rig;
  let boneMap;
  let version;
  try {
    rig = HandRig.fromGltf(bytes);
    boneMap = rig.boneMap();
    version = rig.vrmVersion;
  } finally {
    rig?.free();
  }
  const humanBones = {};
  for (const [bone, name] of Object.entries(boneMap)) {
    const node = scene.getObjectByName(sanitizeNodeName(name)) ?? scene.getObjectByName(name);
    if (node) humanBones[bone] = { node };
  }
  const humanoid = new VRMHumanoid(humanBones);
  scene.add(humanoid.normalizedHumanBonesRoot);
  return new VRM({ scene, humanoid, meta: { metaVersion: version, name: "glTF humanoid" } });
}

/** "0" for VRM 0.x, "1" for VRM 1.0. */
export function vrmVersionOf(vrm) {
  return String(vrm.meta?.metaVersion ?? "1") === "0" ? "0" : "1";
}

// Scratch vectors for per-frame code (three-vrm's pattern): no allocation while playing.
const _a = new THREE.Vector3();
const _b = new THREE.Vector3();
const _dir = new THREE.Vector3();
const UP = new THREE.Vector3(0, 1, 0);

const SIDE_COLOR = { left: 0x4aa3ff, right: 0xff9a3c, center: 0xb8bec9 };
const FINGER_COLOR = {
  thumb: 0xff5d5d, index: 0xffe14d, middle: 0x62e36b, ring: 0x4fd9ff, little: 0xc77dff,
};

function boneSide(name) {
  if (name.startsWith("left")) return "left";
  if (name.startsWith("right")) return "right";
  return "center";
}
function boneFinger(name) {
  const m = /^(?:left|right)(Thumb|Index|Middle|Ring|Little)/.exec(name);
  return m ? m[1].toLowerCase() : null;
}

/**
 * One avatar in one scene, with its skeleton drawing and alignment markers.
 * `scene` is the three.js scene of its view.
 */
export class Avatar {
  constructor(vrm, scene, name) {
    this.vrm = vrm;
    this.name = name;
    this.version = vrmVersionOf(vrm);
    this.scene = scene;
    this.rest = restPoseFromVRM(vrm);
    // Display only: face the viewer like a VRM 1.0 model. handrig math stays in vrm.scene's
    // local (model) frame, where the rest pose above was taken.
    if (this.version === "0") VRMUtils.rotateVRM0(vrm);
    scene.add(vrm.scene);
    vrm.scene.updateMatrixWorld(true);

    this.nodes = new Map();
    for (const name of HUMAN_BONES) {
      const node = vrm.humanoid.getNormalizedBoneNode(name);
      if (node) this.nodes.set(name, node);
    }
    this.boneCount = this.nodes.size;
    // A skinned body mesh (the generated humans): shown by default instead of the drawing.
    this.hasBody = false;
    vrm.scene.traverse((o) => {
      if (o.isSkinnedMesh) this.hasBody = true;
    });
    this.armLength = this.#armLength();
    this.#buildSkeleton();
    this.#buildMarkers();
  }

  /** Upper + lower arm length at rest (m), averaged over sides; sizes the drawing. */
  #armLength() {
    const b = this.rest.bones;
    const d = (a, c) => (b[a] && b[c] ? Math.hypot(b[a][0] - b[c][0], b[a][1] - b[c][1], b[a][2] - b[c][2]) : NaN);
    const lens = ["left", "right"]
      .map((s) => d(`${s}UpperArm`, `${s}LowerArm`) + d(`${s}LowerArm`, `${s}Hand`))
      .filter(Number.isFinite);
    return lens.length ? lens.reduce((x, y) => x + y) / lens.length : 0.5;
  }

  /** The effective parent of a bone: the nearest normalized-bone ancestor (as three-vrm). */
  #parentOf(name) {
    const byNode = new Map([...this.nodes].map(([n, node]) => [node, n]));
    let p = this.nodes.get(name).parent;
    while (p) {
      if (byNode.has(p)) return byNode.get(p);
      p = p.parent;
    }
    return null;
  }

  #buildSkeleton() {
    this.skeleton = new THREE.Group();
    this.skeleton.name = "handrig-skeleton";
    this.scene.add(this.skeleton);
    const cyl = new THREE.CylinderGeometry(1, 1, 1, 12, 1, false);
    const sph = new THREE.SphereGeometry(1, 14, 10);
    this.segments = [];
    this.joints = [];
    const children = new Map();
    for (const name of this.nodes.keys()) {
      const parent = this.#parentOf(name);
      if (parent) {
        if (!children.has(parent)) children.set(parent, []);
        children.get(parent).push(name);
      }
    }
    const L = this.armLength;
    const material = (name) => {
      const finger = boneFinger(name);
      const color = finger ? FINGER_COLOR[finger] : SIDE_COLOR[boneSide(name)];
      return new THREE.MeshStandardMaterial({ color, roughness: 0.55, metalness: 0.05 });
    };
    const radiusFor = (name, len) => {
      const finger = boneFinger(name);
      const lo = finger ? 0.006 * L : 0.012 * L;
      const hi = finger ? 0.014 * L : 0.04 * L;
      return Math.min(hi, Math.max(lo, 0.14 * len));
    };
    const restLen = (a, c) => {
      const b = this.rest.bones;
      return Math.hypot(b[a][0] - b[c][0], b[a][1] - b[c][1], b[a][2] - b[c][2]);
    };

    for (const name of this.nodes.keys()) {
      if (name.endsWith("Eye") || name === "jaw") continue;
      const parent = this.#parentOf(name);
      if (parent) {
        const len = restLen(parent, name);
        const mesh = new THREE.Mesh(cyl, material(name));
        const r = radiusFor(name, len);
        this.skeleton.add(mesh);
        this.segments.push({ from: parent, to: name, mesh, r, tip: null });
        const joint = new THREE.Mesh(sph, mesh.material);
        joint.scale.setScalar(r * 1.25);
        this.skeleton.add(joint);
        this.joints.push({ name, mesh: joint });
      }
      // Leaves that end a limb get a tip segment past the joint along the bone's own
      // direction (rest offset from its parent, rotated with the bone): the distal phalanx,
      // a hand without fingers, the head, the toes.
      const kids = (children.get(name) || []).filter((c) => !c.endsWith("Eye") && c !== "jaw");
      if (kids.length === 0 && parent) {
        const finger = boneFinger(name);
        const k = finger ? TIP_RATIO[finger] : name.endsWith("Hand") ? 0.35 : name === "head" ? 0.9 : 0.6;
        const local = this.nodes.get(name).position.clone().multiplyScalar(k);
        const len = local.length();
        const mesh = new THREE.Mesh(cyl, material(name));
        this.skeleton.add(mesh);
        this.segments.push({ from: name, to: null, local, mesh, r: radiusFor(name, len) * (finger ? 0.9 : 1) });
      }
    }
  }

  #buildMarkers() {
    // Markers live in vrm.scene's local space: handrig positions are in the model frame.
    this.markers = new THREE.Group();
    this.markers.name = "handrig-markers";
    this.vrm.scene.add(this.markers);
    const r = 0.02 * this.armLength;
    const mk = (color, geo) => {
      const m = new THREE.Mesh(geo, new THREE.MeshBasicMaterial({ color, depthTest: false, transparent: true, opacity: 0.9 }));
      m.renderOrder = 10;
      m.visible = false;
      this.markers.add(m);
      return m;
    };
    const sphere = new THREE.SphereGeometry(r, 16, 12);
    const ring = new THREE.TorusGeometry(r * 1.25, r * 0.3, 8, 24);
    const cube = new THREE.BoxGeometry(r * 1.4, r * 1.4, r * 1.4);
    const small = new THREE.OctahedronGeometry(r * 0.45);
    this.marks = {};
    for (const side of ["left", "right"]) {
      this.marks[side] = {
        target: mk(0xff3b6b, sphere),
        avatar: mk(0x35e06f, ring),
        ik: mk(0xffd23b, cube),
        // handStrategy "retarget": the user's fingertips placed on the avatar (small, in each
        // finger's colour).
        tips: ["thumb", "index", "middle", "ring", "little"].map((f) => [f, mk(FINGER_COLOR[f], small)]),
      };
      const line = new THREE.Line(
        new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3()]),
        new THREE.LineBasicMaterial({ color: 0xffffff, depthTest: false }),
      );
      line.renderOrder = 11;
      line.visible = false;
      this.markers.add(line);
      this.marks[side].line = line;
      this.marks[side].point = new THREE.Vector3();
    }
  }

  /**
   * Draws the rig's self-contact face anchors (`rig.contactModel()`): small spheres attached
   * to the head bone, so they follow the head.
   */
  showContactModel(model) {
    this.contactMarks?.removeFromParent();
    const head = this.nodes.get("head");
    const rest = this.rest.bones.head;
    if (!model || !head || !rest) return;
    const group = new THREE.Group();
    group.name = "handrig-face-anchors";
    const geo = new THREE.SphereGeometry(0.008 * this.armLength, 12, 8);
    const mat = new THREE.MeshBasicMaterial({ color: 0x3bd5ff, depthTest: false, transparent: true, opacity: 0.85 });
    for (const [name, p] of Object.entries(model.anchors)) {
      const m = new THREE.Mesh(geo, mat);
      m.name = name;
      m.renderOrder = 10;
      // Normalized bones have identity rest rotations: a rest offset is the local position.
      m.position.set(p[0] - rest[0], p[1] - rest[1], p[2] - rest[2]);
      group.add(m);
    }
    head.add(group);
    this.contactMarks = group;
  }

  /** Shows or hides the model's own meshes (the skeleton drawing stays). */
  setMeshesVisible(visible) {
    this.vrm.scene.traverse((o) => {
      if (o.isMesh && !this.markers.children.includes(o) && o.parent !== this.contactMarks) o.visible = visible;
    });
  }

  /** Shows or hides the drawn skeleton (capsules and joints). */
  setSkeletonVisible(visible) {
    this.skeleton.visible = visible;
  }

  /**
   * Applies a handrig result: the package's `applyToVRM` writes every bone the rig drives
   * (solved, held or back at rest: a result carries them all every frame, so nothing freezes
   * when tracking is lost), and three-vrm copies them onto the model's bones in `vrm.update`.
   */
  apply(result) {
    if (result) applyToVRM(this.vrm, result);
    this.vrm.update(0);
    this.vrm.scene.updateMatrixWorld(true);
  }

  /** World position of a normalized bone (scene frame of the view). */
  boneWorld(name, out = new THREE.Vector3()) {
    const node = this.nodes.get(name);
    return node ? node.getWorldPosition(out) : null;
  }

  /** A bone's rest position in the view's world frame (null if the avatar lacks it). */
  restWorld(name, out = new THREE.Vector3()) {
    const p = this.rest.bones[name];
    return p ? this.vrm.scene.localToWorld(out.fromArray(p)) : null;
  }

  /** A normalized bone's position in the model frame (what handrig reports). */
  boneModel(name, out = new THREE.Vector3()) {
    const w = this.boneWorld(name, out);
    return w ? this.vrm.scene.worldToLocal(w) : null;
  }

  /**
   * The avatar's aligned point (model frame) as three-vrm shows it: the distal joint of
   * `finger`, or for point = "tip" that joint extended by TIP_RATIO along the distal bone.
   */
  alignedPointModel(side, finger, point, out = new THREE.Vector3()) {
    const name = distalBone(side, finger);
    const node = this.nodes.get(name);
    if (!node) return null;
    if (point === "tip") out.copy(node.position).multiplyScalar(TIP_RATIO[finger]);
    else out.set(0, 0, 0);
    node.localToWorld(out);
    return this.vrm.scene.worldToLocal(out);
  }

  /** Moves the capsules onto the current normalized bones. */
  updateSkeleton() {
    const a = _a;
    const b = _b;
    const up = UP;
    const dir = _dir;
    for (const s of this.segments) {
      this.nodes.get(s.from).getWorldPosition(a);
      if (s.to) this.nodes.get(s.to).getWorldPosition(b);
      else this.nodes.get(s.from).localToWorld(b.copy(s.local));
      dir.subVectors(b, a);
      const len = dir.length();
      s.mesh.visible = len > 1e-6;
      if (!s.mesh.visible) continue;
      s.mesh.position.addVectors(a, b).multiplyScalar(0.5);
      s.mesh.quaternion.setFromUnitVectors(up, dir.divideScalar(len));
      s.mesh.scale.set(s.r, len, s.r);
    }
    for (const j of this.joints) this.nodes.get(j.name).getWorldPosition(j.mesh.position);
  }

  /**
   * Places the markers for one side from a handrig result (model frame): target point, the
   * avatar's aligned point as three-vrm shows it, the wrist IK target, a line between the
   * first two, and with `handStrategy: "retarget"` the fingertip targets. Returns the distance
   * (m) between target and the shown avatar point, or null.
   */
  updateMarkers(result, finger, point) {
    let shown = {};
    for (const side of ["left", "right"]) {
      const m = this.marks[side];
      const al = result?.alignment?.[side];
      const ik = result?.ikTargets?.[side];
      const targets = result?.retarget?.[side]?.targets;
      for (const [finger, mesh] of m.tips) {
        const t = targets?.[finger];
        mesh.visible = !!t;
        if (t) mesh.position.fromArray(t);
      }
      m.ik.visible = !!ik;
      if (ik) m.ik.position.fromArray(ik.position);
      const avatarPoint = al ? this.alignedPointModel(side, finger, point, m.point) : null;
      m.target.visible = !!al;
      m.avatar.visible = !!avatarPoint;
      m.line.visible = !!(al && avatarPoint);
      shown[side] = null;
      if (!al) continue;
      m.target.position.fromArray(al.targetDip);
      if (avatarPoint) {
        m.avatar.position.copy(avatarPoint);
        const pos = m.line.geometry.attributes.position;
        pos.setXYZ(0, al.targetDip[0], al.targetDip[1], al.targetDip[2]);
        pos.setXYZ(1, avatarPoint.x, avatarPoint.y, avatarPoint.z);
        pos.needsUpdate = true;
        m.line.geometry.computeBoundingSphere();
        shown[side] = avatarPoint.distanceTo(m.target.position);
      }
    }
    return shown;
  }

  dispose() {
    this.scene.remove(this.vrm.scene);
    this.scene.remove(this.skeleton);
    VRMUtils.deepDispose(this.vrm.scene);
    this.skeleton.traverse((o) => {
      if (o.isMesh) o.material.dispose();
    });
  }
}
