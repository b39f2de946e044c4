// A fist from a recorded hand (issue 52: "chest contact for every hand shape"): the shared
// clips have a flat palm (`please`) and a curved hand (`hungry`) on the chest, and no fist.
// `fistFrames(rec, handedness)` returns the recording's frames with that MediaPipe hand's
// fingers curled into a fist where it was tracked, everything else as recorded:
//
// - world landmarks (metric): each finger bent at its three joints (MCP 90, PIP 100, DIP 70
//   degrees; the thumb 35 at its MCP and 60 at its IP) toward the palm side, about the axis
//   across the finger and the palm normal; the wrist and the palm's five knuckles do not move;
// - image landmarks: from the bent world landmarks through the affine map (3D -> image x, y,
//   z) fitted by least squares on the unmoved palm points of the same frame, so the image hand
//   keeps its place, size and perspective.
//
// Which side of the palm is its front (where fingers curl to) cannot be told from the
// landmarks alone; `palmAway` says it: true where the palm faces away from the camera (a palm
// on the chest, seen from the front), the side of the palm normal whose z (MediaPipe: away
// from the camera) is positive. Used by `node eval/skin-contact.mjs --fist` and
// `node tools/avatars/contact-sheet.mjs --touches`.

const FINGERS = [
  // [joints from the knuckle to the tip, bend at each joint in degrees]
  [[1, 2, 3, 4], [0, 35, 60]],
  [[5, 6, 7, 8], [90, 100, 70]],
  [[9, 10, 11, 12], [90, 100, 70]],
  [[13, 14, 15, 16], [90, 100, 70]],
  [[17, 18, 19, 20], [90, 100, 70]],
];
const PALM = [0, 1, 5, 9, 13, 17];

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const norm = (a) => scale(a, 1 / Math.hypot(...a));

/** `v` turned by `angle` (radians) about the unit axis `k` (Rodrigues). */
function turn(v, k, angle) {
  const c = Math.cos(angle);
  const s = Math.sin(angle);
  return add(add(scale(v, c), scale(cross(k, v), s)), scale(k, dot(k, v) * (1 - c)));
}

/** The 21 world points curled into a fist (see the module comment); `front` the palm's front normal. */
export function curl(world, front) {
  const out = world.map((p) => [...p]);
  for (const [joints, bends] of FINGERS) {
    for (let j = 0; j < 3; j++) {
      const at = out[joints[j]];
      const dir = norm(sub(out[joints[j + 1]], at));
      // Turning about dir x front moves dir toward front.
      const axis = norm(cross(dir, front));
      const angle = (bends[j] * Math.PI) / 180;
      for (let m = j + 1; m < 4; m++) out[joints[m]] = add(at, turn(sub(out[joints[m]], at), axis, angle));
    }
  }
  return out;
}

/** Least squares: the 3 x 4 affine map taking `from` (3D) to `to` (3D), as rows. */
function fitAffine(from, to) {
  // Normal equations A^T A x = A^T b, A rows [x y z 1]; a little ridge keeps them solvable.
  const ata = Array.from({ length: 4 }, () => new Array(4).fill(0));
  const atb = Array.from({ length: 3 }, () => new Array(4).fill(0));
  from.forEach((p, i) => {
    const a = [...p, 1];
    for (let r = 0; r < 4; r++) {
      for (let c = 0; c < 4; c++) ata[r][c] += a[r] * a[c];
      for (let o = 0; o < 3; o++) atb[o][r] += a[r] * to[i][o];
    }
  });
  for (let r = 0; r < 3; r++) ata[r][r] += 1e-9;
  return atb.map((b) => solve4(ata, b));
}

function solve4(m, b) {
  const a = m.map((row, i) => [...row, b[i]]);
  for (let c = 0; c < 4; c++) {
    let p = c;
    for (let r = c + 1; r < 4; r++) if (Math.abs(a[r][c]) > Math.abs(a[p][c])) p = r;
    [a[c], a[p]] = [a[p], a[c]];
    for (let r = 0; r < 4; r++) {
      if (r === c || a[c][c] === 0) continue;
      const f = a[r][c] / a[c][c];
      for (let k = c; k < 5; k++) a[r][k] -= f * a[c][k];
    }
  }
  return a.map((row, i) => row[4] / row[i]);
}

/**
 * The recording's frames with the `handedness` hand ("Left" / "Right", as MediaPipe labels it)
 * made a fist (see the module comment); `palmAway` as there.
 */
export function fistFrames(rec, handedness, { palmAway = true } = {}) {
  return rec.frames.map((f) => ({
    ...f,
    hands: (f.hands ?? []).map((h) => {
      if (h.handedness !== handedness) return h;
      const w = h.worldLandmarks;
      let front = norm(cross(sub(w[5], w[0]), sub(w[17], w[0])));
      if (front[2] < 0 === palmAway) front = scale(front, -1);
      const bent = curl(w, front);
      const map = fitAffine(
        PALM.map((i) => w[i]),
        PALM.map((i) => h.landmarks[i]),
      );
      const image = bent.map((p) => map.map((row) => row[0] * p[0] + row[1] * p[1] + row[2] * p[2] + row[3]));
      // The palm points keep their recorded image positions exactly.
      for (const i of PALM) image[i] = [...h.landmarks[i]];
      return { ...h, landmarks: image, worldLandmarks: bent };
    }),
  }));
}
