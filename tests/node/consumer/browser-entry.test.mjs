// The browser/bundler entry (package.json "browser" / "import" conditions), run in Node with
// `--conditions=browser`: before init() it throws a clear Error, after init() it works, and it
// resolves to index.js, not to the Node entries.

import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import path from "node:path";
import { describe, it } from "node:test";
import { fileURLToPath } from "node:url";

const child = path.join(path.dirname(fileURLToPath(import.meta.url)), "browser-entry.child.mjs");

function runChild(mode) {
  const stdout = execFileSync(process.execPath, ["--conditions=browser", child, mode], {
    encoding: "utf8",
    env: process.env,
  });
  return JSON.parse(stdout.trim().split("\n").pop());
}

describe("browser entry (index.js)", () => {
  for (const mode of ["async", "sync"]) {
    it(`needs init: a clear Error before, a working HandRig after (${mode === "sync" ? "initSync" : "await init"})`, () => {
      const out = runChild(mode);
      assert.equal(out.beforeInit.isError, true);
      assert.match(out.beforeInit.message, /init\(\)/);
      assert.equal(out.boneNames, 53);
      assert.ok(out.solved.includes("rightHand"), `solved ${out.solved}`);
      if (out.entry) assert.match(out.entry, /node_modules\/handrig\/index\.js$/);
      assert.equal(out.version, process.env.HANDRIG_CARGO_VERSION);
    });
  }
});
