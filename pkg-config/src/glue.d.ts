// The wasm-bindgen glues as the entry points import them. esbuild (build.mjs) resolves these
// names to the package's own files, left external: "handrig:wasm-web" to ./wasm/handrig_wasm.js
// (`--target web`, with build.mjs's SIMD chooser), "handrig:wasm-node" to
// ./wasm/handrig_wasm.cjs (`--target nodejs`). build.mjs type-checks the real glues against
// these declarations. Also the two Node built-ins the Node ES module entry uses (no @types/node).

declare module "handrig:wasm-web" {
  // The inits' arguments are typed `never` here: the entry passes the user's value through
  // (wasm-bindgen's types for it name DOM types; it checks the value itself).
  /** wasm-bindgen's init: instantiates the module (`{ module_or_path }`, or nothing: fetch it). */
  export default function init(input?: never): Promise<unknown>;
  /** wasm-bindgen's synchronous init (`{ module }`). */
  export function initSync(module: never): unknown;
  /** build.mjs: whether this engine validates WebAssembly SIMD (the SIMD build is loaded). */
  export function __handrigSimd(): boolean;
  export const HandRig: import("./wasm.js").RawHandRigClass;
  export const RawChainSolver: import("./wasm.js").RawChainSolverClass;
  export function wasmBuild(): string;
}

declare module "handrig:wasm-compat" {
  // The `--target web` glue with the baseline .wasm inlined (build.mjs, for handrig/compat).
  /** wasm-bindgen's init: instantiates the module (no argument: the inlined one). */
  export default function init(input?: never): Promise<unknown>;
  /** wasm-bindgen's synchronous init (`{ module }`). */
  export function initSync(module: never): unknown;
  /** build.mjs: the inlined .wasm's bytes (decoded from base64 on each call). */
  export function __handrigInlineWasm(): Uint8Array;
  export const HandRig: import("./wasm.js").RawHandRigClass;
  export const RawChainSolver: import("./wasm.js").RawChainSolverClass;
  export function wasmBuild(): string;
}

declare module "handrig:wasm-node" {
  /** build.mjs: the .wasm file this process loaded. */
  export function __handrigWasmFile(): string;
  export const HandRig: import("./wasm.js").RawHandRigClass;
  export const RawChainSolver: import("./wasm.js").RawChainSolverClass;
  export function wasmBuild(): string;
}

declare module "node:module" {
  export function createRequire(url: string): (id: string) => unknown;
}

interface ImportMeta {
  url: string;
}
