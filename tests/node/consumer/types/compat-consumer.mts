// Type-checked (not run) by types.test.mjs: handrig/compat's types (compat.d.ts), strict.
import init, { HandRig, initSync, LAYOUT, wasmBuild, type HandRigOptions, type SolveResult } from "handrig/compat";

await init();
initSync();
const options: HandRigOptions = { mirror: true };
const rig: HandRig = HandRig.fromVrm(new Uint8Array(0), options);
const result: SolveResult = rig.solve({ timeMs: 0 });
const build: "simd128" | "baseline" = wasmBuild();
void [result, build, LAYOUT.input.handCount];
// @ts-expect-error compat has no wasmFile(): there is no file
import { wasmFile } from "handrig/compat";
void wasmFile;
