// `handrig/worker` (pkg/worker.js, worker.cjs): a rig in a module Worker, both sides.
//
// The page side, `createRigWorker(worker, { avatar, options, wasm })`, sends frames and receives
// the flat output (LAYOUT.output) as transferred Float32Arrays. It never queues: one frame is in
// the worker at a time, and a frame given while the worker is busy waits as "pending", replaced
// (and counted as dropped) by a newer one; so the avatar shows the newest frame the worker could
// solve, never a backlog. Two output buffers go back and forth (one in the worker being filled,
// one with the page holding the latest result): no per-frame allocation beyond postMessage's
// (the frame's structured clone, the transferred buffer's handle) and a Float32Array view of
// the buffer on each side.
//
// The worker side, `serveRig(handrig)`, is the module the Worker runs: `await init()`,
// `HandRig.fromVrm`, then one solve per message. It takes the package's module namespace
// (`import * as handrig from "handrig"` or `"handrig/compat"`), so this entry carries no
// WebAssembly itself and the page side stays small. docs/guide/workers.md has the recipe.

/**
 * The `handrig/worker` entry point (TypeDoc: `make docs`).
 * @packageDocumentation
 * @module handrig/worker
 */

import type { FrameInput } from "./frame-types.js";
import { describe, givenFields, isObject } from "./errors.js";
import type { HumanBoneName } from "./layout.js";
import { BONES, LO } from "./layout.js";
import type { HandRigOptions } from "./options.js";
import { quat } from "./results.js";

// Workers and pages have it; the package's type-check has no DOM library.
declare const performance: { now(): number };

/** A Worker as the page sees it (a DOM `Worker` fits). */
export interface WorkerLike {
  postMessage(message: any, transfer: any[]): void;
  onmessage: ((ev: any) => any) | null;
  onerror: ((ev: any) => any) | null;
  terminate(): void;
}

/** What `createRigWorker` needs. */
export interface RigWorkerOptions {
  /** The avatar: a `.vrm` / `.glb` file's bytes (transferred to the worker when an ArrayBuffer). */
  avatar: ArrayBuffer | ArrayBufferView;
  /** `HandRig.fromVrm`'s options. */
  options?: HandRigOptions | undefined;
  /**
   * What the worker's `init()` is given: a `.wasm` URL (string) for `handrig` when the bundler
   * does not locate it; nothing for `handrig/compat`, or when the bundler does.
   */
  wasm?: string | undefined;
}

/** One solved frame, as `onResult` sees it. */
export interface RigWorkerResult {
  /**
   * The flat output (LAYOUT.output): `applyToVRM(vrm, output)` (handrig/three-vrm) applies it,
   * `readRotation` reads a bone. Valid until the next result arrives (the buffer then goes back to
   * the worker): copy what you keep.
   */
  output: Float32Array;
  /** The frame's `timeMs`. */
  timeMs: number;
  /** Microseconds the worker spent in `rig.solve` (and copying the output). */
  solveUs: number;
}

/** Counts since `createRigWorker`. */
export interface RigWorkerStats {
  /** Frames given to `solve`. */
  frames: number;
  /** Frames sent to the worker. */
  sent: number;
  /** Frames solved (results delivered). */
  solved: number;
  /** Frames replaced by a newer one while the worker was busy (never sent). */
  dropped: number;
  /** Frames the worker rejected (`onError` got the message). */
  failed: number;
}

/** The page side of a rig in a worker (`createRigWorker`). */
export interface RigWorker {
  /** The avatar's bones the rig drives (`HandRig.boneNames()`). */
  readonly bones: readonly HumanBoneName[];
  /** The newest result's output (see `RigWorkerResult.output`), or null before the first. */
  readonly latest: Float32Array | null;
  /** Counts of frames given, sent, solved, dropped and failed. */
  readonly stats: Readonly<RigWorkerStats>;
  /**
   * Solves `frame` in the worker: sent now if the worker is idle (returns true), otherwise kept
   * as the pending frame, replacing (dropping) any older pending one (returns false). The frame
   * is structured-cloned when sent: do not change it until then. The frame is the one
   * `HandRig.solve` takes, checked the same way in the worker: a bad one comes back through
   * `onError` with the message naming the field, and the warnings (a missing `timeMs`, times
   * in seconds or frame numbers) go to the worker's console.
   */
  solve(frame: FrameInput): boolean;
  /** Called with each result, in order. */
  onResult: ((result: RigWorkerResult) => void) | null;
  /** Called when the worker rejects a frame (a bad frame: the rig stays usable). */
  onError: ((message: string) => void) | null;
  /** Resolves when the worker has solved everything sent and nothing is pending. */
  idle(): Promise<void>;
  /** Stops the worker. */
  terminate(): void;
}

// The messages between the sides.
type ToWorker =
  | { type: "init"; avatar: ArrayBuffer | ArrayBufferView; options: HandRigOptions | undefined; wasm: string | undefined }
  | { type: "solve"; frame: FrameInput | null; output: ArrayBuffer | null };
type FromWorker =
  | { type: "ready"; bones: HumanBoneName[]; length: number }
  | { type: "solved"; output: ArrayBuffer; timeMs: number; us: number }
  | { type: "error"; message: string; output: ArrayBuffer | null; fatal: boolean };

/**
 * Starts a rig in `worker` (a module Worker whose module calls `serveRig`) and resolves once the
 * avatar is loaded, rejecting with the worker's error (a bad avatar or options) otherwise.
 *
 * ```ts
 * const worker = new Worker(new URL("./rig.worker.ts", import.meta.url), { type: "module" });
 * const rig = await createRigWorker(worker, { avatar: vrmBytes });
 * rig.onResult = ({ output }) => applyToVRM(vrm, output);
 * // every tracking result: rig.solve(frame); stale frames are dropped while the worker is busy
 * ```
 */
export function createRigWorker(worker: WorkerLike, options: RigWorkerOptions): Promise<RigWorker> {
  if (!isObject(options) || Array.isArray(options)) {
    return Promise.reject(new TypeError(`options: must be an object { avatar, options?, wasm? }, got ${describe(options)}`));
  }
  // Fields set to undefined are absent (givenFields), as in every options object.
  const given = givenFields(options, "options");
  const avatar = given.avatar as ArrayBuffer | ArrayBufferView;
  if (!(avatar instanceof ArrayBuffer) && !ArrayBuffer.isView(avatar)) {
    return Promise.reject(new TypeError(`options.avatar: must be the bytes of a .vrm / .glb file (an ArrayBuffer or a Uint8Array), got ${describe(avatar)}`));
  }
  const wasm = given.wasm;
  if (wasm !== undefined && typeof wasm !== "string") {
    return Promise.reject(new TypeError(`options.wasm: must be the URL of the .wasm file (a string), got ${describe(wasm)}`));
  }
  const transfer = avatar instanceof ArrayBuffer ? [avatar] : [];
  const init: ToWorker = { type: "init", avatar, options: given.options as HandRigOptions | undefined, wasm };
  return new Promise<RigWorker>((resolve, reject) => {
    worker.onerror = (ev: { message?: string }) => {
      reject(new Error(`handrig/worker: the worker failed to start: ${ev?.message ?? "unknown error"}`));
    };
    worker.onmessage = (ev: { data: FromWorker }) => {
      const m = (isObject(ev) ? ev.data : undefined) as FromWorker | undefined;
      if (!isObject(m)) return;
      if (m.type === "ready") resolve(new PageRig(worker, m.bones, m.length));
      else if (m.type === "error") reject(new Error(m.message));
    };
    worker.postMessage(init, transfer);
  });
}

class PageRig implements RigWorker {
  readonly bones: readonly HumanBoneName[];
  latest: Float32Array | null = null;
  readonly stats: RigWorkerStats = { frames: 0, sent: 0, solved: 0, dropped: 0, failed: 0 };
  onResult: ((result: RigWorkerResult) => void) | null = null;
  onError: ((message: string) => void) | null = null;
  #worker: WorkerLike;
  // The two output buffers, ping-ponged: each is in the worker, held as `latest`, or free here.
  #spare: ArrayBuffer | null;
  // The buffer the page may send next (null while it is in the worker, or held as `latest`).
  #free: ArrayBuffer | null;
  #busy = false;
  #pending: FrameInput | null = null;
  #waiting: (() => void)[] = [];
  // One message object and one result object, reused for every frame.
  #msg: ToWorker & { type: "solve" } = { type: "solve", frame: null, output: null };
  #result: RigWorkerResult = { output: new Float32Array(0), timeMs: 0, solveUs: 0 };
  #transfer: ArrayBuffer[] = [];

  constructor(worker: WorkerLike, bones: HumanBoneName[], length: number) {
    this.bones = bones;
    this.#worker = worker;
    this.#free = new ArrayBuffer(4 * length);
    // The second buffer of the pair becomes `latest` with the first result; made here, once.
    this.#spare = new ArrayBuffer(4 * length);
    worker.onmessage = (ev: { data: FromWorker }) => this.#receive((isObject(ev) ? ev.data : undefined) as FromWorker);
    worker.onerror = (ev: { message?: string }) => this.#fail(`handrig/worker: ${ev?.message ?? "worker error"}`);
  }

  solve(frame: FrameInput): boolean {
    this.stats.frames++;
    if (this.#busy) {
      if (this.#pending !== null) this.stats.dropped++;
      this.#pending = frame;
      return false;
    }
    this.#send(frame);
    return true;
  }

  #send(frame: FrameInput): void {
    const buffer = this.#free ?? this.#spare!;
    if (buffer === this.#free) this.#free = null;
    else this.#spare = null;
    this.#busy = true;
    this.stats.sent++;
    const msg = this.#msg;
    msg.frame = frame;
    msg.output = buffer;
    this.#transfer[0] = buffer;
    this.#worker.postMessage(msg, this.#transfer);
    msg.frame = null;
    msg.output = null;
  }

  #receive(m: FromWorker): void {
    // Only the worker's own replies count (a message of another shape is not one of them).
    if (!isObject(m) || (m.type !== "solved" && m.type !== "error")) return;
    if (m.type === "solved" && !(m.output instanceof ArrayBuffer)) return;
    this.#busy = false;
    if (m.type === "solved") {
      // The previous `latest` buffer is free again; the new one is held until the next result.
      if (this.latest !== null) this.#free = this.latest.buffer as ArrayBuffer;
      const output = new Float32Array(m.output);
      this.latest = output;
      this.stats.solved++;
      const r = this.#result;
      r.output = output;
      r.timeMs = m.timeMs;
      r.solveUs = m.us;
      this.onResult?.(r);
    } else {
      if (m.output instanceof ArrayBuffer) {
        if (this.#free === null) this.#free = m.output;
        else this.#spare = m.output;
      }
      this.stats.failed++;
      this.onError?.(m.message);
    }
    this.#next();
  }

  #next(): void {
    if (this.#pending !== null) {
      const frame = this.#pending;
      this.#pending = null;
      this.#send(frame);
    } else if (!this.#busy) {
      const waiting = this.#waiting;
      this.#waiting = [];
      for (const w of waiting) w();
    }
  }

  #fail(message: string): void {
    this.stats.failed++;
    this.onError?.(message);
  }

  idle(): Promise<void> {
    if (!this.#busy && this.#pending === null) return Promise.resolve();
    return new Promise((resolve) => this.#waiting.push(resolve));
  }

  terminate(): void {
    this.#worker.terminate();
    this.#pending = null;
    this.#busy = false;
    this.#next();
  }
}

const BONE_INDEX = new Map<string, number>(BONES.map((b, i) => [b, i]));

/**
 * Reads `bone`'s local rotation [x, y, z, w] from a flat output (a `RigWorkerResult.output`, or
 * `HandRig.output`) into `dst` (returned; no allocation): what `applyToVRM` writes and
 * `result.bones[bone]` holds. Null when the rig does not drive that bone (the avatar lacks it, or
 * the options turn it off); a driven bone this frame did not solve reads at rest or held
 * (`output[LAYOUT.output.boneFlags + i]` is 2 then, 1 when solved). Throws for a name that is not
 * one of LAYOUT.bones.
 */
export function readRotation(output: Float32Array, bone: HumanBoneName, dst: number[] = [0, 0, 0, 1]): number[] | null {
  const i = BONE_INDEX.get(bone);
  if (i === undefined) throw new Error(`readRotation: bone "${String(bone)}" is not one of LAYOUT.bones`);
  if (output[LO.boneFlags + i] === 0) return null;
  return quat(output, LO.boneRotations + 4 * i, dst);
}

/** The parts of a rig that `serveRig` uses (a `HandRig` fits). */
export interface RigLike {
  solve(frame: any): unknown;
  readonly output: Float32Array;
  boneNames(): HumanBoneName[];
}

/**
 * The parts of the package's module namespace that `serveRig` uses (`handrig` or
 * `handrig/compat`; typed structurally, so either entry's declarations fit).
 */
export interface HandrigModule {
  default: (input?: any) => Promise<void>;
  HandRig: { fromVrm(bytes: ArrayBuffer | ArrayBufferView, options?: any): RigLike };
}

/** The worker's global scope as `serveRig` uses it (a DedicatedWorkerGlobalScope fits). */
export interface WorkerScopeLike {
  postMessage(message: any, transfer: any[]): void;
  onmessage: ((ev: any) => any) | null;
}

/**
 * The worker side: call it in the module a Worker runs, with the package's namespace.
 *
 * ```ts
 * // rig.worker.ts
 * import * as handrig from "handrig"; // or "handrig/compat": no .wasm to serve
 * import { serveRig } from "handrig/worker";
 * serveRig(handrig);
 * ```
 * It answers `createRigWorker`'s messages: `await init(wasm)`, `HandRig.fromVrm(avatar, options)`,
 * then one `rig.solve(frame)` per frame, copying `rig.output` into the buffer the page sent and
 * transferring it back. A frame the rig rejects comes back as an error (with its buffer); the
 * rig stays usable.
 */
export function serveRig(handrig: HandrigModule, scope: WorkerScopeLike = globalThis as unknown as WorkerScopeLike): void {
  let rig: RigLike | null = null;
  const one: ArrayBuffer[] = [];
  const solved = { type: "solved" as const, output: null as ArrayBuffer | null, timeMs: 0, us: 0 };
  // A reply to a message that is not one of createRigWorker's: the error names what is wrong,
  // and the worker goes on (nothing is thrown inside the handler, nothing is transferred).
  const refuse = (message: string, fatal: boolean): void => {
    scope.postMessage({ type: "error", message: `handrig/worker: ${message}`, output: null, fatal }, []);
  };
  scope.onmessage = async (ev: { data: ToWorker }) => {
    const m = (isObject(ev) ? ev.data : undefined) as unknown;
    if (!isObject(m) || (m.type !== "init" && m.type !== "solve")) {
      const type = isObject(m) ? ` with type ${describe(m.type)}` : "";
      refuse(`a message must be { type: "init", avatar, options?, wasm? } or { type: "solve", frame, output }, got ${describe(m)}${type}`, false);
      return;
    }
    if (m.type === "init") {
      try {
        const avatar = m.avatar;
        if (!(avatar instanceof ArrayBuffer) && !ArrayBuffer.isView(avatar)) {
          throw new Error(`handrig/worker: init.avatar must be the bytes of a .vrm / .glb file, got ${describe(avatar)}`);
        }
        if (m.wasm !== undefined && typeof m.wasm !== "string") {
          throw new Error(`handrig/worker: init.wasm must be a string (the .wasm URL), got ${describe(m.wasm)}`);
        }
        await handrig.default(m.wasm);
        const next = handrig.HandRig.fromVrm(avatar, m.options);
        // A second init replaces the rig (the old one's wasm memory is released).
        (rig as { free?: () => void } | null)?.free?.();
        rig = next;
        scope.postMessage({ type: "ready", bones: rig.boneNames(), length: LO.length }, []);
      } catch (e) {
        scope.postMessage({ type: "error", message: String((e as Error)?.message ?? e), output: null, fatal: true }, []);
      }
      return;
    }
    const buffer = m.output;
    if (!(buffer instanceof ArrayBuffer) || buffer.byteLength < 4 * LO.length) {
      refuse(`solve.output must be an ArrayBuffer of at least ${4 * LO.length} bytes, got ${describe(buffer)}${buffer instanceof ArrayBuffer ? ` of ${buffer.byteLength} bytes` : ""}`, false);
      return;
    }
    one[0] = buffer;
    try {
      if (rig === null) throw new Error("handrig/worker: a frame came before the rig was ready");
      if (!isObject(m.frame)) throw new Error(`frame: must be an object { timeMs, hands?, pose? }, got ${describe(m.frame)}`);
      const t0 = performance.now();
      const result = rig.solve(m.frame!) as { timeMs?: number } | null;
      new Float32Array(buffer, 0, LO.length).set(rig.output);
      solved.output = buffer;
      // The rig's time of the frame (a frame without timeMs gets one from the rig).
      solved.timeMs = result?.timeMs ?? (m.frame as { timeMs?: number }).timeMs ?? Number.NaN;
      solved.us = (performance.now() - t0) * 1000;
      scope.postMessage(solved, one);
      solved.output = null;
    } catch (e) {
      scope.postMessage({ type: "error", message: String((e as Error)?.message ?? e), output: buffer, fatal: false }, one);
    }
  };
}
