// What `npm pack` put in the tarball and what the installed package.json says.

import assert from "node:assert/strict";
import fs from "node:fs";
import { createRequire } from "node:module";
import path from "node:path";
import zlib from "node:zlib";
import { describe, it } from "node:test";

const require = createRequire(import.meta.url);
const pack = JSON.parse(process.env.HANDRIG_PACK);
const manifest = require("handrig/package.json");
const installed = path.dirname(require.resolve("handrig/package.json"));

describe("the packed tarball", () => {
  const files = pack.files.map((f) => f.path).sort();

  it("holds exactly the entry points, types, wasm, the command line, README and LICENSE", () => {
    assert.deepEqual(files, [
      "LICENSE",
      "README.md",
      "cli.mjs",
      "compat.cjs",
      "compat.d.cts",
      "compat.d.ts",
      "compat.js",
      "index.cjs",
      "index.d.cts",
      "index.d.ts",
      "index.js",
      "index.mjs",
      "package.json",
      "three-vrm.cjs",
      "three-vrm.d.cts",
      "three-vrm.d.ts",
      "three-vrm.js",
      "three.cjs",
      "three.d.cts",
      "three.d.ts",
      "three.js",
      "wasm/handrig_bg.wasm",
      "wasm/handrig_simd_bg.wasm",
      "wasm/handrig_wasm.cjs",
      "wasm/handrig_wasm.d.ts",
      "wasm/handrig_wasm.js",
      "worker.cjs",
      "worker.d.cts",
      "worker.d.ts",
      "worker.js",
    ]);
  });

  for (const file of ["handrig_bg.wasm", "handrig_simd_bg.wasm"]) it(`ships an optimized ${file} (wasm-opt ran) that Node can compile`, () => {
    const wasm = fs.readFileSync(path.join(installed, "wasm", file));
    assert.ok(WebAssembly.validate(wasm));
    // Debug builds are several times larger; the release build is a few hundred KiB at most.
    // Issue 24's budget: 250 KiB gzipped (issue 10's 150 KiB held until serde and
    // serde-wasm-bindgen came in for setup-time reading: 148.4 -> 205 KiB).
    assert.ok(wasm.length < 1024 * 1024, `wasm is ${wasm.length} bytes`);
    const gzipped = zlib.gzipSync(wasm, { level: 9 }).length;
    // Milestone 4 (the face, the legs, contact on any avatar: 247.1 -> 271.6 KiB, then 254.7
    // without serde_path_to_error): 256 KiB; 250 KiB again without core's float formatting
    // (244.8 KiB, docs/measurements/2026-12-05-size.md).
    assert.ok(gzipped <= 250 * 1024, `wasm is ${(gzipped / 1024).toFixed(1)} KiB gzipped, over the 250 KiB budget (issues 24, 50, 51, 52)`);
    const customSections = WebAssembly.Module.customSections(new WebAssembly.Module(wasm), "name");
    assert.equal(customSections.length, 0, "release wasm keeps no name section");
  });

  it("the README's sizes are the packed files' (gzip -9, within 5%)", () => {
    const readme = fs.readFileSync(path.join(installed, "README.md"), "utf8");
    const m = readme.match(/(\d+) KiB gzip in one file instead of `index\.js`'s (\d+) KiB \+ the `\.wasm`'s (\d+) KiB \(the SIMD build's (\d+) KiB\)/);
    assert.ok(m, "README states compat.js, index.js and the .wasm files' gzip sizes");
    const gzipKiB = (f) => zlib.gzipSync(fs.readFileSync(path.join(installed, f)), { level: 9 }).length / 1024;
    const files = ["compat.js", "index.js", "wasm/handrig_bg.wasm", "wasm/handrig_simd_bg.wasm"];
    files.forEach((f, i) => {
      const stated = Number(m[i + 1]);
      const actual = gzipKiB(f);
      assert.ok(Math.abs(stated - actual) <= Math.max(1, 0.05 * actual), `${f}: README says ${stated} KiB, the package has ${actual.toFixed(1)} KiB gzip (node pkg-config/build.mjs prints it)`);
    });
  });

  it("README and LICENSE are the repository's, the README's links to files the tarball lacks pointing at the repository", () => {
    const repo = process.env.HANDRIG_REPO;
    assert.equal(fs.readFileSync(path.join(installed, "LICENSE"), "utf8"), fs.readFileSync(path.join(repo, "LICENSE"), "utf8"));
    assert.match(fs.readFileSync(path.join(installed, "LICENSE"), "utf8"), /^MIT License/);
    const packed = fs.readFileSync(path.join(installed, "README.md"), "utf8");
    const base = `${manifest.repository.url.replace(/^git\+/, "").replace(/\.git$/, "")}/blob/main/`;
    // Only link targets changed: taking the base out again gives the repository's README.
    assert.equal(packed.split(`](${base}`).join("]("), fs.readFileSync(path.join(repo, "README.md"), "utf8"));
    let rewritten = 0;
    for (const [, target] of packed.replace(/^```[\s\S]*?^```$/gm, "").matchAll(/\]\(([^)\s]+)/g)) {
      const file = target.split("#")[0];
      if (target.startsWith(base)) {
        rewritten++;
        assert.ok(fs.existsSync(path.join(repo, file.slice(base.length))), `${target}: no such file in the repository`);
      } else if (!/^([a-z]+:|#)/i.test(target)) {
        assert.ok(fs.existsSync(path.join(installed, file)), `${target}: a relative link to a file the package does not hold`);
      }
    }
    assert.ok(rewritten >= 10, `${rewritten} links into the repository (docs/, CHANGELOG.md)`);
  });

  it("the README link rewriter (pkg-config/readme-links.mjs): relative links outside the package, anchors kept, code and absolute links untouched", async () => {
    const { packedReadme } = await import(new URL(`file://${path.join(process.env.HANDRIG_REPO, "pkg-config", "readme-links.mjs")}`).href);
    const text = [
      "[a](docs/a.md#x) and ![img](./docs/i.png \"t\") and [lic](LICENSE) and [web](https://x.org/a.md) and [top](#install)",
      "```md",
      "[code](docs/a.md)",
      "```",
      "`[span](docs/b.md)` [root](/abs.md) [mail](mailto:a@b.c) [deep](docs/guide/c.md) [a link",
      "over two lines](docs/d.md#y).",
    ].join("\n");
    assert.equal(
      packedReadme(text, "https://h/blob/main/", ["LICENSE", "wasm/"]),
      [
        "[a](https://h/blob/main/docs/a.md#x) and ![img](https://h/blob/main/docs/i.png \"t\") and [lic](LICENSE) and [web](https://x.org/a.md) and [top](#install)",
        "```md",
        "[code](docs/a.md)",
        "```",
        "`[span](https://h/blob/main/docs/b.md)` [root](/abs.md) [mail](mailto:a@b.c) [deep](https://h/blob/main/docs/guide/c.md) [a link",
        "over two lines](https://h/blob/main/docs/d.md#y).",
      ].join("\n"),
    );
  });
});

describe("package.json", () => {
  it("name, version from Cargo.toml, license, sideEffects", () => {
    assert.equal(manifest.name, "handrig");
    assert.equal(manifest.version, process.env.HANDRIG_CARGO_VERSION);
    assert.equal(manifest.license, "MIT");
    assert.equal(manifest.sideEffects, false);
    assert.equal(manifest.type, "module");
  });

  it("bin: the handrig command (cli.mjs, executable)", () => {
    assert.deepEqual(manifest.bin, { handrig: "cli.mjs" });
    assert.ok(fs.statSync(path.join(installed, "cli.mjs")).mode & 0o100, "cli.mjs is executable");
  });

  it("repository, homepage and bugs name Cargo.toml's repository; keywords; engines", () => {
    const cargo = fs.readFileSync(path.join(process.env.HANDRIG_REPO, "Cargo.toml"), "utf8");
    const repository = cargo.match(/^repository\s*=\s*"([^"]+)"/m)?.[1];
    assert.ok(repository?.startsWith("https://github.com/"), `Cargo.toml repository: ${repository}`);
    assert.deepEqual(manifest.repository, { type: "git", url: `git+${repository}.git` });
    assert.equal(manifest.homepage, `${repository}#readme`);
    assert.deepEqual(manifest.bugs, { url: `${repository}/issues` });
    assert.ok(manifest.keywords.includes("vrm") && manifest.keywords.includes("mediapipe"));
    assert.equal(manifest.engines.node, ">=18");
    // node10 resolution (no exports) reads `types`: the CommonJS declarations, as `main` is CommonJS.
    assert.equal(manifest.main, "./index.cjs");
    assert.equal(manifest.types, "./index.d.cts");
  });

  it("main, module, types and every export target exist in the package", () => {
    const targets = [manifest.main, manifest.module, manifest.types];
    const walk = (v) => {
      if (typeof v === "string") targets.push(v);
      else for (const x of Object.values(v)) walk(x);
    };
    walk(manifest.exports);
    for (const t of targets) assert.ok(fs.existsSync(path.join(installed, t)), `${t} missing`);
    assert.deepEqual(Object.keys(manifest.exports), [
      ".",
      "./three-vrm",
      "./compat",
      "./three",
      "./worker",
      "./handrig_bg.wasm",
      "./handrig_simd_bg.wasm",
      "./package.json",
    ]);
  });

  it("resolves to the Node builds under Node's conditions", () => {
    assert.equal(require.resolve("handrig"), path.join(installed, "index.cjs"));
    assert.equal(require.resolve("handrig/three-vrm"), path.join(installed, "three-vrm.cjs"));
    assert.equal(require.resolve("handrig/compat"), path.join(installed, "compat.cjs"));
    assert.equal(require.resolve("handrig/three"), path.join(installed, "three.cjs"));
    assert.equal(require.resolve("handrig/worker"), path.join(installed, "worker.cjs"));
    if (import.meta.resolve) {
      assert.equal(import.meta.resolve("handrig"), `file://${path.join(installed, "index.mjs")}`);
      assert.equal(import.meta.resolve("handrig/three-vrm"), `file://${path.join(installed, "three-vrm.js")}`);
      assert.equal(import.meta.resolve("handrig/compat"), `file://${path.join(installed, "compat.js")}`);
      assert.equal(import.meta.resolve("handrig/three"), `file://${path.join(installed, "three.js")}`);
      assert.equal(import.meta.resolve("handrig/worker"), `file://${path.join(installed, "worker.js")}`);
    }
  });

  it("does not expose internals (wasm glue) as subpaths", () => {
    assert.throws(() => require.resolve("handrig/wasm/handrig_wasm.cjs"), { code: "ERR_PACKAGE_PATH_NOT_EXPORTED" });
  });
});
