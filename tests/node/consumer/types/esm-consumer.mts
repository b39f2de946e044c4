// Type-checked (not run) by types.test.mjs: the ES module API as an app would write it, with no
// DOM lib and no @types/node (tsconfig.strict.json).
import init, { HandRig, MotionRecorder, initSync, version } from "handrig";
import type { BVHOptions, Frame, HandRigOptions, OptionDescription, Quat, RestPose, SolveResult, VRMAOptions, Vec3 } from "handrig";

declare const bytes: Uint8Array;
declare const buffer: ArrayBuffer;

await init();
initSync(buffer);
const v: string = version;

const options: HandRigOptions = {
  inputMirrored: false,
  mirror: true,
  alignment: { enabled: true, finger: "index", point: "tip", weight: 0.5 },
  calibration: { bodyScale: 1.1 },
  minHandScore: 0.6,
};
const rig: HandRig = HandRig.fromVrm(bytes, options);
const rest: RestPose = { bones: rig.restWorldPositions(), vrmVersion: rig.vrmVersion };
const rig2 = new HandRig(rest);
HandRig.fromVrm(buffer);

const landmarks = Array.from({ length: 21 }, (_, i) => ({ x: i, y: 0, z: 0 }));
const frames: Frame[] = [
  { timeMs: 0, hands: [{ handedness: "Left", score: 0.9, worldLandmarks: new Float32Array(63) }] },
  { timeMs: 1, hands: [{ handedness: "Right", worldLandmarks: landmarks, landmarks }] },
  { timeMs: 2, hands: { worldLandmarks: [landmarks], landmarks: [landmarks], handedness: [[{ categoryName: "Left", score: 1 }]] } },
  { timeMs: 3, hands: { multiHandWorldLandmarks: [landmarks], multiHandedness: [{ label: "Right", score: 1 }] } },
  { timeMs: 4, pose: { worldLandmarks: Array.from({ length: 33 }, () => ({ x: 0, y: 0, z: 0, visibility: 1 })) } },
  { timeMs: 5, wrists: { right: { position: [0.3, 1.2, 0.1], rotation: [0, 0, 0, 1] } } },
];
// A tasks-vision HolisticLandmarkerResult spread into a frame.
const pose33 = Array.from({ length: 33 }, () => ({ x: 0, y: 0, z: 0, visibility: 1 }));
rig.solve({
  timeMs: 6,
  faceLandmarks: [],
  faceBlendshapes: [],
  poseLandmarks: [pose33],
  poseWorldLandmarks: [pose33],
  poseSegmentationMasks: [],
  leftHandLandmarks: [landmarks],
  leftHandWorldLandmarks: [landmarks],
  rightHandLandmarks: [],
  rightHandWorldLandmarks: [],
});
for (const frame of frames) {
  const r: SolveResult = rig.solve(frame);
  const q: Quat | undefined = r.bones.rightIndexDistal;
  const p: Vec3 | undefined = r.worldPositions.rightHand;
  const target: Vec3 | undefined = r.ikTargets.left?.position;
  const error: number | null | undefined = r.alignment.right?.error;
  void [q, p, target, error];
}
const recorder = new MotionRecorder(rig);
recorder.add(0, rig.solve({ timeMs: 0 }));
const vrmaOptions: VRMAOptions = { tolerance: 0.005 };
const bvhOptions: BVHOptions = { unit: "m", fps: 30 };
const vrma: Uint8Array = recorder.toVRMA(vrmaOptions);
const bvh: string = recorder.toBVH(bvhOptions);
const recorded: number = recorder.frameCount + recorder.duration;
recorder.clear();
void [vrma, bvh, recorded];
// @ts-expect-error the BVH unit is "cm" or "m"
recorder.toBVH({ unit: "mm" });
const names: string[] = rig.boneNames();
const scale: number = rig.bodyScale;
rig.resetCalibration();
const described: OptionDescription[] = HandRig.optionDescriptions();
for (const d of described) {
  if (d.type === "enum") void d.values.join();
  if (d.type === "number") void (d.min + d.max + d.step);
}
const freed: boolean = rig.freed;
rig.free();
rig2.free();
void [v, names, scale, freed];

// @ts-expect-error misspelled option
HandRig.fromVrm(bytes, { mirrror: true });
// @ts-expect-error not a finger
HandRig.fromVrm(bytes, { alignment: { finger: "pinky" } });
// @ts-expect-error a frame is required
rig.solve();
// @ts-expect-error handedness is "Left" or "Right"
rig.solve({ hands: [{ handedness: "Middle", worldLandmarks: landmarks }] });
// @ts-expect-error vrmVersion is read-only
rig.vrmVersion = "0";

// handrig/worker: the page side takes the frames HandRig.solve takes, with their types.
import type { RigWorker } from "handrig/worker";
declare const rigWorker: RigWorker;
for (const f of frames) rigWorker.solve(f);
rigWorker.solve({ timeMs: 4, hands: { worldLandmarks: [landmarks], landmarks: [landmarks], handedness: [[{ categoryName: "Left", score: 1 }]] } });
// @ts-expect-error handedness is "Left" or "Right", in a worker too
rigWorker.solve({ hands: [{ handedness: "Middle", worldLandmarks: landmarks }] });
// @ts-expect-error timeMs is a number, in a worker too
rigWorker.solve({ timeMs: "5" });

// Optional fields take undefined (not given), under exactOptionalPropertyTypes too
// (tsconfig.strict.json): options, frames and the worker's options, as apps build them.
declare const maybe: boolean;
const optionsMaybe: HandRigOptions = {
  mirror: maybe ? true : undefined,
  arm: { idle: maybe ? "tpose" : undefined, maxTurnSpeed: undefined },
  filter: maybe ? false : undefined,
  calibration: undefined,
};
HandRig.fromVrm(bytes, optionsMaybe);
rig.solve({ timeMs: maybe ? 1 : undefined, hands: maybe ? [] : undefined, imageAspect: maybe ? 4 / 3 : undefined });
import type { RigWorkerOptions } from "handrig/worker";
const workerOptions: RigWorkerOptions = { avatar: bytes, options: maybe ? optionsMaybe : undefined, wasm: maybe ? "x.wasm" : undefined };
void workerOptions;
