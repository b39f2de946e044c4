// One verdict per bad frame on every input path: the JS object API's part. The table
// (tests/fixtures/bad-frames.json: a valid base frame, and cases that change one number of it
// with the field each must be rejected for) is the one tests/it/bad_frames.rs runs through the
// native and flat paths in Rust. Here HandRig.solve must reject each case with an Error naming
// that field, keep working, and accept the base frame.

import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";
import { it } from "node:test";

import { HandRig } from "handrig";
import { avatars, readBytes, repo } from "./support.mjs";

const table = JSON.parse(fs.readFileSync(path.join(repo, "tests", "fixtures", "bad-frames.json"), "utf8"));

const special = { NaN: Number.NaN, Infinity: Number.POSITIVE_INFINITY, "-Infinity": Number.NEGATIVE_INFINITY };
const num = (v) => (typeof v === "string" ? special[v] : v);
const scale = (v, by) => (Array.isArray(v) ? v.map((x) => scale(x, by)) : v * by);

/** The base frame with one case's change, as tests/it/bad_frames.rs makes it. */
function edited(base, c) {
  const frame = structuredClone(base);
  let at = frame;
  for (const key of c.path.slice(0, -1)) at = at[key];
  const last = c.path[c.path.length - 1];
  at[last] = "value" in c ? num(c.value) : scale(at[last], c.scale);
  return frame;
}

it("the JS object API rejects each bad frame naming the field Rust names", () => {
  const rig = HandRig.fromVrm(readBytes(avatars.robot));
  rig.solve(table.base);
  let checked = 0;
  for (const c of table.cases) {
    if (c.paths && !c.paths.includes("object")) continue;
    const frame = edited(table.base, c);
    assert.notDeepEqual(frame, table.base, `${c.name}: the case changes nothing`);
    assert.throws(
      () => rig.solve(frame),
      (e) => {
        assert.ok(e instanceof Error, `${c.name}: threw a non-Error`);
        // The field, then the message; the field may go on into a sub-field
        // (`[3]` for a visibility given as the fourth number), not into a sibling.
        const rest = e.message.slice(c.field.length);
        assert.ok(
          e.message.startsWith(c.field) && /^[:.[]/.test(rest),
          `${c.name}: expected an error naming ${c.field}, got ${e.message}`,
        );
        return true;
      },
      `${c.name}: accepted`,
    );
    // The rig keeps working.
    const result = rig.solve(table.base);
    assert.ok(Number.isFinite(result.timeMs), `${c.name}: the base frame afterwards`);
    checked++;
  }
  assert.ok(checked >= 15, `only ${checked} cases apply to the object API`);
  rig.free();
});
