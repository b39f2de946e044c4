// The package's Node ES module entry (pkg/index.mjs): the CommonJS build (index-node.ts), so that
// import and require share one WebAssembly instance (no dual-package hazard).

/// <reference path="glue.d.ts" />

import { createRequire } from "node:module";
import type * as api from "./index.js";

const cjs = createRequire(import.meta.url)("./index.cjs") as typeof api;

export const HandRig = cjs.HandRig;
export const ChainSolver = cjs.ChainSolver;
export const wasmBuild = cjs.wasmBuild;
export const wasmFile = cjs.wasmFile;
export const LAYOUT = cjs.LAYOUT;
export const MotionRecorder = cjs.MotionRecorder;
export const init = cjs.init;
export const initSync = cjs.initSync;
export const version = cjs.version;
export default init;
