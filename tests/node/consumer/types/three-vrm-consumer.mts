// Type-checked (not run) by types.test.mjs: the adapter with three-vrm's real VRM type (needs
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
