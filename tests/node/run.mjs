#!/usr/bin/env node
// Node tests of the packed package, the way a user gets it:
//   1. `npm pack` the built package (pkg/, made by `make pkg`);
//   2. a fresh temp project installs the tarball from file, plus the test tooling from the npm
//      registry (three, @pixiv/three-vrm, @types/three, typescript, esbuild: the versions of
//      tests/node/package.json and its lockfile);
//   3. the node:test files in tests/node/consumer/ are copied there and run with `node --test`,
//      so `import "handrig"` / `require("handrig")` resolve through the package's own exports.
//
//   node tests/node/run.mjs [--pkg DIR] [--keep] [--only REGEXP] [-- extra node --test args]
//
// --only runs the test files whose names match (the linters run whatever it says).
//
// Environment passed to the tests: HANDRIG_SHARED (the shared/ folder: avatars and recordings;
// default <repo>/../shared), HANDRIG_REPO (the repository, for tests/fixtures), HANDRIG_PACK
// (npm pack's JSON report), HANDRIG_CARGO_VERSION.

import { execFileSync, spawnSync } from "node:child_process";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { fileURLToPath } from "node:url";

const here = path.dirname(fileURLToPath(import.meta.url));
const repo = path.resolve(here, "..", "..");

function fail(msg) {
  console.error(`tests/node/run.mjs: ${msg}`);
  process.exit(1);
}

const argv = process.argv.slice(2);
let pkgDir = path.join(repo, "pkg");
let keep = Boolean(process.env.HANDRIG_KEEP_TMP);
let only = /./;
const extra = [];
for (let i = 0; i < argv.length; i++) {
  if (argv[i] === "--pkg") pkgDir = path.resolve(argv[++i]);
  else if (argv[i] === "--keep") keep = true;
  else if (argv[i] === "--only") only = new RegExp(argv[++i] ?? fail("--only needs a pattern"));
  else if (argv[i] === "--") extra.push(...argv.slice(i + 1)), (i = argv.length);
  else fail(`unknown argument ${argv[i]}`);
}

if (!fs.existsSync(path.join(pkgDir, "package.json"))) {
  fail(`${pkgDir}/package.json not found: build the package first (make pkg)`);
}
const shared = path.resolve(process.env.HANDRIG_SHARED || path.join(repo, "..", "shared"));
if (!fs.existsSync(path.join(shared, "avatars", "debug-robot.vrm"))) {
  fail(`${shared}/avatars/debug-robot.vrm not found: set HANDRIG_SHARED to the shared/ folder`);
}

const npm = process.platform === "win32" ? "npm.cmd" : "npm";

// The package linters (devDependencies of tests/node, run from here, not installed in the
// consumer project): publint (package.json against the files, exports order and formats) and
// @arethetypeswrong/cli (what TypeScript resolves for every entry point under node10, node16
// CJS and ESM, and bundler resolution). attw's "strict" profile; the .wasm entry points carry no
// types by design and are excluded.
const LINTERS = ["publint", "@arethetypeswrong/cli", "remark-cli", "remark-validate-links"];
const WASM_ENTRYPOINTS = ["./handrig_bg.wasm", "./handrig_simd_bg.wasm"];

function lint(tarball) {
  const bin = (name) => {
    const p = path.join(here, "node_modules", ".bin", name);
    if (!fs.existsSync(p)) fail(`${p} is missing: run \`make setup\` (npm ci --prefix tests/node)`);
    return p;
  };
  const runLinter = (name, args) => {
    console.log(`# ${name} ${args.map((a) => (path.isAbsolute(a) ? path.relative(repo, a) : a)).join(" ")}`);
    const res = spawnSync(bin(name), args, { stdio: "inherit", cwd: tmp });
    if (res.status !== 0) fail(`${name} found problems in the package (above)`);
  };
  runLinter("publint", ["--strict", pkgDir]);
  runLinter("attw", ["--profile", "strict", "--no-emoji", "--no-color", "--exclude-entrypoints", ...WASM_ENTRYPOINTS, "--", tarball]);
}
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), "handrig-node-tests-"));
const cleanup = () => {
  if (keep) console.log(`tests/node/run.mjs: kept ${tmp}`);
  else fs.rmSync(tmp, { recursive: true, force: true });
};

let status = 1;
try {
  // 1. Pack exactly what `npm publish` would upload.
  const packJson = execFileSync(npm, ["pack", "--json", "--pack-destination", tmp, pkgDir], {
    encoding: "utf8",
    stdio: ["ignore", "pipe", "inherit"],
  });
  const pack = JSON.parse(packJson)[0];
  const tarball = path.join(tmp, pack.filename);
  console.log(`# packed ${pack.filename}: ${pack.entryCount} files, ${pack.size} bytes`);
  lint(tarball);

  // 2. A fresh consumer project.
  const project = path.join(tmp, "consumer");
  fs.mkdirSync(project);
  // Same test tooling as tests/node (devDependencies and lockfile, so three, three-vrm,
  // typescript and esbuild resolve to the locked versions), plus handrig from the tarball.
  const tools = { ...JSON.parse(fs.readFileSync(path.join(here, "package.json"), "utf8")).devDependencies };
  for (const name of LINTERS) delete tools[name];
  fs.writeFileSync(
    path.join(project, "package.json"),
    `${JSON.stringify(
      {
        name: "handrig-consumer",
        private: true,
        type: "commonjs",
        dependencies: { handrig: `file:${tarball}` },
        devDependencies: tools,
      },
      null,
      2,
    )}\n`,
  );
  fs.copyFileSync(path.join(here, "package-lock.json"), path.join(project, "package-lock.json"));
  execFileSync(npm, ["install", "--no-audit", "--no-fund", "--prefer-offline", "--loglevel", "error"], {
    cwd: project,
    stdio: ["ignore", "inherit", "inherit"],
  });
  const installed = path.join(project, "node_modules", "handrig", "package.json");
  if (!fs.existsSync(installed)) fail("npm install did not install handrig from the tarball");

  // 3. The tests, run from inside the consumer project.
  const consumerSrc = path.join(here, "consumer");
  fs.cpSync(consumerSrc, path.join(project, "test"), { recursive: true });
  const files = fs
    .readdirSync(path.join(project, "test"))
    .filter((f) => /\.test\.(c|m)?js$/.test(f) && only.test(f))
    .sort()
    .map((f) => path.join("test", f));
  if (files.length === 0) fail("no tests in tests/node/consumer");
  const cargoToml = fs.readFileSync(path.join(repo, "Cargo.toml"), "utf8");
  const cargoVersion = cargoToml.match(/^\[package\][\s\S]*?^version\s*=\s*"([^"]+)"/m)?.[1];
  const env = {
    ...process.env,
    HANDRIG_SHARED: shared,
    HANDRIG_REPO: repo,
    HANDRIG_PACK: JSON.stringify(pack),
    HANDRIG_CARGO_VERSION: cargoVersion ?? "",
  };
  // --no-concurrent-recompilation reaches every test file's process (node --test passes its own
  // flags on): Node 20 can hang at exit on a background TurboFan job (consumer/support.mjs,
  // CHILD_NODE_FLAGS), and a test file that never exits would hold CI until its time runs out.
  const res = spawnSync(process.execPath, ["--no-concurrent-recompilation", "--test", "--test-reporter=spec", ...extra, ...files], {
    cwd: project,
    env,
    stdio: "inherit",
  });
  status = res.status ?? 1;
} catch (e) {
  console.error(e);
  status = 1;
} finally {
  cleanup();
}
process.exit(status);
