// Options: nested objects or dotted paths (as optionDescriptions() spells them), checked against
// the descriptions generated from the Rust option table (options.json from src/options/table.rs:
// every path, type, range and default),
// normalized into a fresh plain nested object that the raw constructors pass to Rust, which
// reads it with serde-wasm-bindgen. No option path is written here: they all come from
// `optionDescriptions()`. Their TypeScript type, `HandRigOptions`, is generated from the same
// table (options-types.ts).

import { describe, fail, givenFields, isObject, readUser, reading, type Bag } from "./errors.js";
import type { HandRigOptions } from "./options-types.js";
import { point3 } from "./points.js";

export type { HandRigOptions };

/** One option, for building UIs: its dot-separated path, type, range and default. */
export type OptionDescription =
  | { path: string; type: "boolean"; default: boolean; description: string }
  | { path: string; type: "enum"; values: string[]; default: string; description: string }
  | {
      path: string;
      type: "number";
      min: number;
      max: number;
      /** Absent when the option is unset by default. */
      default?: number | null;
      step: number;
      /** True when only whole numbers are accepted. */
      integer?: boolean;
      description: string;
    }
  | {
      path: string;
      /** An object of named points `{ name: [x, y, z] }`; no default (derived values apply). */
      type: "points";
      names: string[];
      default: null;
      description: string;
    }
  | {
      path: string;
      /** A fixed-length array of numbers, each in min..max. */
      type: "numbers";
      length: number;
      min: number;
      max: number;
      default: number[];
      description: string;
    };

// Defined by build.mjs (esbuild `define`): options.json, generated from the Rust option table
// (the .wasm carries neither the list nor the descriptions' text). Numbers are the shortest
// decimals of the f32 values Rust holds (`0.05`, not `0.05000000074505806`).
declare const __HANDRIG_OPTIONS__: readonly OptionDescription[];

/** Every option's description (a fresh array of fresh objects each call: a caller may change what it gets). */
export function cleanDescriptions(): OptionDescription[] {
  return JSON.parse(JSON.stringify(__HANDRIG_OPTIONS__)) as OptionDescription[];
}

let descriptionsCache: Map<string, OptionDescription> | undefined;
function descriptions(): Map<string, OptionDescription> {
  if (descriptionsCache === undefined) {
    descriptionsCache = new Map(cleanDescriptions().map((d) => [d.path, d]));
  }
  return descriptionsCache;
}

function checkOptionValue(d: OptionDescription, value: unknown, field: string): unknown {
  switch (d.type) {
    case "boolean":
      if (typeof value !== "boolean") fail(field, `must be true or false, got ${describe(value)}`);
      return value;
    case "enum":
      if (typeof value !== "string" || !d.values.includes(value)) {
        fail(field, `must be one of ${d.values.map((v) => JSON.stringify(v)).join(", ")}, got ${describe(value)}`);
      }
      return value;
    case "points": {
      // { name: [x, y, z] | {x, y, z} } with names from d.names, normalized to arrays; null:
      // none given (the default).
      if (value === null) return null;
      if (!isObject(value) || Array.isArray(value)) {
        fail(field, `must be an object { ${d.names.join(", ")} } of [x, y, z] (meters), got ${describe(value)}`);
      }
      const out: { [name: string]: [number, number, number] } = {};
      const given = givenFields(value, field);
      for (const key of Object.keys(given)) {
        if (!d.names.includes(key)) {
          fail(`${field}.${key}`, `unknown point (expected one of ${d.names.join(", ")})`);
        }
        const p = given[key];
        if (p === null) continue;
        out[key] = point3(p, `${field}.${key}`);
      }
      return out;
    }
    case "numbers": {
      // A fixed-length array of numbers, copied.
      if (!Array.isArray(value) || value.length !== d.length) {
        fail(field, `must be an array of ${d.length} numbers in ${d.min}..${d.max}, got ${describe(value)}`);
      }
      return value.map((x: unknown, i) => {
        if (typeof x !== "number" || !Number.isFinite(x) || x < d.min || x > d.max) {
          fail(`${field}[${i}]`, `must be a number in ${d.min}..${d.max}, got ${describe(x)}`);
        }
        return x;
      });
    }
    case "number":
      if (value === null && d.default === null) return null;
      if (typeof value !== "number" || !Number.isFinite(value)) {
        fail(field, `must be a number in ${d.min}..${d.max}, got ${describe(value)}`);
      }
      if (value < d.min || value > d.max) fail(field, `must be in ${d.min}..${d.max}, got ${value}`);
      if (d.integer && !Number.isInteger(value)) fail(field, `must be a whole number in ${d.min}..${d.max}, got ${value}`);
      return value;
    default:
      return value;
  }
}

type Nested = { [key: string]: unknown };

function normalizeOptions(options: unknown): Nested | undefined {
  if (options === undefined || options === null) return undefined;
  if (!isObject(options) || Array.isArray(options)) {
    fail("options", `must be an object, got ${describe(options)}`);
  }
  const known = descriptions();
  const out: Nested = {};
  const seen = new Set<string>();
  const walk = (obj: Bag, prefix: string): void => {
    reading.part = prefix === "" ? "options" : `options.${prefix}`;
    const given = givenFields(obj, prefix === "" ? "options" : `options.${prefix}`);
    for (const key of Object.keys(given)) {
      const path = prefix === "" ? key : `${prefix}.${key}`;
      const field = `options.${path}`;
      reading.part = field;
      const value = given[key];
      const d = known.get(path);
      if (d !== undefined) {
        if (seen.has(path)) fail(field, "given twice (as a nested object and as a dotted path)");
        seen.add(path);
        const parts = path.split(".");
        let o = out;
        for (let i = 0; i < parts.length - 1; i++) {
          if (!isObject(o[parts[i]!])) o[parts[i]!] = {};
          o = o[parts[i]!] as Nested;
        }
        o[parts[parts.length - 1]!] = checkOptionValue(d, value, field);
        continue;
      }
      let group = false;
      for (const p of known.keys()) {
        if (p.startsWith(`${path}.`)) {
          group = true;
          break;
        }
      }
      if (!group) fail(field, `unknown option${optionHint(path, known)}`);
      // `filter: false` is `filter: { enabled: false }` (any group with an `enabled` switch).
      if (typeof value === "boolean" && known.has(`${path}.enabled`)) {
        walk({ enabled: value }, path);
        continue;
      }
      if (!isObject(value) || Array.isArray(value)) {
        fail(field, `must be an object of ${path}.* options, got ${describe(value)}`);
      }
      walk(value, path);
    }
  };
  walk(options, "");
  return out;
}

// Names users bring from MediaPipe and other rigs for handrig's options.
const OPTION_ALIASES: { readonly [name: string]: string } = {
  selfieMode: "inputMirrored",
  mirrored: "mirror",
  flipHorizontal: "inputMirrored",
};

/**
 * " (did you mean X?)" for an unknown option path: a known alias, or the option or group path
 * nearest in spelling (at most 2 edits, or the same name in another case).
 */
function optionHint(path: string, known: Map<string, OptionDescription>): string {
  const alias: unknown = OPTION_ALIASES[path];
  if (alias !== undefined) return ` (did you mean ${String(alias)}?)`;
  const names = new Set<string>();
  for (const p of known.keys()) {
    const parts = p.split(".");
    for (let i = 1; i <= parts.length; i++) names.add(parts.slice(0, i).join("."));
  }
  let best: string | undefined;
  let bestDistance = 3;
  for (const name of names) {
    const d = name.toLowerCase() === path.toLowerCase() ? 0 : editDistance(name, path);
    if (d < bestDistance) {
      best = name;
      bestDistance = d;
    }
  }
  return best === undefined ? "" : ` (did you mean ${best}?)`;
}

/** Levenshtein distance (setup-time: option names are short). */
function editDistance(a: string, b: string): number {
  let prev = Array.from({ length: b.length + 1 }, (_, j) => j);
  for (let i = 1; i <= a.length; i++) {
    const row = [i];
    for (let j = 1; j <= b.length; j++) {
      row[j] = Math.min(prev[j]! + 1, row[j - 1]! + 1, prev[j - 1]! + (a[i - 1] === b[j - 1] ? 0 : 1));
    }
    prev = row;
  }
  return prev[b.length]!;
}

/**
 * Options as the raw constructors take them: a fresh plain object of checked values (no user
 * getters or prototypes reach Rust, which reads it with serde-wasm-bindgen), or undefined for the
 * defaults.
 */
export function optionsValue(options: unknown): Nested | undefined {
  return readUser("options", () => normalizeOptions(options));
}
