// `handrig/compat` (pkg/compat.js, compat.cjs): the same API with the WebAssembly inlined, as
// rapier's -compat packages do. build.mjs bundles the `--target web` glue into this entry with
// the baseline .wasm as base64 in its place: `await init()` decodes and instantiates it, with no
// fetch and no .wasm file to serve, so any bundler (or none) needs no asset configuration. The
// cost is bytes: base64 is 4/3 of the .wasm (build.mjs prints the entry's size), and the SIMD
// build is not included (the baseline runs everywhere; SIMD is about 7% faster a frame).

/**
 * The `handrig/compat` entry point (TypeDoc: `make docs`).
 * @packageDocumentation
 * @module handrig/compat
 */

/// <reference path="glue.d.ts" />

import * as glue from "handrig:wasm-compat";
import type { InitInput } from "./api.js";
import { bindWasm, initArgument } from "./wasm.js";

export * from "./api.js";

let ready = false;
bindWasm(glue, () => ready);

/**
 * Instantiates the inlined WebAssembly module: required once, in every environment, before any
 * other call (`await init()`; no fetch, no file). Passing a `.wasm` URL, Response, bytes or
 * `WebAssembly.Module` uses that instead, as `handrig`'s `init` does. Calling it again is a no-op.
 */
export async function init(input?: InitInput | { module_or_path: InitInput }): Promise<void> {
  await glue.default(initArgument(input) as never);
  ready = true;
}

/**
 * Synchronous `init` from the inlined module (or the bytes or module given): for workers and
 * Node. Browsers refuse to compile a module this large synchronously on the main thread: use
 * `await init()` there.
 */
export function initSync(module?: ArrayBuffer | ArrayBufferView | object): void {
  const arg =
    module === undefined
      ? { module: glue.__handrigInlineWasm() }
      : module !== null && typeof module === "object" && Object.getPrototypeOf(module) === Object.prototype
        ? module
        : { module };
  glue.initSync(arg as never);
  ready = true;
}

export default init;
