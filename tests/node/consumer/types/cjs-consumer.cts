// Type-checked (not run) by types.test.mjs: the CommonJS view of the types (index.d.cts).
import handrig = require("handrig");
import adapter = require("handrig/three-vrm");
import compat = require("handrig/compat");

const rig: handrig.HandRig = handrig.HandRig.fromVrm(new Uint8Array(0));
const result: handrig.SolveResult = rig.solve({ timeMs: 0 });
const init: Promise<void> = handrig.init();
const rest: adapter.VRMRestPose = { bones: {}, vrmVersion: "1" };
new handrig.HandRig(rest);
const vrma: Uint8Array = new handrig.MotionRecorder(rig).toVRMA();
void [result, init, handrig.version, vrma];
const compatInit: Promise<void> = compat.init();
compat.initSync();
void [compatInit, compat.HandRig.fromVrm(new Uint8Array(0)).solve({ timeMs: 0 })];
// @ts-expect-error CommonJS has no default export
void handrig.default;
