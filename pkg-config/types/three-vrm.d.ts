// Types of `handrig/three-vrm`. The VRM is typed structurally (the members the adapter uses),
// so neither three nor @pixiv/three-vrm is needed to type-check; a three-vrm `VRM` fits.
// build.mjs emits this file as three-vrm.d.ts and three-vrm.d.cts.

/** The parts of three-vrm's `VRM` the adapter uses. */
export interface VRMLike {
  meta: { metaVersion: "0" | "1" | string };
  humanoid: {
    /** Local positions of the normalized bones at rest (offsets from the nearest existing humanoid ancestor). */
    normalizedRestPose: { [boneName: string]: { position?: ArrayLike<number> } | undefined };
    getNormalizedBoneNode(name: any): {
      parent: unknown;
      quaternion: { set(x: number, y: number, z: number, w: number): unknown };
    } | null | undefined;
  };
}

/** Same shape as handrig's `RestPose` (import that type from "handrig"). */
export interface VRMRestPose {
  /** Rest world positions of the normalized bones, meters, the model's own frame. */
  bones: { [boneName: string]: [number, number, number] };
  /** `vrm.meta.metaVersion`: "0" models face -Z, "1" models face +Z. */
  vrmVersion: "0" | "1";
}

/**
 * The rest pose handrig needs, from three-vrm's normalized humanoid (`normalizedRestPose`): world
 * positions of the normalized bones at rest in the model's own frame, plus the VRM version.
 * Unaffected by the avatar's current pose, its scene transform and `VRMUtils.rotateVRM0`.
 * Use it as `new HandRig(restPoseFromVRM(vrm), options)`.
 * @throws TypeError when `vrm` is not a three-vrm VRM.
 */
export declare function restPoseFromVRM(vrm: VRMLike): VRMRestPose;

/**
 * Writes a solve's rotations to `vrm.humanoid.getNormalizedBoneNode(name).quaternion`: `result`
 * is a `HandRig.solve` result (its `bones`: every bone the rig drives, every frame) or a flat
 * output array (`rig.output`, or what `solveInto` filled: every bone whose flag is not 0).
 * No VRM 0.x sign flip is applied or needed: handrig already returns rotations in the model's own
 * frame. Call `vrm.update(delta)` afterwards as usual. Returns how many bones were written. The
 * bone nodes are looked up once per VRM and cached.
 * @throws TypeError when `vrm` or `result` has the wrong shape.
 */
export declare function applyToVRM(
  vrm: VRMLike,
  result: { bones: { [boneName: string]: ArrayLike<number> | undefined } } | Float32Array,
): number;
