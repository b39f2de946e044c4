// The raw wasm-bindgen module under the JS layer, as the entry point for each target hands it
// over (`bindWasm`): the `--target web` glue in browsers and bundlers, the `--target nodejs` glue
// in Node. Only the members below are used; build.mjs type-checks the real glue against
// `RawModule`, so this interface cannot drift from src/wasm/.

/** wasm-bindgen's `HandRig` (src/wasm/mod.rs): thin, flat buffers in wasm memory. */
export interface RawHandRig {
  inputPtr(): number;
  outputPtr(): number;
  solveFlat(timeMs: number): number;
  takeError(): string | undefined;
  boneStates(): Uint8Array;
  contactModel(): Float32Array;
  alignedBones(): Uint8Array;
  readonly alignmentWarning: string | undefined;
  restPositions(): Float32Array;
  readonly vrmVersion: string;
  readonly bodyScale: number;
  resetCalibration(): void;
  reset(): void;
  calibrateHandScale(): Float32Array;
  calibrateFace(): void;
  boneMap(): object | undefined;
  free(): void;
}

export interface RawHandRigClass {
  new (
    rest: Float64Array,
    vrmVersion: number,
    options: unknown,
    skinPositions?: Float32Array,
    skinBones?: Uint8Array,
    skinTriangles?: Uint32Array,
    lookAt?: Float32Array,
  ): RawHandRig;
  fromVrm(bytes: Uint8Array, options: unknown): RawHandRig;
  fromGltf(bytes: Uint8Array, boneMap: string[], options: unknown): RawHandRig;
  memory(): unknown;
}

/** wasm-bindgen's `RawChainSolver` (src/wasm/chain.rs). */
export interface RawChainSolver {
  readonly jointCount: number;
  goalPtr(): number;
  posePtr(): number;
  readonly poseLength: number;
  solveFlat(): number;
  takeError(): string | undefined;
  reset(): void;
  free(): void;
}

export interface RawChainSolverClass {
  new (options: unknown): RawChainSolver;
}

/** What the JS layer uses of the wasm-bindgen glue. */
export interface RawModule {
  HandRig: RawHandRigClass;
  RawChainSolver: RawChainSolverClass;
  wasmBuild(): string;
}

let raw: RawModule | undefined;
let isReady: () => boolean = () => false;

/** Called once by the entry point: the glue, and whether its module is instantiated. */
export function bindWasm(module: RawModule, ready: () => boolean): void {
  raw = module;
  isReady = ready;
}

/** The glue (the entry point bound it before any class of this layer can be used). */
export function wasm(): RawModule {
  return raw as RawModule;
}

export function ensureReady(what: string): void {
  if (!isReady()) {
    throw new Error(
      `handrig: ${what} was called before the WebAssembly module was initialized. ` +
        "In browsers and bundlers, `await init()` (the package's default export) first.",
    );
  }
}

let memory: { readonly buffer: ArrayBuffer } | undefined;

/** wasm's memory (its `buffer` is replaced when the memory grows). */
export function wasmMemory(): { readonly buffer: ArrayBuffer } {
  if (memory === undefined) memory = wasm().HandRig.memory() as { readonly buffer: ArrayBuffer };
  return memory;
}

/** `[Symbol.dispose]()`, an alias of `free()`, where the engine has `Symbol.dispose`. */
export function addDispose(C: { prototype: { free(): void } }): void {
  const dispose = typeof Symbol === "function" ? (Symbol as { dispose?: unknown }).dispose : undefined;
  if (typeof dispose === "symbol") {
    Object.defineProperty(C.prototype, dispose, { value: C.prototype.free, writable: true, configurable: true });
  }
}

/**
 * `init(input)`'s argument as wasm-bindgen's glue takes it: `undefined` (the default file), an
 * options object as given, or `{ module_or_path: input }` for a URL, Response, bytes or module.
 */
export function initArgument(input: unknown): unknown {
  if (input === undefined) return undefined;
  return input !== null && Object.getPrototypeOf(input) === Object.prototype ? input : { module_or_path: input };
}
