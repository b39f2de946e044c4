// The static server (no browser): what it serves, what it refuses, the port fallback.

import { test } from "node:test";
import assert from "node:assert/strict";
import { createServer } from "node:net";
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { spawn } from "node:child_process";
import { WWW } from "./helpers.mjs";
import { findPackageDir, startServer } from "../serve.mjs";

test("serves the page, assets, node_modules and the package; refuses escapes", async () => {
  const { server, url, packageDir } = await startServer({ port: 0 });
  try {
    assert.match(url, /^http:\/\/127\.0\.0\.1:\d+\/$/);
    const index = await fetch(url);
    assert.equal(index.status, 200);
    assert.match(index.headers.get("content-type"), /text\/html/);
    assert.equal(index.headers.get("cross-origin-opener-policy"), "same-origin");
    assert.equal(index.headers.get("cross-origin-embedder-policy"), "credentialless");
    assert.equal(await index.text(), readFileSync(join(WWW, "index.html"), "utf8"));

    const vrm = await fetch(url + "assets/debug-robot.vrm");
    assert.equal(vrm.status, 200);
    assert.deepEqual(Buffer.from(await vrm.arrayBuffer()), readFileSync(join(WWW, "assets", "debug-robot.vrm")));

    // The generated human avatars, from tests/fixtures/avatars (not copied into www/).
    const woman = await fetch(url + "avatars/woman-vrm1.vrm");
    assert.equal(woman.status, 200);
    assert.equal(woman.headers.get("content-type"), "model/gltf-binary");
    assert.deepEqual(Buffer.from(await woman.arrayBuffer()), readFileSync(join(WWW, "..", "tests", "fixtures", "avatars", "woman-vrm1.vrm")));
    for (const evil of ["avatars/..%2f..%2fvrm.rs", "avatars/%2e%2e/%2e%2e/%2e%2e/Cargo.toml"]) {
      const r = await fetch(url + evil);
      assert.ok(r.status === 403 || r.status === 404, `${evil} -> ${r.status}`);
    }

    const three = await fetch(url + "node_modules/three/build/three.module.js");
    assert.equal(three.status, 200);
    assert.match(three.headers.get("content-type"), /javascript/);

    if (packageDir) {
      const wasm = await fetch(url + "handrig/wasm/handrig_bg.wasm");
      assert.equal(wasm.status, 200);
      assert.equal(wasm.headers.get("content-type"), "application/wasm");
    }

    assert.equal((await fetch(url + "nope.txt")).status, 404);
    for (const evil of ["..%2f..%2fCargo.toml", "%2e%2e/%2e%2e/Cargo.toml", "handrig/..%2f..%2fCargo.toml"]) {
      const r = await fetch(url + evil);
      assert.ok(r.status === 403 || r.status === 404, `${evil} -> ${r.status}`);
      assert.doesNotMatch(await r.text(), /\[package\]/);
    }
    assert.equal((await fetch(url, { method: "POST" })).status, 405);
  } finally {
    server.close();
  }
});

test("a taken port falls back to a free one", async () => {
  const blocker = createServer();
  await new Promise((r) => blocker.listen(0, "127.0.0.1", r));
  const taken = blocker.address().port;
  const { server, port } = await startServer({ port: taken });
  try {
    assert.notEqual(port, taken);
    assert.equal((await fetch(`http://127.0.0.1:${port}/`)).status, 200);
  } finally {
    server.close();
    blocker.close();
  }
});

test("the package directory: $HANDRIG_PKG when it holds a package, else the next candidate", () => {
  const dir = mkdtempSync(join(tmpdir(), "handrig-pkg-"));
  try {
    const fallback = findPackageDir({});
    assert.equal(findPackageDir({ HANDRIG_PKG: dir }), fallback, "an empty directory is not a package");
    writeFileSync(join(dir, "package.json"), "{}");
    assert.equal(findPackageDir({ HANDRIG_PKG: dir }), fallback, "a package.json alone is not a built package");
    writeFileSync(join(dir, "index.js"), "");
    assert.equal(findPackageDir({ HANDRIG_PKG: dir }), dir);
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});

test("`node serve.mjs` prints the URL and serves it", async () => {
  const child = spawn(process.execPath, [join(WWW, "serve.mjs")], { env: { ...process.env, PORT: "0" } });
  try {
    const url = await new Promise((resolve, reject) => {
      let out = "";
      child.stdout.on("data", (d) => {
        out += d;
        const m = out.match(/handrig demo: (http:\/\/127\.0\.0\.1:\d+\/)/);
        if (m) resolve(m[1]);
      });
      child.on("exit", (code) => reject(new Error(`serve.mjs exited ${code}: ${out}`)));
    });
    assert.equal((await fetch(url)).status, 200);
  } finally {
    child.kill();
  }
});
