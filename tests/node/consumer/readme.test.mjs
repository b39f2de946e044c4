// The options reference (docs/reference/options.md, generated from the Rust option table and linked from
// the README shipped in the package) documents every option exactly as the running module
// describes it (HandRig.optionDescriptions()): path, type, default, enum values and range.

import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";
import { createRequire } from "node:module";
import { describe, it } from "node:test";

import { HandRig, LAYOUT } from "handrig";

import { repo as repoRoot } from "./support.mjs";

const require = createRequire(import.meta.url);
// README.md is not an export; find it next to the package.json, which is.
const readme = fs.readFileSync(path.join(path.dirname(require.resolve("handrig/package.json")), "README.md"), "utf8");

/**
 * Rows of the options reference (docs/reference/options.md in the repository, generated from the Rust
 * option table; the README links to it): { path: [spec, description] }.
 */
function optionRows() {
  const page = fs.readFileSync(path.join(repoRoot, "docs", "reference", "options.md"), "utf8");
  const rows = {};
  for (const line of page.split("\n")) {
    const m = line.match(/^\| `([A-Za-z.]+)` \| (.*) \| (.*) \|$/);
    if (m) rows[m[1]] = [m[2], m[3]];
  }
  return rows;
}

// optionDescriptions() gives the shortest decimals of Rust's f32 values; the page prints them
// as Rust's `{}` does, never in exponent notation (1e-9 is 0.000000001).
function num(x) {
  const s = String(x);
  const m = s.match(/^(-?)(\d)(?:\.(\d+))?e-(\d+)$/);
  if (!m) return s;
  return `${m[1]}0.${"0".repeat(Number(m[4]) - 1)}${m[2]}${m[3] ?? ""}`;
}

/** The page's "type, range, default" cell for one description of the running module. */
function spec(d) {
  const def = (v) => (v === null || v === undefined ? "unset" : `\`${v}\``);
  switch (d.type) {
    case "boolean":
      return `boolean, default ${def(d.default)}`;
    case "enum":
      return `one of ${d.values.map((v) => `\`"${v}"\``).join(", ")}, default ${def(`"${d.default}"`)}`;
    case "number":
      return `${d.integer ? "whole number" : "number"} in ${num(d.min)}..${num(d.max)}, default ${def(d.default === null ? null : num(d.default))}`;
    case "numbers":
      return `${d.length} numbers in ${num(d.min)}..${num(d.max)}, default ${def(`[${d.default.map(num).join(", ")}]`)}`;
    case "points":
      return `object of [x, y, z] (meters, within 10) named ${d.names.join(", ")}, default unset`;
    default:
      throw new Error(`unknown option type ${d.type} for ${d.path}`);
  }
}

describe("options reference (docs/reference/options.md) against the running module", () => {
  const rows = optionRows();
  const described = HandRig.optionDescriptions();

  it("lists exactly the options of HandRig.optionDescriptions()", () => {
    assert.deepEqual(Object.keys(rows).sort(), described.map((d) => d.path).sort());
  });

  it("the README links to it", () => {
    // (The packed README links into the repository: pkg-config/readme-links.mjs.)
    assert.match(readme, /\((?:https:\/\/github\.com\/handrig\/handrig\/blob\/main\/)?docs\/reference\/options\.md\)/);
  });

  for (const d of described) {
    it(`${d.path}: type, default, values and range`, () => {
      const row = rows[d.path];
      assert.ok(row, `docs/reference/options.md has no row for \`${d.path}\` (HANDRIG_GENERATE=write cargo test --lib options)`);
      assert.equal(row[0], spec(d));
      assert.equal(row[1], d.description);
    });
  }
});

describe("flat layout table (docs/reference/flat-layout.md, linked from the README)", () => {
  const page = fs.readFileSync(path.join(repoRoot, "docs", "reference", "flat-layout.md"), "utf8");
  const section = page.split(/^# Flat frame layout/m)[1]?.split(/^##+ /m)[0];

  it("the README links to it", () => {
    // (The packed README links into the repository: pkg-config/readme-links.mjs.)
    assert.match(readme, /\((?:https:\/\/github\.com\/handrig\/handrig\/blob\/main\/)?docs\/reference\/flat-layout\.md\)/);
  });

  const rows = {};
  for (const line of (section ?? "").split("\n")) {
    const m = line.match(/^\| `((?:input|output)\.[A-Za-z.]+)` \| \+?(\d+) \|/);
    if (m) rows[m[1]] = Number(m[2]);
  }

  it("has a row with the right offset for every field of LAYOUT", () => {
    const leaves = [];
    const walk = (o, prefix) => {
      for (const [k, v] of Object.entries(o)) {
        const p = `${prefix}.${k}`;
        if (typeof v === "number") leaves.push([p, v]);
        else walk(v, p);
      }
    };
    walk(LAYOUT.input, "input");
    walk(LAYOUT.output, "output");
    // Strides are given in the size column of their section's row.
    const strides = leaves.filter(([p]) => /Stride$/.test(p));
    for (const [p, v] of leaves) {
      if (/Stride$/.test(p)) continue;
      assert.equal(rows[p], v, `docs/reference/flat-layout.md row \`${p}\``);
    }
    for (const [p, v] of strides) assert.match(section, new RegExp(`\`${p.replace(".", "\\.")}\` = ${v}\\b`), p);
    assert.equal(Object.keys(rows).length, leaves.length - strides.length, "no rows for fields LAYOUT lacks");
    assert.match(section, new RegExp(`Layout version ${LAYOUT.version} `));
  });
});
