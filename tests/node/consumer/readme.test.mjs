// The README shipped in the package documents every option exactly as the running module
// describes it (HandRig.optionDescriptions()): path, type, default, enum values and range.
// When an option is added or changed in Rust, this test names the README row to update.

import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";
import { createRequire } from "node:module";
import { describe, it } from "node:test";

import { HandRig, LAYOUT } from "handrig";

const require = createRequire(import.meta.url);
// README.md is not an export; find it next to the package.json, which is.
const readme = fs.readFileSync(path.join(path.dirname(require.resolve("handrig/package.json")), "README.md"), "utf8");

/** Rows of the table under "### Options": { path: [type, default, values, description] }. */
function optionRows() {
  const section = readme.split(/^### Options$/m)[1]?.split(/^##+ /m)[0];
  assert.ok(section, "README has a '### Options' section");
  const rows = {};
  for (const line of section.split("\n")) {
    const m = line.match(/^\| `([A-Za-z.]+)` \|(.*)\|$/);
    if (!m) continue;
    rows[m[1]] = m[2].split("|").map((c) => c.trim());
  }
  return rows;
}

// optionDescriptions() gives the shortest decimals of Rust's f32 values; the README shows them as
// they are (a rounded bound, e.g. 1.5708 for pi/2, would be outside the range it documents).
const num = (x) => String(x);

describe("README options table", () => {
  const rows = optionRows();
  const described = HandRig.optionDescriptions();

  it("lists exactly the options of HandRig.optionDescriptions()", () => {
    assert.deepEqual(Object.keys(rows).sort(), described.map((d) => d.path).sort());
  });

  for (const d of described) {
    it(`${d.path}: type, default, values and range`, () => {
      const row = rows[d.path];
      assert.ok(row, `README: add a row for \`${d.path}\``);
      const [type, def, values] = row;
      assert.equal(type, d.type);
      if (d.type === "boolean") {
        assert.equal(def, `\`${d.default}\``);
      } else if (d.type === "enum") {
        assert.equal(def, `\`"${d.default}"\``);
        assert.equal(values, d.values.map((v) => `\`"${v}"\``).join(", "));
      } else if (d.type === "points") {
        assert.equal(def, "unset");
        assert.equal(values, d.names.map((v) => `\`${v}\``).join(", "));
      } else {
        assert.equal(def, d.default === null || d.default === undefined ? "unset" : `\`${num(d.default)}\``);
        assert.equal(values, `${num(d.min)} – ${num(d.max)}`);
      }
    });
  }
});

describe("README flat layout table", () => {
  const section = readme.split(/^### Flat frame layout/m)[1]?.split(/^##+ /m)[0];
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
      assert.equal(rows[p], v, `README row \`${p}\``);
    }
    for (const [p, v] of strides) assert.match(section, new RegExp(`\`${p.replace(".", "\\.")}\` = ${v}\\b`), p);
    assert.equal(Object.keys(rows).length, leaves.length - strides.length, "no rows for fields LAYOUT lacks");
    assert.match(section, new RegExp(`Layout version ${LAYOUT.version} `));
  });
});
