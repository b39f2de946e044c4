// Errors of the JS layer: every failure is an `Error` whose message starts with the path of the
// field that is wrong (`frame.hands[0].worldLandmarks: must have 21 points, got 20`).
//
// Paths are passed as pieces (`fa`, `fi`, `fb`: "frame.hands", 1, ".worldLandmarks") and joined
// only when something is wrong, so a good frame builds no strings. `where` remembers the part of
// the frame being read and `reading` the part of the options, a rest pose or a ChainSolver
// argument (setup-time reads), to name it when a user getter or Proxy throws.

/** A user object's properties, read one at a time (and checked before use). */
export type Bag = { readonly [key: string]: unknown };

/** An input problem found in JavaScript: the message starts with the field's path. */
export class FieldError extends Error {}

export function path(fa: string, fi: number, fb: string): string {
  return fi < 0 ? fa + fb : `${fa}[${fi}]${fb}`;
}

export function fail(field: string, problem: string): never {
  throw new FieldError(`${field}: ${problem}`);
}

/** The part of the frame being read (set by the packers, read when a getter throws). */
export const where = { a: "frame", i: -1, b: "" };

export function at(a: string, i: number, b: string): void {
  where.a = a;
  where.i = i;
  where.b = b;
}

/** The part of the options, a rest pose or a ChainSolver argument being read. */
export const reading = { part: "" };

export function tag(v: unknown): string {
  return Object.prototype.toString.call(v).slice(8, -1);
}

export function isObject(v: unknown): v is Bag {
  return v !== null && typeof v === "object";
}

/**
 * The fields of an options object that are given: its own enumerable fields, except those set to
 * `undefined`, which mean absent, as TypeScript's optional fields do (`{ constraints: undefined }`
 * reads as `{}`). The one rule for every options object of the package (HandRig's options, the
 * ChainSolver's and its constraints, fromGltf's `skeleton`, toVRMA/toBVH's, createRigWorker's):
 * each reader reads the user's object through this, once per field (a getter runs once), and
 * passes on only this plain copy (no `undefined` reaches Rust's serde reader). `field` is the
 * object's path (`options.skeleton`), for errors.
 */
export function givenFields(options: Bag, field: string): { [key: string]: unknown } {
  const out: { [key: string]: unknown } = {};
  // `reading.part` names what a throwing getter or Proxy trap was reading (see readUser).
  reading.part = field;
  for (const key of Object.keys(options)) {
    reading.part = `${field}.${key}`;
    const value = options[key];
    if (value !== undefined) out[key] = value;
  }
  return out;
}

/** A typed array or DataView (its length and elements read like an array's). */
export function isView(v: unknown): v is ArrayBufferView & Bag {
  return ArrayBuffer.isView(v);
}

export function isFiniteNumber(v: unknown): v is number {
  return typeof v === "number" && v - v === 0;
}

/** What `v` is, for messages: "an array of 20", "a Float32Array of 62", "string \"x\"". */
export function describe(v: unknown): string {
  if (v === null) return "null";
  if (v === undefined) return "undefined";
  if (Array.isArray(v)) return `an array of ${v.length}`;
  if (isView(v)) return `a ${tag(v)} of ${String(v.length)}`;
  if (typeof v === "object") return tag(v) === "Object" ? "an object" : `a ${tag(v)}`;
  if (typeof v === "string") return `string ${JSON.stringify(v.length > 40 ? `${v.slice(0, 40)}...` : v)}`;
  return `${typeof v} ${String(v)}`;
}

// A frame's points (meters; image landmarks in image units) lie within this of the origin, as
// Rust checks (`COORDINATE_LIMIT` in src/input/validate.rs): larger finite numbers overflow the solvers.
export const COORDINATE_LIMIT = 1000;
const RANGE_MESSAGE = `must be within -${COORDINATE_LIMIT}..${COORDINATE_LIMIT} (meters; image landmarks in image units)`;

export function notFinite(v: unknown, field: string): never {
  return fail(field, typeof v === "number" ? "must be a finite number" : `must be a number, got ${describe(v)}`);
}

/** A finite number, for fields read once per frame (the path is a constant string). */
export function finite(v: unknown, field: string): number {
  if (!isFiniteNumber(v)) notFinite(v, field);
  return v;
}

/**
 * Whether `v` is a number within -limit..limit (the frame's points: COORDINATE_LIMIT;
 * ChainSolver's: CHAIN_LIMIT, 1e9). NaN fails the comparison.
 */
export function within(v: unknown, limit: number): v is number {
  return typeof v === "number" && Math.abs(v) <= limit;
}

/**
 * Throws the error for a `v` that is not `within(v, limit)`. Callers build `field` only then: a
 * template string per good number would be garbage every frame.
 */
export function outOfBounds(v: unknown, limit: number, field: string): never {
  if (!isFiniteNumber(v)) notFinite(v, field);
  return fail(field, limit === COORDINATE_LIMIT ? `${RANGE_MESSAGE}, got ${v}` : `must be within -1e9..1e9, got ${v}`);
}

/** What a user getter threw, as text (whatever it threw: a value whose toString throws too). */
function thrownMessage(e: unknown): string {
  try {
    return isObject(e) && typeof e.message === "string" ? e.message : String(e);
  } catch {
    return "a value that cannot be shown";
  }
}

/**
 * What a user getter threw while `part` was read, as an Error naming it (our own FieldErrors pass
 * through).
 */
export function userError(e: unknown, part: string): Error {
  if (e instanceof FieldError) return e;
  const err = new Error(`${part}: reading it threw: ${thrownMessage(e)}`);
  err.cause = e;
  return err;
}

/** A user getter or Proxy threw while the frame was read: name the part being read. */
export function readError(e: unknown): Error {
  return userError(e, path(where.a, where.i, where.b));
}

/**
 * Runs `read` (which reads user objects and reports bad values with `fail`), turning what a user
 * getter throws into an Error naming the part being read.
 */
export function readUser<T>(what: string, read: () => T): T {
  reading.part = what;
  try {
    return read();
  } catch (e) {
    throw userError(e, reading.part);
  }
}

/** Anything thrown (by wasm-bindgen, or a user getter), as an Error. */
export function asError(e: unknown): Error {
  if (e instanceof Error) return e;
  // Errors from another realm (iframe, vm context) are still errors: keep them.
  if (isObject(e) && typeof e.message === "string") return e as unknown as Error;
  return new Error(typeof e === "string" ? e : `handrig: ${String(e)}`);
}
