// Generated from the option table (src/options/table.rs) by `HANDRIG_GENERATE=write cargo test
// --lib options`; a test fails when this file is stale. Do not edit.

/** Options, set at construction. `HandRig.optionDescriptions()` lists them with ranges and defaults. */
export interface HandRigOptions {
  /** The image given to MediaPipe was flipped horizontally (selfie view). (boolean, default `false`.) */
  inputMirrored?: boolean | undefined;
  /** The avatar mirrors the user: the user's right hand drives the avatar's left. (boolean, default `false`.) */
  mirror?: boolean | undefined;
  /** How hands are solved: analytic = palm frame + anatomically limited joint angles; retarget = the avatar's fingertips placed where the user's are (scaled to the avatar's hand), within the same limits. (one of `"analytic"`, `"retarget"`, default `"analytic"`.) */
  handStrategy?: "analytic" | "retarget" | undefined;
  /** Arm IK solver reaching the wrist target: twoBone = analytic two-bone IK with a pole; fabrik = FABRIK (seed 002); ccd = CCD with priority effectors (seed 004). (one of `"twoBone"`, `"fabrik"`, `"ccd"`, default `"twoBone"`.) */
  armSolver?: "twoBone" | "fabrik" | "ccd" | undefined;
  /** Options every arm solver shares. */
  arm?: {
    /** Largest angle (radians) the shoulder turns to help a far reach; 0 keeps shoulders at rest. (number in 0..1.5707964, default `0.26`.) */
    shoulderAngle?: number | undefined;
    /** Fraction of the arm's length beyond which the shoulder starts to turn toward the target. (number in 0.5..1, default `0.9`.) */
    shoulderReach?: number | undefined;
    /** Share of the hand's twist about the forearm that the forearm takes (the rest stays at the wrist). (number in 0..1, default `0.5`.) */
    forearmTwist?: number | undefined;
    /** Clamp wrist flexion (80°), extension (70°), radial (20°) and ulnar (40°) deviation against the forearm; the hand turns about the aligned fingertip, so alignment stays exact. (boolean, default `true`.) */
    wristLimits?: boolean | undefined;
    /** Fastest turn of an arm or hand (rad/s): a faster one (a tracking flip) is spread over frames. 0 = no limit. (number in 0..1000, default `23`.) */
    maxTurnSpeed?: number | undefined;
    /** Where an arm with no wrist to follow rests: down = by the side, elbow slightly bent; tpose = the avatar's rest pose. (one of `"down"`, `"tpose"`, default `"down"`.) */
    idle?: "down" | "tpose" | undefined;
  } | undefined;
  /** Arms from hands alone (no pose): the camera and framing assumed. `false` / `true` sets `enabled`. */
  handsOnly?:
    | boolean
    | {
        /** No pose: each arm placed from its hand's image position and size. (boolean, default `true`.) */
        enabled?: boolean | undefined;
        /** Camera's vertical field of view (radians; 1.05 = 60°). (number in 0.1..3, default `1.05`.) */
        fov?: number | undefined;
        /** The user's shoulders' distance from the camera (m). (number in 0.2..5, default `0.9`.) */
        distance?: number | undefined;
        /** The shoulder line's height in the image (0 top, 1 bottom). (number in -1..2, default `0.7`.) */
        shoulderY?: number | undefined;
      }
    | undefined;
  /** Fingertip alignment (seeds 000/001). `false` / `true` sets `enabled`. */
  alignment?:
    | boolean
    | {
        /** Fingertip alignment: place the wrist so the avatar's finger lands where the user's is. (boolean, default `true`.) */
        enabled?: boolean | undefined;
        /** Which finger is aligned. On an avatar without its distal bone, its deepest bone, another finger or the palm stands in (reported in alignment.<side>.finger and .bone; docs/how-it-works/alignment-ik.md). (one of `"thumb"`, `"index"`, `"middle"`, `"ring"`, `"little"`, default `"index"`.) */
        finger?: "thumb" | "index" | "middle" | "ring" | "little" | undefined;
        /** Aligned point: dip = the distal bone's joint (exact); tip = distal bone extended by anatomical ratio. (one of `"dip"`, `"tip"`, default `"dip"`.) */
        point?: "dip" | "tip" | undefined;
        /** Blend between the plain pose wrist (0) and the fully aligned wrist (1). (number in 0..1, default `1`.) */
        weight?: number | undefined;
      }
    | undefined;
  /** Body-scale calibration from pose landmarks. */
  calibration?: {
    /** Preset body scale (avatar arm / user arm) for pose input; unset = calibrate automatically. (number in 0.1..10, default unset.) */
    bodyScale?: number | null | undefined;
    /** Pose frames with a visible arm that automatic body-scale calibration averages (outliers beyond 20% of the median dropped). (whole number in 1..300, default `30`.) */
    frames?: number | undefined;
    /** Pose landmarks below this visibility are ignored (arm at rest without a visible wrist; default elbow pole without a visible elbow). (number in 0..1, default `0.5`.) */
    minVisibility?: number | undefined;
  } | undefined;
  /** Hands whose handedness score is below this are ignored. (number in 0..1, default `0.5`.) */
  minHandScore?: number | undefined;
  /** A hand whose label contradicts the pose wrists (needs hand and pose image landmarks): reassign = drives the side the pose says; drop = ignored; trust = MediaPipe's label decides. (one of `"reassign"`, `"drop"`, `"trust"`, default `"reassign"`.) */
  handedness?: "reassign" | "drop" | "trust" | undefined;
  /** One Euro filtering of the landmarks. `false` / `true` sets `enabled`. */
  filter?:
    | boolean
    | {
        /** One Euro filtering of the landmarks (hands, pose, tracker wrists) before solving; alignment and IK stay exact on the filtered data. (boolean, default `true`.) */
        enabled?: boolean | undefined;
        /** One Euro cutoff at rest (Hz): lower is smoother, with more lag. (number in 0.05..1000, default `1.5`.) */
        minCutoff?: number | undefined;
        /** One Euro speed coefficient (Hz per m/s): higher follows fast motion with less lag. (number in 0..10000, default `2`.) */
        beta?: number | undefined;
        /** One Euro cutoff of the speed estimate (Hz). (number in 0.05..1000, default `1`.) */
        dCutoff?: number | undefined;
      }
    | undefined;
  /** Where the torso comes from: frame = the app's frame.torso (rest where not given; handrig does not write the torso bones); pose = tracked from frame.body joints or the pose (handrig drives hips, spine, chest, upperChest, neck, head, shoulders); off = the rest torso. (one of `"off"`, `"frame"`, `"pose"`, default `"frame"`.) */
  torso?: "off" | "frame" | "pose" | undefined;
  /** Holding and easing over tracking loss. `false` / `true` sets `enabled`. */
  dropout?:
    | boolean
    | {
        /** A lost hand or arm holds its pose, then eases to rest; a returning one blends in (otherwise both snap). (boolean, default `true`.) */
        enabled?: boolean | undefined;
        /** How long a lost hand or arm keeps its last pose (ms). (number in 0..10000, default `250`.) */
        holdMs?: number | undefined;
        /** How long it then takes to ease to rest (ms). (number in 0..10000, default `500`.) */
        fadeOutMs?: number | undefined;
        /** How long a returning hand or arm blends from the shown pose to the solved one (ms). (number in 0..10000, default `250`.) */
        fadeInMs?: number | undefined;
      }
    | undefined;
  /** Self-contact retargeting: face, hand-to-hand, body colliders. `false` / `true` sets `enabled`. */
  contact?:
    | boolean
    | {
        /** Self-contact retargeting: a finger on the user's face lands on the avatar's face, touching hands stay touching, hands stay out of the avatar's body. (boolean, default `true`.) */
        enabled?: boolean | undefined;
        /** Contact blend radius in head breadths (the user's ear-to-ear distance, about 0.145 m): full contact mapping within half of it, plain alignment beyond it. (number in 0.05..3, default `0.5`.) */
        radius?: number | undefined;
        /** Scale of the contact blend: 0 = plain alignment, 1 = full contact mapping near the face or the other hand. (number in 0..1, default `1`.) */
        weight?: number | undefined;
        /** Hand-to-hand contact: when the user's hands touch, both avatar targets are solved together so its hands touch too. (boolean, default `true`.) */
        hands?: boolean | undefined;
        /** The avatar's face points, each [x, y, z] meters from the head bone at rest in the model's axes (e.g. raycast on its mesh); missing ones are derived from the rig (eye bones, look-at offset, an average face). (object of [x, y, z] (meters, within 10) named nose, chin, mouth, leftCheek, rightCheek, leftEar, rightEar, forehead, default unset.) */
        faceAnchors?: { [name in "nose" | "chin" | "mouth" | "leftCheek" | "rightCheek" | "leftEar" | "rightEar" | "forehead"]?: [number, number, number] | { x: number; y: number; z: number } | null } | null | undefined;
        /** Body colliders (torso and neck capsules, head sphere, derived from the rig) push hand targets out of the avatar's body. (boolean, default `true`.) */
        colliders?: boolean | undefined;
        /** Torso capsule radius (m, hips to chest); unset = 0.6 x the shoulder half-width; 0 = no torso collider. (number in 0..2, default unset.) */
        torsoRadius?: number | null | undefined;
        /** Head sphere radius (m); unset = half the head breadth; 0 = no head collider (never covers a face anchor). (number in 0..2, default unset.) */
        headRadius?: number | null | undefined;
        /** MediaPipe pose input: how much the tracked depth between fingertip and face counts (monocular hand depth at the face is off by 15-35 cm); where on the face comes from the image. 1 = as tracked; tracker input always uses its depth. (number in 0..1, default `0.1`.) */
        depthTrust?: number | undefined;
        /** How fast (m/s) contact may move a hand's target onto the face, chest or other hand: a touch lands over a few frames instead of jerking the arm. 0 = no limit. (number in 0..20, default `6`.) */
        maxSpeed?: number | undefined;
      }
    | undefined;
  /** The objective of handStrategy "retarget" (seed 003). */
  retarget?: {
    /** handStrategy retarget: fingertip weights, thumb to little (thumb and index emphasized for pinching, as the seed does). (5 numbers in 0..1000, default `[2, 2, 1, 1, 1]`.) */
    tipWeights?: [number, number, number, number, number] | undefined;
    /** handStrategy retarget: weight of each intermediate joint, hung back from the fingertip target along the user's phalanges. (number in 0..1000, default `0.02`.) */
    jointWeight?: number | undefined;
    /** handStrategy retarget: weight of the thumb tip relative to the index tip when the user pinches (within half of pinchDistance, fading out at it). (number in 0..10000, default `10`.) */
    pinchWeight?: number | undefined;
    /** handStrategy retarget: scaled thumb-index tip distance (m) below which the pinch term counts. (number in 0.001..0.5, default `0.04`.) */
    pinchDistance?: number | undefined;
    /** handStrategy retarget: weight (m^2/rad^2) pulling each DIP toward two thirds of its PIP. (number in 0..1, default `0.000002`.) */
    spatialWeight?: number | undefined;
    /** handStrategy retarget: weight (m^2/rad^2) toward the previous frame's angles for a finger whose target stood still. (number in 0.000000001..1, default `0.004`.) */
    temporalWeight?: number | undefined;
    /** handStrategy retarget: the fingertip target move (m per frame) at which the temporal weight has halved. (number in 0.00001..1, default `0.003`.) */
    temporalSpeed?: number | undefined;
    /** handStrategy retarget: most Gauss-Newton iterations per finger and frame. (whole number in 1..1000, default `50`.) */
    maxIterations?: number | undefined;
    /** handStrategy retarget: converged when a Gauss-Newton step's largest angle is at most this (radians). (number in 0..1, default `0.0001`.) */
    stepTolerance?: number | undefined;
  } | undefined;
  /** Options. `false` / `true` sets `enabled`. */
  face?:
    | boolean
    | {
        /** A tracked face (FaceLandmarker, Holistic) drives the expressions, the look-at and the head. (boolean, default `true`.) */
        enabled?: boolean | undefined;
        /** One Euro smoothing of the face's weights and head, and the blink's limited opening; false = each frame's weights as tracked. (boolean, default `true`.) */
        smoothing?: boolean | undefined;
        /** Face smoothing: One Euro cutoff at rest (Hz); lower is smoother and slower. (number in 0.01..30, default `2`.) */
        minCutoff?: number | undefined;
        /** Face smoothing: how fast the cutoff rises with a weight's speed (per unit/s); the head's is 10 times it (per rad/s). (number in 0..100, default `1`.) */
        beta?: number | undefined;
        /** Shortest time (s) a closed eye takes to open (a blink closes at once). (number in 0..1, default `0.1`.) */
        blinkOpenTime?: number | undefined;
        /** Seconds of the first face frames averaged into the neutral face, a frame far above the average so far (a blink) left out (again after rig.calibrateFace()). (number in 0..60, default `2`.) */
        calibrationTime?: number | undefined;
        /** The neck's share of the head's turn from the face (the head bone takes the rest). (number in 0..1, default `0.3`.) */
        neckShare?: number | undefined;
        /** The face's transformation matrix turns the head and neck (over the torso's chest). (boolean, default `true`.) */
        head?: boolean | undefined;
      }
    | undefined;
  /** Options. `false` / `true` sets `enabled`. */
  legs?:
    | boolean
    | {
        /** Legs from the pose's lower body (two-bone IK, knee and ankle limits); a leg whose hip, knee or ankle is not seen stays standing at rest. (boolean, default `true`.) */
        enabled?: boolean | undefined;
        /** A leg is tracked when its hip, knee and ankle have at least this visibility and lie inside the image (when the pose's image landmarks are given). (number in 0..1, default `0.5`.) */
        minVisibility?: number | undefined;
        /** The hips move with the user while the legs are tracked: up and down so the lower foot stands on the avatar's floor, sideways and toward the camera from the pose's image (hipsOffset); false keeps them at rest. (boolean, default `true`.) */
        moveHips?: boolean | undefined;
        /** A foot on the floor that bears weight stays where it was planted (no sliding) until it lifts or moves off. (boolean, default `true`.) */
        plant?: boolean | undefined;
        /** Where legs that are not seen rest: "standing" (the avatar's rest pose) or "seated" (hips and knees bent 90 degrees, feet flat, the hips in place: for a webcam that sees a seated user from the waist up). (one of `"standing"`, `"seated"`, default `"standing"`.) */
        rest?: "standing" | "seated" | undefined;
      }
    | undefined;
  /** Options. */
  camera?: {
    /** How far the camera looks down (radians; negative: up; 0.5 = 29°), taken out of the pose's world landmarks (oriented with the camera) before the legs are solved; null = estimated over a few seconds from the user's straight legs. (number in -1.5..1.5, default unset.) */
    pitch?: number | null | undefined;
  } | undefined;
  /** Dotted paths as `optionDescriptions()` spells them are accepted too: `{ "alignment.weight": 0.5 }`. */
  [dottedPath: `${string}.${string}`]: unknown;
}
