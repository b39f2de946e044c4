// The bundled real recordings, paired frame by frame into handrig frames.
//
// Hands: MediaPipe Hands output for a video of a right hand (assets/right-hand-video-mediapipe.json,
// not mirrored, so the subject's right hand is labelled "Left"; handrig maps it to the avatar's
// right hand with the default options). It goes to handrig unchanged as `frame.hands`.
//
// Wrists: an Azure Kinect body session (assets/kinect-upper-body.json), a different take of a
// different person, paired with the hand video by frame index (frame i of both; the session is
// the shorter one, 281 frames, so playback covers 281 frames). Its left hand touches the face
// around frames 130-160. Kinect gives no hand landmarks, so the avatar's left arm follows the
// Kinect wrist alone and the avatar's right arm carries the video's hand with alignment.
//
// Kinect frame -> avatar frame (handrig's `wrists` input, seed 000's Kinect wrist):
//   * The recording app's frame is +Y up, the subject faces the camera (+Z: the nose is at
//     larger z than the back of the head, the hands in front of the body), and the subject's
//     LEFT shoulder is at -X (it is a left-handed, mirror-view frame).
//   * The avatar (VRM 1.0 frame) faces +Z with its left at +X, so the conversion is a
//     reflection of x only: a = (-x, y, z). The subject's left wrist drives the avatar's left.
//   * Positions are made relative to the subject's shoulder joint (Kinect SHOULDER_*, the
//     glenohumeral joint = VRM upperArm) and scaled by avatar arm length / subject arm length
//     (upper + lower arm; the subject's from the median over the session, both sides
//     averaged, so per-frame tracking noise does not change the scale), then placed at the
//     avatar's upperArm rest position:
//         wrist = avatar upperArm + (L_avatar / L_subject) * (a(WRIST) - a(SHOULDER))
//   * VRM 0.x models face -Z in their own frame and handrig wants `wrists` in the model's own
//     frame, so for them the offset is turned 180 degrees about +Y (negate x and z).
//   * With the `mirror` option the avatar mirrors the user, and handrig sends the subject's
//     right hand to the avatar's left. `wrists` are already in the avatar's frame, so mirroring
//     them is the caller's job: the avatar's left wrist then comes from the subject's RIGHT
//     Kinect wrist, reflected left-right (x negated in the VRM 1.0 frame). (`inputMirrored`
//     concerns the image given to MediaPipe only and does not touch the Kinect data.)
// No wrist rotation is given: the hand's rotation comes from the hand landmarks.
//
// Body joints (handrig's `body` input, used with `torso: "pose"`): the Kinect joints of the
// docs/how-it-works/torso.md's mapping (PELVIS -> hips, HIP_* -> *UpperLeg, SHOULDER_* -> *UpperArm, NOSE, EYE_*,
// EAR_*), in the same reflected frame (a = (-x, y, z)), with their confidences; with `mirror`
// the sides swap and x is reflected again, for VRM 0.x models x and z are negated (model
// frame). handrig then turns, bends and nods the avatar's torso; the wrists are then placed
// from the shoulders as the torso poses them (`frameAt`'s `shoulders`), so that the arms stay
// attached to the moving torso.

const KINECT_FPS = 30;

// handrig body joint -> Kinect joint of the subject's [left, right] side (the same joint for
// central ones).
const BODY_JOINTS = {
  hips: ["PELVIS", "PELVIS"],
  leftUpperLeg: ["HIP_LEFT", "HIP_RIGHT"],
  rightUpperLeg: ["HIP_RIGHT", "HIP_LEFT"],
  leftUpperArm: ["SHOULDER_LEFT", "SHOULDER_RIGHT"],
  rightUpperArm: ["SHOULDER_RIGHT", "SHOULDER_LEFT"],
  nose: ["NOSE", "NOSE"],
  leftEye: ["EYE_LEFT", "EYE_RIGHT"],
  rightEye: ["EYE_RIGHT", "EYE_LEFT"],
  leftEar: ["EAR_LEFT", "EAR_RIGHT"],
  rightEar: ["EAR_RIGHT", "EAR_LEFT"],
};

/** Fetches and pairs the two recordings. */
export async function loadRecordings(base = "./assets/") {
  const [hands, kinect] = await Promise.all(
    ["right-hand-video-mediapipe.json", "kinect-upper-body.json"].map(async (f) => {
      const r = await fetch(base + f);
      if (!r.ok) throw new Error(`cannot load ${f}: HTTP ${r.status}`);
      return r.json();
    }),
  );
  return new PairedRecording(hands, kinect);
}

const median = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  const m = s.length >> 1;
  return s.length % 2 ? s[m] : (s[m - 1] + s[m]) / 2;
};
const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);

export class PairedRecording {
  constructor(hands, kinect) {
    if (!Array.isArray(hands) || !Array.isArray(kinect?.frames)) {
      throw new Error("recordings: unexpected format");
    }
    this.hands = hands;
    this.kinect = kinect;
    const idx = (n) => {
      const i = kinect.jointNames.indexOf(n);
      if (i < 0) throw new Error(`kinect recording: joint ${n} missing`);
      return i;
    };
    this.joint = {};
    for (const side of ["left", "right"]) {
      const S = side.toUpperCase();
      this.joint[side] = {
        shoulder: idx(`SHOULDER_${S}`),
        elbow: idx(`ELBOW_${S}`),
        wrist: idx(`WRIST_${S}`),
      };
    }
    this.bodyJoints = Object.entries(BODY_JOINTS).map(([joint, names]) => [joint, names.map(idx)]);
    this.length = Math.min(hands.length, kinect.frames.length);
    this.fps = KINECT_FPS;
    // Subject arm length (m): median over the session per side, sides averaged.
    const perSide = ["left", "right"].map((side) => {
      const j = this.joint[side];
      return median(
        kinect.frames.map((f) => dist(f.joints[j.shoulder], f.joints[j.elbow]) + dist(f.joints[j.elbow], f.joints[j.wrist])),
      );
    });
    this.subjectArmLength = (perSide[0] + perSide[1]) / 2;
  }

  /**
   * Per-avatar placement for `wristsAt`: the avatar's upperArm rest positions (model frame),
   * its arm length, and whether it is VRM 0.x.
   */
  placementFor(restPose) {
    const b = restPose.bones;
    const need = ["leftUpperArm", "leftLowerArm", "leftHand", "rightUpperArm", "rightLowerArm", "rightHand"];
    if (need.some((n) => !b[n])) return null;
    const arm = (s) => dist(b[`${s}UpperArm`], b[`${s}LowerArm`]) + dist(b[`${s}LowerArm`], b[`${s}Hand`]);
    return {
      shoulder: { left: b.leftUpperArm, right: b.rightUpperArm },
      scale: (arm("left") + arm("right")) / 2 / this.subjectArmLength,
      vrm0: restPose.vrmVersion === "0",
    };
  }

  /**
   * The Kinect wrists of frame `i` in the avatar's model frame (see the top of this file);
   * `mirror` as handrig's option of that name.
   */
  wristsAt(i, placement, mirror = false, shoulders = null) {
    if (!placement) return undefined;
    const f = this.kinect.frames[i].joints;
    const wrists = {};
    for (const side of ["left", "right"]) {
      const subjectSide = mirror ? (side === "left" ? "right" : "left") : side;
      const j = this.joint[subjectSide];
      const w = f[j.wrist];
      const s = f[j.shoulder];
      // a = (-x, y, z): subject's left (-X in Kinect) becomes the avatar's +X.
      let o = [-(w[0] - s[0]), w[1] - s[1], w[2] - s[2]];
      if (mirror) o[0] = -o[0];
      if (placement.vrm0) o = [-o[0], o[1], -o[2]];
      const base = shoulders?.[side] ?? placement.shoulder[side];
      const k = placement.scale;
      wrists[side] = { position: [base[0] + k * o[0], base[1] + k * o[1], base[2] + k * o[2]] };
    }
    return wrists;
  }

  /**
   * The Kinect body joints of frame `i` as handrig's `body` input (model frame; see the top of
   * this file).
   */
  bodyAt(i, placement, mirror = false) {
    const f = this.kinect.frames[i].joints;
    const body = {};
    for (const [joint, [left, right]] of this.bodyJoints) {
      const j = f[mirror ? right : left];
      let p = [-j[0], j[1], j[2]];
      if (mirror) p[0] = -p[0];
      if (placement?.vrm0) p = [-p[0], p[1], -p[2]];
      body[joint] = [p[0], p[1], p[2], j[3]];
    }
    return body;
  }

  /**
   * The handrig frame for index `i` (hands unchanged from MediaPipe, wrists converted, body
   * joints); `shoulders` ({ left, right } model-frame positions) places the wrists from the
   * torso's posed shoulders instead of the rest pose's.
   */
  frameAt(i, placement, mirror = false, shoulders = null) {
    const h = this.hands[i];
    return {
      timeMs: h.timeMs,
      hands: h.hands,
      wrists: this.wristsAt(i, placement, mirror, shoulders),
      body: this.bodyAt(i, placement, mirror),
    };
  }

  /** The frame's time and body joints alone (for a torso-only solve). */
  torsoFrameAt(i, placement, mirror = false) {
    return { timeMs: this.hands[i].timeMs, body: this.bodyAt(i, placement, mirror) };
  }
}
