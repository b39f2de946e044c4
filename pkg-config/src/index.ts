// The package's ES module entry for browsers and bundlers (pkg/index.js): `await init()` once,
// then HandRig. Its declarations are the package's types (pkg/index.d.ts; index.d.cts without the
// default export). The glue is wasm-bindgen's `--target web` output (pkg/wasm/handrig_wasm.js).

/**
 * The `handrig` entry point (TypeDoc: `make docs`).
 * @packageDocumentation
 * @module handrig
 */

/// <reference path="glue.d.ts" />

import * as glue from "handrig:wasm-web";
import type { InitInput } from "./api.js";
import { bindWasm, initArgument } from "./wasm.js";

export * from "./api.js";

let ready = false;
bindWasm(glue, () => ready);

/**
 * Instantiates the WebAssembly module. Required once in browsers and bundlers before any other
 * call (`await init()` fetches `handrig_simd_bg.wasm` next to the module where the engine has
 * WebAssembly SIMD, `handrig_bg.wasm` elsewhere: bundlers that understand
 * `new URL(..., import.meta.url)` copy them; or pass either's URL, a Response, its bytes or a
 * WebAssembly.Module); a resolved no-op in Node. Calling it again is a no-op.
 */
export async function init(input?: InitInput | { module_or_path: InitInput }): Promise<void> {
  await glue.default(initArgument(input) as never);
  ready = true;
}

/** Synchronous `init` from the .wasm bytes or a compiled module (workers); a no-op in Node. */
export function initSync(module?: ArrayBuffer | ArrayBufferView | object): void {
  const arg =
    module !== null && typeof module === "object" && Object.getPrototypeOf(module) === Object.prototype
      ? module
      : { module };
  glue.initSync(arg as never);
  ready = true;
}

/**
 * The file in the package's `wasm/` folder that `init()` loads in this engine:
 * `"handrig_simd_bg.wasm"` where it has WebAssembly SIMD, else `"handrig_bg.wasm"`. Needs no
 * `init()`: what a page fetches for a worker's `initSync`.
 */
export function wasmFile(): "handrig_simd_bg.wasm" | "handrig_bg.wasm" {
  return glue.__handrigSimd() ? "handrig_simd_bg.wasm" : "handrig_bg.wasm";
}

export default init;
