// `ChainSolver`: FABRIK or CCD on any chain (tails, spines, custom rigs), over the raw class's
// flat goal and pose buffers in wasm memory (src/wasm/chain.rs). Options are checked for shape
// here (field-named errors, no user code run inside wasm); Rust checks the geometry.

import { asError, describe, fail, finite, FieldError, givenFields, isObject, readUser, reading, userError } from "./errors.js";
import type { Landmark, Quat, Vec3 } from "./frame-types.js";
import { point3, readVec3 } from "./points.js";
import { quat, vec } from "./results.js";
import { addDispose, ensureReady, wasm, wasmMemory, type RawChainSolver } from "./wasm.js";

/** A joint limit of a chain bone, in the parent bone's frame (bone 0: against its rest direction). */
export type JointConstraint =
  | { type: "cone"; maxAngle: number }
  | { type: "hinge"; axis: Vec3 | Landmark; min: number; max: number };

/** Options of a `ChainSolver`. */
export interface ChainSolverOptions {
  /** "fabrik" (default, seed 002) or "ccd" (seed 004). */
  method?: "fabrik" | "ccd";
  /** Rest joint positions, root first, at least 3 (meters). */
  joints: ReadonlyArray<Vec3 | Landmark>;
  /** One entry per bone (joints.length - 1), or null for a free bone; omit for none. */
  constraints?: ReadonlyArray<JointConstraint | null>;
  /** Most iterations per solve (default FABRIK 100, CCD 200). */
  iterations?: number;
  /** End-to-target distance that counts as reached (default 1e-5 of the chain length). */
  tolerance?: number;
  /** CCD's damping: the largest angle (radians) a joint turns per step (default 0.5). */
  maxStepAngle?: number;
}

/** A solved chain. */
export interface ChainSolution {
  /** Joint positions, root first. */
  joints: Vec3[];
  /** Each bone's world rotation from its rest direction. */
  rotations: Quat[];
  /** The end is within the tolerance of the target. */
  reached: boolean;
  /** The target is within the chain's length (limits ignored). */
  reachable: boolean;
  /** End-to-target distance (m). */
  error: number;
  /** Iterations run. */
  iterations: number;
}

// ChainSolver's joints, targets and poles lie within this of the origin, as Rust checks
// (chain_solver.rs COORDINATE_LIMIT): any unit of length, but squares must stay finite.
const CHAIN_LIMIT = 1e9;

/**
 * Checks the shape of ChainSolver options in JS (field-named errors, no user code run inside
 * wasm) and returns a plain copy for the Rust side, which checks the geometry.
 */
function chainOptions(given: unknown): object {
  if (!isObject(given) || Array.isArray(given)) {
    fail("options", `must be an object { method?, joints, constraints?, iterations?, tolerance? }, got ${describe(given)}`);
  }
  // Fields this function does not read go to Rust as given: its reader
  // (`ChainSolverOptions::from_value`, unknown fields denied) names them and lists the known
  // ones, so no list of names is kept here. Fields set to undefined are absent (givenFields).
  const options = givenFields(given, "options");
  const out: { [key: string]: unknown } = { ...options };
  const method = options.method;
  if (method !== undefined) {
    if (method !== "fabrik" && method !== "ccd") fail("options.method", `must be "fabrik" or "ccd", got ${describe(method)}`);
    out.method = method;
  }
  const joints = options.joints;
  if (!Array.isArray(joints)) fail("options.joints", `must be an array of [x, y, z] rest joint positions, root first, got ${describe(joints)}`);
  if (joints.length < 3) fail("options.joints", `needs at least 3 joints (2 bones), got ${joints.length}`);
  out.joints = joints.map((p: unknown, i) => point3(p, `options.joints[${i}]`, CHAIN_LIMIT));
  const constraints = options.constraints;
  if (constraints === null) delete out.constraints;
  else if (constraints !== undefined) {
    if (!Array.isArray(constraints)) fail("options.constraints", `must be an array (one entry per bone, or null), got ${describe(constraints)}`);
    out.constraints = constraints.map((c: unknown, i) => {
      const field = `options.constraints[${i}]`;
      if (c === null || c === undefined) return null;
      if (!isObject(c)) fail(field, `must be { type: "cone", maxAngle } or { type: "hinge", axis, min, max } or null, got ${describe(c)}`);
      // Unread fields pass through to Rust, which names them (as above).
      const g = givenFields(c, field);
      if (g.type === "cone") {
        return { ...g, type: "cone", maxAngle: finite(g.maxAngle, `${field}.maxAngle`) };
      }
      if (g.type === "hinge") {
        return {
          ...g,
          type: "hinge",
          axis: point3(g.axis, `${field}.axis`),
          min: finite(g.min, `${field}.min`),
          max: finite(g.max, `${field}.max`),
        };
      }
      return fail(`${field}.type`, `must be "cone" or "hinge", got ${describe(g.type)}`);
    });
  }
  if (options.iterations !== undefined) {
    const it = options.iterations;
    if (!Number.isInteger(it) || (it as number) < 1 || (it as number) > 100000) {
      fail("options.iterations", `must be a whole number in 1..100000, got ${describe(it)}`);
    }
    out.iterations = it;
  }
  if (options.tolerance !== undefined) out.tolerance = finite(options.tolerance, "options.tolerance");
  if (options.maxStepAngle !== undefined) out.maxStepAngle = finite(options.maxStepAngle, "options.maxStepAngle");
  return out;
}

/** FABRIK or CCD on any chain (tails, spines, custom rigs). Create once, `solve` per frame, `free()` when done. */
export class ChainSolver {
  #raw: RawChainSolver | null;
  #goal: Float32Array;
  #pose: Float32Array;
  #n: number;
  #result: { [key: string]: unknown } | undefined;

  /**
   * `new ChainSolver({ method: "fabrik" | "ccd", joints, constraints?, iterations?, tolerance?,
   * maxStepAngle? })`: `joints` are rest joint positions [x, y, z], root first (at least 3);
   * `constraints` one entry per bone (or null).
   * @throws Error naming the field (`options.joints[3]`, `options.constraints[1].maxAngle`).
   */
  constructor(options: ChainSolverOptions) {
    ensureReady("new ChainSolver()");
    let r: RawChainSolver;
    try {
      r = new (wasm().RawChainSolver)(readUser("options", () => chainOptions(options)));
    } catch (e) {
      const err = asError(e);
      // The Rust side names fields of the options (`joints[1]`, `constraints[0].maxAngle`).
      if (!(err instanceof FieldError) && !/^options/.test(err.message)) err.message = `options.${err.message}`;
      throw err;
    }
    this.#raw = r;
    this.#n = r.jointCount;
    this.#goal = new Float32Array(0);
    this.#pose = new Float32Array(0);
  }

  #views(method: string): RawChainSolver {
    const r = this.#raw;
    if (r === null) throw new Error(`ChainSolver.${method}: this solver was freed (free() was called)`);
    if (this.#goal.length === 0) {
      const buffer = wasmMemory().buffer;
      this.#goal = new Float32Array(buffer, r.goalPtr(), 7);
      this.#pose = new Float32Array(buffer, r.posePtr(), r.poseLength);
    }
    return r;
  }

  #run(method: string, target: unknown, pole: unknown): Float32Array {
    const r = this.#views(method);
    const g = this.#goal;
    // No closure (readUser's) here: a solve allocates nothing.
    reading.part = "target";
    try {
      readVec3(target, "target", g, 0, CHAIN_LIMIT);
      if (pole === undefined || pole === null) g[3] = 0;
      else {
        reading.part = "pole";
        readVec3(pole, "pole", g, 4, CHAIN_LIMIT);
        g[3] = 1;
      }
    } catch (e) {
      throw userError(e, reading.part);
    }
    // A getter that freed this solver or grew wasm memory (creating solvers or rigs) while the
    // goal was read: the goal view is gone and what was read with it.
    if (g.length === 0) {
      this.#views(method);
      throw new Error(`${method}: reading the goal changed wasm memory (a getter created or freed solvers or rigs); nothing was solved, call it again`);
    }
    if (r.solveFlat() !== 0) throw new Error(r.takeError());
    return this.#pose;
  }

  /** Number of joints. */
  get jointCount(): number {
    return this.#n;
  }

  /**
   * Solves toward `{ target, pole? }` (with the middle joints turned toward `goal.pole`): returns
   * `{ joints, rotations, reached, reachable, error, iterations }` (joints [x, y, z] root first;
   * rotations: each bone's world rotation from its rest direction [x, y, z, w]). The result
   * object is reused by the next call; pass `into` (e.g. `{}`) for one of your own.
   */
  solve(goal: { target: Vec3 | Landmark; pole?: Vec3 | Landmark }, into?: object): ChainSolution {
    if (!isObject(goal)) throw new FieldError(`goal: must be { target: [x, y, z], pole?: [x, y, z] }, got ${describe(goal)}`);
    let target: unknown;
    let pole: unknown;
    reading.part = "goal.target";
    try {
      target = goal.target;
      reading.part = "goal.pole";
      pole = goal.pole;
    } catch (e) {
      throw userError(e, reading.part);
    }
    const p = this.#run("solve", target, pole);
    const n = this.#n;
    let out = into as { [key: string]: unknown } | undefined | null;
    if (out === undefined || out === null) {
      if (this.#result === undefined) this.#result = {};
      out = this.#result;
    }
    if (!Array.isArray(out.joints)) out.joints = Array.from({ length: n }, () => [0, 0, 0]);
    if (!Array.isArray(out.rotations)) out.rotations = Array.from({ length: n - 1 }, () => [0, 0, 0, 1]);
    const joints = out.joints as number[][];
    const rotations = out.rotations as number[][];
    for (let k = 0; k < n; k++) vec(p, 3 * k, joints[k]!);
    const r0 = 3 * n;
    for (let k = 0; k < n - 1; k++) quat(p, r0 + 4 * k, rotations[k]!);
    const st = r0 + 4 * (n - 1);
    out.reached = p[st] === 1;
    out.reachable = p[st + 1] === 1;
    out.error = p[st + 2];
    out.iterations = p[st + 3];
    return out as unknown as ChainSolution;
  }

  /**
   * Solves toward `target` (and `pole`) into `out.joints` (a Float32Array of 3 N) and
   * `out.rotations` (4 (N - 1)); sets `out.reached`, `out.reachable`, `out.error`,
   * `out.iterations`. Allocates nothing.
   */
  solveInto<T extends { joints: Float32Array; rotations: Float32Array }>(
    target: Vec3 | Landmark | Float32Array,
    out: T,
    pole?: Vec3 | Landmark | Float32Array,
  ): T & { reached: boolean; reachable: boolean; error: number; iterations: number } {
    const n = this.#n;
    if (
      !isObject(out) ||
      !(out.joints instanceof Float32Array) ||
      out.joints.length !== 3 * n ||
      !(out.rotations instanceof Float32Array) ||
      out.rotations.length !== 4 * (n - 1)
    ) {
      throw new TypeError(`out: must be { joints: Float32Array(${3 * n}), rotations: Float32Array(${4 * (n - 1)}) }`);
    }
    const p = this.#run("solveInto", target, pole);
    out.joints.set(p.subarray(0, 3 * n));
    out.rotations.set(p.subarray(3 * n, 3 * n + 4 * (n - 1)));
    const st = 3 * n + 4 * (n - 1);
    const o = out as T & { reached: boolean; reachable: boolean; error: number; iterations: number };
    o.reached = p[st] === 1;
    o.reachable = p[st + 1] === 1;
    o.error = p[st + 2]!;
    o.iterations = p[st + 3]!;
    return o;
  }

  /** Back to the rest pose. */
  reset(): void {
    this.#views("reset").reset();
  }

  /** Releases the wasm memory. Safe to call twice (idempotent). */
  free(): void {
    const r = this.#raw;
    if (r) {
      this.#raw = null;
      this.#goal = new Float32Array(0);
      this.#pose = new Float32Array(0);
      r.free();
    }
  }

  /** True once `free()` was called. */
  get freed(): boolean {
    return this.#raw === null;
  }
}

addDispose(ChainSolver);
