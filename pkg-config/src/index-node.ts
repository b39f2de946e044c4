// The package's Node CommonJS entry (pkg/index.cjs): the glue (wasm-bindgen's `--target nodejs`
// output, pkg/wasm/handrig_wasm.cjs) compiles and instantiates the wasm synchronously when it is
// required, so the API is ready at once; init and initSync are no-ops kept for code shared with
// browsers. Same exports as index.ts (whose declarations type it), less the default export.

/// <reference path="glue.d.ts" />

import * as glue from "handrig:wasm-node";
import { bindWasm } from "./wasm.js";

export * from "./api.js";

bindWasm(glue, () => true);

/** A no-op in Node (the module is ready once required); kept for code shared with browsers. */
export function init(): Promise<void> {
  return Promise.resolve();
}

/** A no-op in Node. */
export function initSync(): void {}

/** The file in `wasm/` this process loaded (HANDRIG_WASM, else by the engine's SIMD support). */
export const wasmFile = (): string => glue.__handrigWasmFile();
