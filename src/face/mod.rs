//! The face (issue 50): MediaPipe's face tracking into the avatar's expressions.
//!
//! In: FaceLandmarker's 52 blendshape categories (its `_neutral` left out, ARKit's
//! `tongueOut` added at 0: [`ARKIT`] order), its facial transformation matrix (4x4, column-major,
//! the canonical face in the camera's axes: x to the image right, y up, z toward the camera), or
//! without blendshapes a few face-mesh landmarks ([`MESH`]) from which the blinks and the mouth
//! are measured. Out: the 52 ARKit weights (perfect sync), the VRM 1.0 presets ([`PRESETS`]), the
//! look-at (yaw, pitch in degrees, three-vrm's `VRMLookAt` convention: yaw > 0 toward the avatar's
//! left, pitch > 0 down) and the head's world rotation.
//!
//! Sides: MediaPipe's blendshape names are the face's own sides in the image it was given (on
//! the shared clips `eyeBlinkLeft` follows the eye on the image's right and `eyeLookOutLeft` the
//! gaze toward it: the subject's left on an un-mirrored image), so they are swapped exactly when
//! the x axis is ([`CameraMapping::flips_x`]); after [`Face::solve`] every `Left` weight is the avatar's
//! left. See docs/how-it-works/face.md.

use glam::{Mat3, Quat, Vec3};

use crate::filter::one_euro::alpha;
use crate::input::mediapipe::CameraMapping;

/// How many ARKit blendshapes.
pub const SHAPES: usize = 52;

/// The 52 ARKit blendshape names in the order of the flat layout's `faceShapes` and `arkit`
/// (MediaPipe's order without `_neutral`, then `tongueOut`, which MediaPipe does not give).
pub const ARKIT: [&str; SHAPES] = [
    "browDownLeft",
    "browDownRight",
    "browInnerUp",
    "browOuterUpLeft",
    "browOuterUpRight",
    "cheekPuff",
    "cheekSquintLeft",
    "cheekSquintRight",
    "eyeBlinkLeft",
    "eyeBlinkRight",
    "eyeLookDownLeft",
    "eyeLookDownRight",
    "eyeLookInLeft",
    "eyeLookInRight",
    "eyeLookOutLeft",
    "eyeLookOutRight",
    "eyeLookUpLeft",
    "eyeLookUpRight",
    "eyeSquintLeft",
    "eyeSquintRight",
    "eyeWideLeft",
    "eyeWideRight",
    "jawForward",
    "jawLeft",
    "jawOpen",
    "jawRight",
    "mouthClose",
    "mouthDimpleLeft",
    "mouthDimpleRight",
    "mouthFrownLeft",
    "mouthFrownRight",
    "mouthFunnel",
    "mouthLeft",
    "mouthLowerDownLeft",
    "mouthLowerDownRight",
    "mouthPressLeft",
    "mouthPressRight",
    "mouthPucker",
    "mouthRight",
    "mouthRollLower",
    "mouthRollUpper",
    "mouthShrugLower",
    "mouthShrugUpper",
    "mouthSmileLeft",
    "mouthSmileRight",
    "mouthStretchLeft",
    "mouthStretchRight",
    "mouthUpperUpLeft",
    "mouthUpperUpRight",
    "noseSneerLeft",
    "noseSneerRight",
    "tongueOut",
];

/// The `Left`/`Right` pairs of [`ARKIT`] (indices): swapped when the avatar's left is the
/// label's right.
const PAIRS: [(u8, u8); 20] = [
    (0, 1),
    (3, 4),
    (6, 7),
    (8, 9),
    (10, 11),
    (12, 13),
    (14, 15),
    (16, 17),
    (18, 19),
    (20, 21),
    (23, 25),
    (27, 28),
    (29, 30),
    (32, 38),
    (33, 34),
    (35, 36),
    (43, 44),
    (45, 46),
    (47, 48),
    (49, 50),
];

// Indices into ARKIT.
const BROW_DOWN: usize = 0;
const BROW_INNER_UP: usize = 2;
const BROW_OUTER_UP: usize = 3;
const BLINK: usize = 8;
const LOOK_DOWN: usize = 10;
const LOOK_IN: usize = 12;
const LOOK_OUT: usize = 14;
const LOOK_UP: usize = 16;
const JAW_OPEN: usize = 24;
const MOUTH_CLOSE: usize = 26;
const FROWN: usize = 29;
const FUNNEL: usize = 31;
const PUCKER: usize = 37;
const SMILE: usize = 43;
const STRETCH: usize = 45;
const UPPER_UP: usize = 47;

/// How many VRM 1.0 presets the face gives.
pub const PRESET_COUNT: usize = 17;

/// The VRM 1.0 preset expressions, in the order of the flat layout's `expressions`.
pub const PRESETS: [&str; PRESET_COUNT] = [
    "happy",
    "angry",
    "sad",
    "relaxed",
    "surprised",
    "aa",
    "ih",
    "ou",
    "ee",
    "oh",
    "blink",
    "blinkLeft",
    "blinkRight",
    "lookUp",
    "lookDown",
    "lookLeft",
    "lookRight",
];

/// The face-mesh landmarks read without blendshapes (MediaPipe face mesh indices, 468 or 478
/// points), in the flat layout's `faceMesh` order: the image-left eye's outer corner, two upper
/// lid points, inner corner, two lower lid points (33 160 158 133 153 144), the image-right
/// eye's (263 387 385 362 380 373), the inner lips (13 upper, 14 lower), the mouth's corners
/// (61, 291), the forehead (10), the chin (152) and the cheeks' edges (234, 454).
pub const MESH: [u16; MESH_POINTS] = [
    33, 160, 158, 133, 153, 144, 263, 387, 385, 362, 380, 373, 13, 14, 61, 291, 10, 152, 234, 454,
];

/// How many face-mesh landmarks are read ([`MESH`]).
pub const MESH_POINTS: usize = 20;

/// One frame's face, as tracked (the flat layout's face-tracking section).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceObservation {
    /// Blendshape scores 0..1 in [`ARKIT`] order (MediaPipe's names and sides).
    pub shapes: Option<[f32; SHAPES]>,
    /// The facial transformation matrix, 16 numbers column-major.
    pub matrix: Option<[f32; 16]>,
    /// The [`MESH`] landmarks, normalized image coordinates.
    pub mesh: Option<[Vec3; MESH_POINTS]>,
}

/// The face's options (JS `options.face`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceOptions {
    /// Whether a tracked face drives expressions, look-at and the head.
    pub enabled: bool,
    /// One Euro smoothing of the weights and the head, and the blink's limited opening.
    pub smoothing: bool,
    /// One Euro cutoff at rest (Hz).
    pub min_cutoff: f32,
    /// One Euro speed coefficient.
    pub beta: f32,
    /// Shortest time (s) a closed eye takes to open.
    pub blink_open_time: f32,
    /// Seconds of face frames averaged into the neutral face (outliers left out:
    /// [`NEUTRAL_OUTLIER`]).
    pub calibration_time: f32,
    /// The neck's share of the head's turn (the head takes the rest).
    pub neck_share: f32,
    /// Whether the head and neck are turned by the face's matrix.
    pub head: bool,
}

/// Most eye rotation (degrees) a full `eyeLook*` weight stands for.
pub const EYE_RANGE_DEG: f32 = 30.0;
/// How much of `eyeLookDown` is taken off the same eye's blink (MediaPipe's lid closes as the
/// eye looks down, and its `eyeLookDown` rises on a real blink too: 0.7 on the shared clips' one
/// blink and on the bench's rendered ones). Chosen on the tuning half (the bench's woman, the
/// ASL clips `again`, `eat`, `please`, `thanks`): from 0.5 down to 0.2 no false blink appears
/// there and the woman's blinks come through from 0.3 on (0.1 gives the first false blink);
/// 0.25 keeps a step from that edge. Figures: docs/measurements/2026-12-06-face.md.
pub const LOOK_DOWN_BLINK: f32 = 0.25;
/// The head's One Euro speed coefficient over the weights' (`face.beta`): its speed is in rad/s,
/// a few a second at most, where a weight moves several units a second. 10 follows the shared
/// clips' nods within 2.2 degrees of the matrix on their tuning half (1: 5.4; `eval/face.mjs`).
pub const HEAD_BETA: f32 = 10.0;
/// A calibrated blink below this is open, above [`BLINK_CLOSED`] closed (between: linear).
pub const BLINK_OPEN: f32 = 0.2;
/// See [`BLINK_OPEN`].
pub const BLINK_CLOSED: f32 = 0.6;
/// Both eyes together: the smaller of the two eyes' corrected blinks below this is open, above
/// the user's closed level closed (linear between; each eye shows the larger of this and its
/// own ramp). Both lids rising together is a blink's own sign: on the ASL clips' open frames
/// the smaller eye reads at most 0.17-0.18 (signers looking down lower one lid more than the
/// other), where one eye alone reaches 0.30-0.33, so both eyes can close on less than one
/// eye; the bench's hooded man closes both at 0.32-0.39, under the one-eye ramp's 0.4.
pub const BOTH_OPEN: f32 = 0.15;
/// The user's closed level for both eyes before any blink is seen (see [`BOTH_OPEN`]): each
/// frame both eyes read as closed (at least half) adds its reading to a mean that starts at
/// this, weighted as [`BOTH_PRIOR_FRAMES`] frames, so the ramp ends at what this user's closed
/// eyes score (a hooded eye, glasses or a camera from below score them lower). Chosen on the
/// tuning half with [`BOTH_OPEN`]: the ramp's middle (0.30) halfway between the ASL clips'
/// largest open reading (0.17) and the bench woman's smallest closed one (0.43).
pub const BOTH_CLOSED: f32 = 0.45;
/// How many frames [`BOTH_CLOSED`] counts for in the user's closed level.
pub const BOTH_PRIOR_FRAMES: f32 = 10.0;
/// The lowest closed level learned (see [`BOTH_CLOSED`]): both eyes read as half closed from
/// 0.25 at least, 0.08 above the ASL tuning clips' largest open reading, however a user's
/// blinks score (a user who never closes their eyes is not taught to).
pub const BOTH_CLOSED_FLOOR: f32 = 0.35;
/// A wink: one eye's corrected blink this much above the other's is open, [`WINK_CLOSED`]
/// closed (each eye shows the larger of this and its own ramp). MediaPipe scores one closed
/// eye lower than both closed (0.2-0.45 on the bench's rendered winks where a blink scores
/// 0.5-0.78), with the other eye at 0. Chosen on the tuning half: the most of the bench woman's
/// wink frames (10 of 22; 5 with the one-eye ramp alone) with the ASL clips' other frames no
/// closer to a blink than 0.4 (`thanks`: one lid 0.37 above the other, looking down).
pub const WINK_OPEN: f32 = 0.25;
/// See [`WINK_OPEN`].
pub const WINK_CLOSED: f32 = 0.55;
/// The longest closure of both eyes whose readings teach the user's closed level
/// ([`BOTH_CLOSED`]), counted from its first closed frame to its first open one: a blink lasts
/// 100-400 ms (the bench's longest, 0.4 s), where a squint or a laugh holds both eyes half shut
/// for seconds and would sink the level to its floor (`eval/face-blink-both.mjs --squint`).
pub const BLINK_LEARN_MS: f64 = 500.0;
/// Hysteresis: an eye shown at least half closed the frame before reads this much higher in
/// its three ramps, so a held blink does not follow its reading's noise over the ramp's top
/// (the bench man's closed eyes read 0.32-0.39 under his learned level's 0.39: shown
/// 0.85-1.0 and moving 0.06 a frame). A blink still closes at the ramps' middle and opens
/// limited. The largest move of a held reading from one frame to the next on the tuning half
/// (the bench woman's still stretches: 0.035 open, 0.020 closed; `eval/face-blink-both.mjs
/// --noise`), so a closed eye keeps closed through a frame's noise.
pub const BLINK_HOLD: f32 = 0.035;
/// A shown blink's move of up to this in a frame is the channel's jitter, not a closing or an
/// opening: it is smoothed at the face's cutoff at rest (`alpha(dt, face.minCutoff)`, 0.295 at
/// 30 fps and the default 2 Hz). A rise: its first this much smoothed, the rest at once, and a
/// closing (from under half closed to at least half) all at once, so no blink is shown closed
/// a frame later; a fall of this or more, or to an eye read open, opens limited as before. A
/// half-read wink held on the report half (the bench child's: `eyeBlink` 0.42-0.44, a wink
/// ramp three times as steep) followed its reading's noise, 0.039 a frame. The size is not
/// chosen on data: issue 50's 0.02 a frame over that smoothing step (0.3), so jitter within it
/// moves at most 0.02 a frame at the defaults. On the tuning half (the bench woman, the ASL
/// clips again, eat, please, thanks) every size from 0.03 to 0.15 gives the same blink rows
/// and still moves under 0.02 (`eval/face-blink-both.mjs --still`). Figures:
/// docs/measurements/2026-12-06-face.md (still13).
pub const BLINK_STILL: f32 = 0.02 / 0.3;
/// A calibration frame whose weight is more than this above that weight's mean so far is left
/// out of its neutral value: an expression only raises a weight above the user's rest, and a
/// blink within the calibration (the bench's first two blinks fall within its 2 s; a user
/// blinks every 3-4 s) raised the mean `eyeBlink` and `eyeLookDown`, so every later blink read
/// lower. Frames within it are averaged as before (the neutral moves as smoothly). Chosen on
/// the tuning half (the bench's woman, the ASL clips again, eat, please, thanks): 0.3 to 0.5
/// leave no false blink on the ASL clips (0.25: 4 of 237 frames, 0.1: 6); 0.35 keeps the
/// largest blink on their open frames at the mean's 0.32 and raises the woman's closed frames'
/// blink 0.44 -> 0.50. The median gave the same blink but 0.41 on open frames, and jumped
/// (a still face's weights up to 0.23-0.32 in a frame) while an expression filled half the
/// calibration so far; an interquartile mean moved them twice as fast as the mean. Figures:
/// docs/measurements/2026-12-06-face.md.
pub const NEUTRAL_OUTLIER: f32 = 0.35;
/// The jaw's and mouth's weights (`jawForward` to `mouthUpperUpRight`, contiguous in
/// [`ARKIT`]) are filtered faster than the rest: a talking mouth opens and shuts 4-5 times a
/// second, and with the face's filter a mouth shut 1-2 frames after a wide opening still showed
/// `aa` 0.3-0.7 (the bench's talking clip: 61% of the woman's closed frames at most 0.1). Their
/// One Euro speed estimate is smoothed at [`MOUTH_D_CUTOFF`] Hz (the rest's at 1) and their speed
/// coefficient is [`MOUTH_BETA`] times `face.beta`. Chosen on the tuning half (the bench woman's
/// `face-talk`: every open frame at least 0.3 and every closed one at most 0.1; `aa`'s largest
/// move a frame on the ASL clips again, eat, please, thanks 0.043 -> 0.072) by a replica of this
/// arithmetic; reported on the man, the child and a real talking face in
/// docs/measurements/2026-12-06-face.md.
pub const MOUTH_D_CUTOFF: f32 = 10.0;
/// See [`MOUTH_D_CUTOFF`].
pub const MOUTH_BETA: f32 = 5.0;
/// The jaw's and mouth's weights in [`ARKIT`] (see [`MOUTH_D_CUTOFF`]).
const MOUTH: std::ops::Range<usize> = 22..49;
/// The mouth's gain: `aa` is the calibrated `jawOpen` times this.
pub const MOUTH_GAIN: f32 = 1.6;

/// A scalar One Euro filter.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Euro {
    x: f32,
    dx: f32,
}

/// Every weight's One Euro filter over one step (`dt` seconds; `None` or 0 restarts them at
/// `raw`): the filtered weights. One loop without branches over all 52 (the blinks' filters
/// run unused: their weights are limited instead; the mouth's take their own speed factor and
/// coefficient, [`MOUTH_D_CUTOFF`]); the speed factors once a step, not per weight. The same
/// arithmetic as one filter a weight: the same results, bit for bit.
fn filter_all(
    euro: &mut [Euro; SHAPES],
    raw: &[f32; SHAPES],
    dt: Option<f32>,
    o: &FaceOptions,
) -> [f32; SHAPES] {
    let mut out = [0.0; SHAPES];
    match dt {
        Some(dt) if dt > 0.0 => {
            // The mouth's weights with their own speed estimate and coefficient (MOUTH_D_CUTOFF).
            let alphas = [alpha(dt, 1.0), alpha(dt, MOUTH_D_CUTOFF)];
            let betas = [o.beta, o.beta * MOUTH_BETA];
            for (k, ((e, &v), y)) in euro.iter_mut().zip(raw).zip(&mut out).enumerate() {
                let m = usize::from(MOUTH.contains(&k));
                e.dx += alphas[m] * ((v - e.x) / dt - e.dx);
                e.x += alpha(dt, o.min_cutoff + betas[m] * e.dx.abs()) * (v - e.x);
                *y = e.x;
            }
        }
        _ => {
            for ((e, &v), y) in euro.iter_mut().zip(raw).zip(&mut out) {
                *e = Euro { x: v, dx: 0.0 };
                *y = v;
            }
        }
    }
    out
}

/// The face solver's history: filters, the neutral face, the blinks, the loss easing.
#[derive(Clone, Debug)]
pub struct Face {
    euro: [Euro; SHAPES],
    head: crate::filter::OneEuroQuat,
    /// Each weight's calibration frames taken into its neutral value: their sum and count.
    neutral_sum: [f32; SHAPES],
    neutral_count: [f32; SHAPES],
    neutral_frames: u32,
    /// The neutral face: `neutral_sum` over `neutral_count`, capped at 0.5 (updated with them).
    neutral: [f32; SHAPES],
    /// The frames both eyes read as closed: the sum of their readings and their count (the
    /// user's closed level, [`BOTH_CLOSED`]).
    closed_sum: f32,
    closed_count: f32,
    /// The closure of both eyes under way: its readings' sum and count, its first frame (ms);
    /// added to the closed level when it ends within [`BLINK_LEARN_MS`].
    run_sum: f32,
    run_count: f32,
    run_start: f64,
    calibration_start: Option<f64>,
    /// Last frame time with a face (ms).
    seen_ms: Option<f64>,
    /// The ARKit weights shown (avatar's sides).
    pub arkit: [f32; SHAPES],
    /// The presets shown.
    pub presets: [f32; PRESET_COUNT],
    /// Look-at yaw and pitch (degrees).
    pub look_at: [f32; 2],
    /// The head's world rotation (avatar frame) last tracked.
    pub head_rotation: Option<Quat>,
}

impl Default for Face {
    fn default() -> Self {
        Face {
            euro: [Euro::default(); SHAPES],
            head: crate::filter::OneEuroQuat::default(),
            neutral_sum: [0.0; SHAPES],
            neutral_count: [0.0; SHAPES],
            neutral_frames: 0,
            neutral: [0.0; SHAPES],
            closed_sum: 0.0,
            closed_count: 0.0,
            run_sum: 0.0,
            run_count: 0.0,
            run_start: 0.0,
            calibration_start: None,
            seen_ms: None,
            arkit: [0.0; SHAPES],
            presets: [0.0; PRESET_COUNT],
            look_at: [0.0; 2],
            head_rotation: None,
        }
    }
}

fn clamp01(x: f32) -> f32 {
    x.clamp(0.0, 1.0)
}

/// The head's world rotation from a facial transformation matrix (column-major), in the
/// avatar frame: the matrix's rotation orthonormalized, mirrored when `flip`.
#[must_use]
pub fn head_rotation(m: &[f32; 16], flip: bool) -> Quat {
    let c0 = Vec3::new(m[0], m[1], m[2]);
    let c1 = Vec3::new(m[4], m[5], m[6]);
    let x = c0.normalize_or(Vec3::X);
    let y = (c1 - x * x.dot(c1)).normalize_or(Vec3::Y);
    let q = Quat::from_mat3(&Mat3::from_cols(x, y, x.cross(y))).normalize();
    if flip {
        Quat::from_xyzw(q.x, -q.y, -q.z, q.w)
    } else {
        q
    }
}

/// ARKit-like weights measured on face-mesh landmarks (no blendshapes): the blinks from each
/// eye's opening over its width, `jawOpen` from the inner lips' gap over the face's height,
/// `mouthPucker` and `mouthStretch` from the mouth's width over the face's width. The rest stay
/// 0. Constants are typical faces'; the neutral calibration takes each user's offsets off.
fn from_mesh(p: &[Vec3; MESH_POINTS], aspect: f32, out: &mut [f32; SHAPES]) {
    let q = |k: usize| Vec3::new(p[k].x * aspect, p[k].y, p[k].z * aspect);
    let d = |a: usize, b: usize| (q(a) - q(b)).truncate().length();
    *out = [0.0; SHAPES];
    for e in 0..2 {
        let b = 6 * e;
        let ear = (d(b + 1, b + 5) + d(b + 2, b + 4)) / (2.0 * d(b, b + 3)).max(1e-6);
        // Open eyes measure about 0.3, closed about 0.08. The image-left eye (e = 0) is the
        // face's right.
        out[BLINK + 1 - e] = clamp01((0.28 - ear) / 0.2);
    }
    let height = d(16, 17).max(1e-6);
    let width = d(18, 19).max(1e-6);
    out[JAW_OPEN] = clamp01(d(12, 13) / height / 0.2);
    let mouth = d(14, 15) / width;
    out[PUCKER] = clamp01((0.38 - mouth) / 0.1);
    let wide = clamp01((mouth - 0.42) / 0.1);
    out[STRETCH] = wide;
    out[STRETCH + 1] = wide;
}

impl Face {
    /// Starts the neutral face's calibration again from the next face frame.
    pub fn calibrate(&mut self) {
        self.neutral_sum = [0.0; SHAPES];
        self.neutral_count = [0.0; SHAPES];
        self.neutral_frames = 0;
        self.calibration_start = None;
        self.closed_sum = 0.0;
        self.closed_count = 0.0;
        self.run_sum = 0.0;
        self.run_count = 0.0;
    }

    /// A frame without a face: the next face restarts the filters.
    pub fn lose(&mut self) {
        self.seen_ms = None;
    }

    /// Whether a face was seen since the last loss.
    #[must_use]
    pub fn seen(&self) -> bool {
        self.seen_ms.is_some()
    }

    /// Forgets the history but the neutral face and the closed eyes' level.
    pub fn restart(&mut self) {
        let (sum, count, n, neutral, start) = (
            self.neutral_sum,
            self.neutral_count,
            self.neutral_frames,
            self.neutral,
            self.calibration_start,
        );
        let closed = (self.closed_sum, self.closed_count);
        *self = Face::default();
        (self.closed_sum, self.closed_count) = closed;
        self.neutral_sum = sum;
        self.neutral_count = count;
        self.neutral_frames = n;
        self.neutral = neutral;
        self.calibration_start = start;
    }

    /// One frame with a face: fills [`Face::arkit`], [`Face::presets`], [`Face::look_at`] and
    /// [`Face::head_rotation`]. `dt`: seconds since the last face frame's, `None` restarts the
    /// filters.
    pub fn solve(
        &mut self,
        obs: &FaceObservation,
        camera: CameraMapping,
        aspect: f32,
        now_ms: f64,
        dt: Option<f32>,
        o: &FaceOptions,
    ) {
        // A face after a loss restarts the filters.
        let dt = dt.filter(|_| self.seen_ms.is_some());
        self.seen_ms = Some(now_ms);
        let mut raw = [0.0; SHAPES];
        if let Some(s) = &obs.shapes {
            raw = s.map(clamp01);
        } else if let Some(m) = &obs.mesh {
            from_mesh(m, aspect, &mut raw);
        }
        if camera.flips_x() {
            for (a, b) in PAIRS {
                raw.swap(a as usize, b as usize);
            }
        }
        // The neutral face: each weight's mean over the first `calibration_time` seconds of
        // face frames, but for frames more than NEUTRAL_OUTLIER above the mean so far (a blink).
        let start = *self.calibration_start.get_or_insert(now_ms);
        if now_ms - start <= f64::from(o.calibration_time) * 1000.0 || self.neutral_frames == 0 {
            let first = self.neutral_frames == 0;
            self.neutral_frames = self.neutral_frames.saturating_add(1);
            for (((s, c), &r), n) in self
                .neutral_sum
                .iter_mut()
                .zip(&mut self.neutral_count)
                .zip(&raw)
                .zip(&mut self.neutral)
            {
                if first || r <= *s / *c + NEUTRAL_OUTLIER {
                    *s += r;
                    *c += 1.0;
                }
                *n = (*s / *c).min(0.5);
            }
        }
        let neutral = self.neutral;
        let cal = |k: usize, x: f32| clamp01((x - neutral[k]) / (1.0 - neutral[k]));
        // Smoothing: One Euro per weight; a blink closes at once and opens at most at the
        // limited speed (a low-pass would lag the close).
        let dt = dt.filter(|_| o.smoothing);
        let open_step = dt.map(|dt| dt / o.blink_open_time.max(1e-3));
        let limit = |x: f32, prev: f32| match open_step {
            Some(step) if x < prev => x.max(prev - step),
            _ => x,
        };
        // A shown blink's small moves are smoothed (BLINK_STILL).
        let settle = dt.map_or(1.0, |dt| alpha(dt, o.min_cutoff));
        let shown_blinks = [
            self.presets[10] + self.presets[11],
            self.presets[10] + self.presets[12],
        ];
        // A lid lowered by looking down is not a blink: each eye's calibrated blink less a
        // share of its calibrated look-down.
        let b = [0, 1].map(|e| {
            cal(BLINK + e, raw[BLINK + e])
                - LOOK_DOWN_BLINK * cal(LOOK_DOWN + e, raw[LOOK_DOWN + e])
        });
        // Both eyes together, up to the user's closed level (learned from the frames read as
        // closed in closures as short as a blink, from a prior, floored).
        let both = b[0].min(b[1]);
        let level = ((BOTH_CLOSED * BOTH_PRIOR_FRAMES + self.closed_sum)
            / (BOTH_PRIOR_FRAMES + self.closed_count))
            .max(BOTH_CLOSED_FLOOR);
        if (both - BOTH_OPEN) / (level - BOTH_OPEN) >= 0.5 {
            if self.run_count == 0.0 {
                self.run_start = now_ms;
            }
            self.run_sum += both;
            self.run_count += 1.0;
        } else {
            if now_ms - self.run_start <= BLINK_LEARN_MS {
                self.closed_sum += self.run_sum;
                self.closed_count += self.run_count;
            }
            self.run_sum = 0.0;
            self.run_count = 0.0;
        }
        let mut blinks = [0.0; 2];
        for e in 0..2 {
            let k = BLINK + e;
            self.arkit[k] = limit(raw[k], self.arkit[k]);
            // Each eye: its own ramp (BLINK_OPEN..BLINK_CLOSED), both eyes' and a wink's
            // (above the other eye), the largest; read BLINK_HOLD higher while shown closed.
            let hold = if open_step.is_some() && shown_blinks[e] >= 0.5 {
                BLINK_HOLD
            } else {
                0.0
            };
            let own = clamp01((b[e] + hold - BLINK_OPEN) / (BLINK_CLOSED - BLINK_OPEN));
            let together = clamp01((both + hold - BOTH_OPEN) / (level - BOTH_OPEN));
            let wink = clamp01((b[e] + hold - b[1 - e] - WINK_OPEN) / (WINK_CLOSED - WINK_OPEN));
            let (x, p) = (own.max(together).max(wink), shown_blinks[e]);
            blinks[e] = match open_step {
                // A rise but a closing (from under half closed to at least half): its first
                // BLINK_STILL smoothed, the rest at once.
                Some(_) if x > p && (p >= 0.5 || x < 0.5) => {
                    x - (1.0 - settle) * (x - p).min(BLINK_STILL)
                }
                // A fall under BLINK_STILL to an eye not read open: smoothed.
                Some(_) if x > 0.0 && x < p && p - x < BLINK_STILL => p - settle * (p - x),
                _ => limit(x, p),
            };
        }
        let filtered = filter_all(&mut self.euro, &raw, dt, o);
        for k in (0..SHAPES).filter(|k| *k != BLINK && *k != BLINK + 1) {
            self.arkit[k] = filtered[k];
        }
        let a = &self.arkit;
        let one = |k: usize| cal(k, a[k]);
        let pair = |k: usize| 0.5 * (one(k) + one(k + 1));
        // Emotions, summing to at most 1 (nothing tracked tells "relaxed").
        let mut emotions = [
            pair(SMILE),
            pair(BROW_DOWN),
            pair(FROWN),
            0.0,
            0.5 * (one(BROW_INNER_UP) + pair(BROW_OUTER_UP)),
        ];
        normalize_sum(&mut emotions);
        // Mouth shapes, summing to at most 1.
        let mut mouth = [
            clamp01(MOUTH_GAIN * (one(JAW_OPEN) - one(MOUTH_CLOSE))),
            pair(UPPER_UP),
            one(PUCKER),
            pair(STRETCH),
            one(FUNNEL),
        ];
        normalize_sum(&mut mouth);
        // Gaze: the avatar's left eye looking out and its right eye looking in turn it left.
        let h = 0.5 * (one(LOOK_OUT) + one(LOOK_IN + 1) - one(LOOK_IN) - one(LOOK_OUT + 1));
        let v = 0.5 * (one(LOOK_UP) + one(LOOK_UP + 1) - one(LOOK_DOWN) - one(LOOK_DOWN + 1));
        let both = blinks[0].min(blinks[1]);
        self.presets[..5].copy_from_slice(&emotions);
        self.presets[5..10].copy_from_slice(&mouth);
        self.presets[10..].copy_from_slice(&[
            both,
            blinks[0] - both,
            blinks[1] - both,
            clamp01(v),
            clamp01(-v),
            clamp01(h),
            clamp01(-h),
        ]);
        // three-vrm's pitch is > 0 looking down.
        self.look_at = [h * EYE_RANGE_DEG, -v * EYE_RANGE_DEG];
        self.head_rotation = obs.matrix.map(|m| {
            let euro = crate::filter::OneEuroOptions {
                min_cutoff: o.min_cutoff,
                beta: o.beta * HEAD_BETA,
                d_cutoff: 1.0,
            };
            self.head.filter(
                head_rotation(&m, camera.flips_x()),
                dt.unwrap_or(0.0),
                &euro,
            )
        });
    }
}

/// Scales `x` down so it sums to at most 1.
fn normalize_sum(x: &mut [f32]) {
    let s: f32 = x.iter().sum();
    if s > 1.0 {
        for v in x.iter_mut() {
            *v /= s;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`MOUTH`] is the jaw's and mouth's weights of [`ARKIT`], and only those.
    #[test]
    fn the_mouth_range_is_the_jaw_and_mouth_weights() {
        for (k, name) in ARKIT.iter().enumerate() {
            let mouth = name.starts_with("jaw") || name.starts_with("mouth");
            assert_eq!(MOUTH.contains(&k), mouth, "{k} {name}");
        }
    }
}
