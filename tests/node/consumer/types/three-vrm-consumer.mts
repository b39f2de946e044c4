// Type-checked (not run) by types.test.mjs: the adapters with three-vrm's VRM and three's Object3D (needs
// @types/three and the DOM lib, see tsconfig.three.json).
import { HandRig } from "handrig";
import { applyToVRM, restPoseFromVRM } from "handrig/three-vrm";
import type { VRM } from "@pixiv/three-vrm";

declare const vrm: VRM;
const rig = new HandRig(restPoseFromVRM(vrm));
const written: number = applyToVRM(vrm, rig.solve({ timeMs: 0 }));
vrm.update(1 / 60);
void written;
// @ts-expect-error a solve result is required
applyToVRM(vrm, {});

// handrig/three with three's real Object3D, and fromGltf's options.
import { applyToSkeleton, restPoseFromSkeleton } from "handrig/three";
import type { Object3D } from "three";

declare const scene: Object3D;
declare const glb: Uint8Array;
const rest = restPoseFromSkeleton(scene);
const plain = new HandRig(rest);
const n: number = applyToSkeleton(scene, plain.solve({ timeMs: 0 }), rest.boneMap);
const gltfRig = HandRig.fromGltf(glb, { mirror: true, skeleton: { boneMap: { leftHand: "Hand.L" } } });
const binding = gltfRig.boneMap();
if (binding) applyToSkeleton(scene, gltfRig.solve({ timeMs: 0 }), binding);
void n;
// @ts-expect-error node names are strings
HandRig.fromGltf(glb, { skeleton: { boneMap: { leftHand: 3 } } });
// @ts-expect-error bone maps are keyed by humanoid bone names
HandRig.fromGltf(glb, { skeleton: { boneMap: { leftWing: "Wing.L" } } });
