#!/usr/bin/env node
// Builds the npm package into pkg/ (rapier.js style): wasm-pack compiles the crate once and
// emits two wasm-bindgen glues for the same .wasm, then the templates in pkg-config/ are merged
// around them.
//
//   node pkg-config/build.mjs [--dev] [--out-dir DIR]
//
//   --dev       wasm-pack --dev (debug build, no wasm-opt): faster, larger, slower.
//
// wasm-opt: wasm-pack runs with --no-opt and this script runs binaryen's wasm-opt from npm
// (pkg-config/node_modules, `make setup`) once on the shared .wasm. Debian's binaryen 108 is too
// old: it rewrites wasm-bindgen 0.2.130's externref table export into the funcref table and the
// module then fails to instantiate ("WebAssembly.Table.set(): Argument 1 is invalid").
//   --out-dir   where the package goes (default: pkg/ at the repository root).
//
// Layout of the package:
//   index.js          browsers and bundlers (ES module): `await init()` once, then HandRig.
//   index.cjs         Node CommonJS: the wasm is compiled synchronously at require time.
//   index.mjs         Node ES module: re-exports index.cjs, so require and import share one
//                     WebAssembly instance (no dual-package hazard).
//   index.d.ts/.d.cts types; three-vrm.{js,cjs,d.ts,d.cts} the three-vrm adapter.
//   wasm/             wasm-bindgen output: handrig_wasm.js (--target web glue),
//                     handrig_wasm.cjs (--target nodejs glue), handrig_bg.wasm (shared; the
//                     package exports it as "handrig/handrig_bg.wasm") and
//                     handrig_simd_bg.wasm ("handrig/handrig_simd_bg.wasm").
//
// Two builds of the crate: the baseline, and one with WebAssembly SIMD
// (`-C target-feature=+simd128`, its own target dir), which runs a full frame about 7% faster
// in V8 (glam's vector math in 128-bit lanes; README, "Speed"). The glues are the same for both
// (the build checks), and both glues pick the file when they load: the SIMD build where the
// engine validates a SIMD instruction (Chrome 91+, Firefox 89+, Safari 16.4+, Node 16.4+), the
// baseline elsewhere. In Node HANDRIG_WASM=baseline or simd128 forces one.

import { execFileSync } from "node:child_process";
import { createRequire } from "node:module";
import fs from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";
import zlib from "node:zlib";

// The shipped WebAssembly file's one name (in wasm/, exported as "handrig/handrig_bg.wasm").
const WASM_NAME = "handrig_bg.wasm";
// The SIMD build's file, beside it.
const WASM_SIMD_NAME = "handrig_simd_bg.wasm";

// Size budget of the shipped .wasm, gzipped, from issue 10 (set before the chain IK and the
// retargeting landed). Printed with every build; tests/node guards it (the release build
// measures 148.4 KiB, SIMD 144.3, with everything of milestone 2; see the README, "Speed").
const WASM_GZIP_BUDGET = 150 * 1024;

// Code generation for both WebAssembly builds: LLVM unrolls loops up to a cost of 125 instead
// of its -O3 default (300). Fully unrolled loops over bones, fingers and sides made the
// constructors and the frame's stages 13 KiB gzip larger: 161.2 -> 148.4 KiB baseline, 155.5 ->
// 144.3 SIMD, at the same speed (`node eval/ab.mjs`, three runs: object API 0.97-1.00 of the
// time, flat path 0.97-1.07; a threshold of 50 was 5% slower, 150 left the baseline at
// 150.9 KiB). Natively (cargo build, tests, benches) the crate keeps LLVM's defaults.
const WASM_RUSTFLAGS = "-C llvm-args=-unroll-threshold=125";

const here = path.dirname(fileURLToPath(import.meta.url));
const root = path.resolve(here, "..");

function fail(msg) {
  console.error(`build.mjs: ${msg}`);
  process.exit(1);
}

function parseArgs(argv) {
  const args = { dev: false, outDir: path.join(root, "pkg") };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    if (a === "--dev") args.dev = true;
    else if (a === "--out-dir") args.outDir = path.resolve(argv[++i] ?? fail("--out-dir needs a value"));
    else if (a === "--help" || a === "-h") {
      console.log("usage: node pkg-config/build.mjs [--dev] [--out-dir DIR]");
      process.exit(0);
    } else fail(`unknown argument ${a}`);
  }
  return args;
}

/** The `key = "string"` entries of Cargo.toml's [package] table (all this script needs). */
function cargoPackage(tomlText) {
  const out = {};
  let inPackage = false;
  for (const line of tomlText.split(/\r?\n/)) {
    const table = line.match(/^\s*\[([^\]]+)\]\s*$/);
    if (table) {
      inPackage = table[1].trim() === "package";
      continue;
    }
    if (!inPackage) continue;
    const kv = line.match(/^\s*([A-Za-z0-9_-]+)\s*=\s*"((?:[^"\\]|\\.)*)"\s*(#.*)?$/);
    if (kv) out[kv[1]] = JSON.parse(`"${kv[2]}"`);
  }
  return out;
}

/** The version of `crate` locked in Cargo.lock. */
function lockedVersion(lockText, crate) {
  const re = new RegExp(`\\[\\[package\\]\\]\\s*\\nname = "${crate}"\\s*\\nversion = "([^"]+)"`);
  const m = lockText.match(re);
  return m ? m[1] : undefined;
}

function run(cmd, args, opts = {}) {
  console.log(`$ ${cmd} ${args.join(" ")}`);
  try {
    execFileSync(cmd, args, { stdio: "inherit", cwd: root, ...opts });
  } catch (e) {
    fail(`${cmd} failed (${e.status === null ? e.signal : `exit ${e.status}`})`);
  }
}

function checkWasmBindgen(lockText) {
  const want = lockedVersion(lockText, "wasm-bindgen");
  if (!want) fail("Cargo.lock has no wasm-bindgen package");
  let have;
  try {
    have = execFileSync("wasm-bindgen", ["--version"], { encoding: "utf8" }).trim();
  } catch {
    fail(`wasm-bindgen is not on PATH; run \`make setup\` (cargo install wasm-bindgen-cli --version ${want})`);
  }
  // wasm-pack would otherwise try to download the matching CLI, which fails offline.
  if (have !== `wasm-bindgen ${want}`) {
    fail(`${have} on PATH, Cargo.lock wants ${want}; run \`make setup\``);
  }
}

// The features rustc enables by default for wasm32-unknown-unknown (Rust >= 1.82), which the
// module uses; wasm-opt must keep them.
const WASM_FEATURES = [
  "--enable-bulk-memory",
  "--enable-nontrapping-float-to-int",
  "--enable-reference-types",
  "--enable-sign-ext",
  "--enable-mutable-globals",
  "--enable-multivalue",
];

function wasmOpt(input, output, simd = false) {
  const bin = path.join(here, "node_modules", ".bin", "wasm-opt");
  if (!fs.existsSync(bin)) fail(`${bin} is missing; run \`make setup\` (npm ci --prefix pkg-config)`);
  // Names and producers sections only add bytes: with panic=abort there are no symbolized
  // panics to print.
  const features = simd ? [...WASM_FEATURES, "--enable-simd"] : WASM_FEATURES;
  run(bin, ["-O3", ...features, "--strip-debug", "--strip-producers", input, "-o", output]);
}

// Prepended to both glues: which .wasm to load. The probe is the smallest module using a SIMD
// instruction, `(func (result v128) i32.const 0 i8x16.splat)`: engines with WebAssembly SIMD
// validate it.
const SIMD_PROBE = `// handrig (pkg-config/build.mjs): load the SIMD build where the engine has WebAssembly SIMD.
const HANDRIG_SIMD_PROBE = new Uint8Array([
  0x00, 0x61, 0x73, 0x6d, 0x01, 0x00, 0x00, 0x00, // "\\0asm", version 1
  0x01, 0x05, 0x01, 0x60, 0x00, 0x01, 0x7b, // type section: one type, () -> v128
  0x03, 0x02, 0x01, 0x00, // function section: one function of type 0
  0x0a, 0x08, 0x01, 0x06, 0x00, 0x41, 0x00, 0xfd, 0x0f, 0x0b, // code: i32.const 0, i8x16.splat, end
]);
function handrigSimd() {
  try {
    return WebAssembly.validate(HANDRIG_SIMD_PROBE);
  } catch {
    return false;
  }
}
`;
const NODE_CHOOSER = `${SIMD_PROBE}function handrigWasmFile() {
  const force = typeof process === "object" && process.env ? process.env.HANDRIG_WASM : undefined;
  if (force === "baseline") return "${WASM_NAME}";
  if (force === "simd128") return "${WASM_SIMD_NAME}";
  if (force) throw new Error(\`handrig: HANDRIG_WASM must be "baseline" or "simd128", got \${JSON.stringify(force)}\`);
  return handrigSimd() ? "${WASM_SIMD_NAME}" : "${WASM_NAME}";
}
`;

// Entry points: the shared core (no module syntax) between a prologue and an epilogue.
function esmBrowserEntry(core, version, layout) {
  return `${banner(version)}
import wasmInit, * as raw from "./wasm/handrig_wasm.js";

let ready = false;

${layoutConst(layout)}
${core}
const api = createHandRigApi(raw, () => ready);

/**
 * Instantiates the WebAssembly module; call once (await it) before anything else. With no
 * argument it fetches wasm/handrig_bg.wasm next to this file (bundlers that understand
 * \`new URL(..., import.meta.url)\` copy it); or pass its URL, a Response, its bytes or a
 * WebAssembly.Module. Calling it again is a no-op.
 */
export async function init(input) {
  const arg =
    input === undefined
      ? undefined
      : input !== null && Object.getPrototypeOf(input) === Object.prototype
        ? input
        : { module_or_path: input };
  await wasmInit(arg);
  ready = true;
}

/** Synchronous init from the .wasm bytes or a compiled WebAssembly.Module (e.g. in a worker). */
export function initSync(module) {
  const arg =
    module !== null && typeof module === "object" && Object.getPrototypeOf(module) === Object.prototype
      ? module
      : { module };
  raw.initSync(arg);
  ready = true;
}

export const HandRig = api.HandRig;
export const ChainSolver = api.ChainSolver;
export const wasmBuild = api.wasmBuild;
/** The file in \`wasm/\` that \`init()\` loads in this engine (no init needed): what a worker fetches. */
export function wasmFile() {
  return raw.__handrigSimd() ? ${JSON.stringify(WASM_SIMD_NAME)} : ${JSON.stringify(WASM_NAME)};
}
export { LAYOUT };
export const version = ${JSON.stringify(version)};
export default init;
`;
}

function cjsNodeEntry(core, version, layout) {
  return `${banner(version)}
"use strict";
// Node: the glue compiles and instantiates the wasm synchronously when it is required.
const raw = require("./wasm/handrig_wasm.cjs");

${layoutConst(layout)}
${core}
const api = createHandRigApi(raw, () => true);

/** A no-op in Node (the module is ready once required); kept for code shared with browsers. */
function init() {
  return Promise.resolve();
}
/** A no-op in Node. */
function initSync() {}

exports.HandRig = api.HandRig;
exports.ChainSolver = api.ChainSolver;
exports.wasmBuild = api.wasmBuild;
/** The file in \`wasm/\` this process loaded (HANDRIG_WASM, else by the engine's SIMD support). */
exports.wasmFile = () => raw.__handrigWasmFile();
exports.LAYOUT = LAYOUT;
exports.init = init;
exports.initSync = initSync;
exports.version = ${JSON.stringify(version)};
`;
}

function esmNodeEntry(version) {
  return `${banner(version)}
// Node ES module entry: the CommonJS build, so import and require share one wasm instance.
import { createRequire } from "node:module";

const cjs = createRequire(import.meta.url)("./index.cjs");

export const HandRig = cjs.HandRig;
export const ChainSolver = cjs.ChainSolver;
export const wasmBuild = cjs.wasmBuild;
export const wasmFile = cjs.wasmFile;
export const LAYOUT = cjs.LAYOUT;
export const init = cjs.init;
export const initSync = cjs.initSync;
export const version = cjs.version;
export default init;
`;
}

function adapterEsm(core, version, layout) {
  return `${banner(version)}
${layoutConst(layout)}
${core}
export { restPoseFromVRM, applyToVRM };
`;
}

function adapterCjs(core, version, layout) {
  return `${banner(version)}
"use strict";
${layoutConst(layout)}
${core}
exports.restPoseFromVRM = restPoseFromVRM;
exports.applyToVRM = applyToVRM;
`;
}

/** The flat frame layout (src/flat.rs), frozen, as a constant of the generated module. */
function layoutConst(layout) {
  return `// The flat frame layout of this build (src/flat.rs, read from the wasm by build.mjs).
const LAYOUT = deepFreeze(${JSON.stringify(layout)});
function deepFreeze(o) {
  for (const v of Object.values(o)) if (v !== null && typeof v === "object") deepFreeze(v);
  return Object.freeze(o);
}`;
}

function banner(version) {
  return `// handrig ${version}. Generated by pkg-config/build.mjs from pkg-config/src; edit those.`;
}

/** The CommonJS flavor of a .d.ts: no default export (CommonJS has none). */
function toCts(dts) {
  const out = dts.replace(/^export default [^;]+;\n/m, "");
  if (out === dts && /^export default/m.test(dts)) fail("could not drop the default export for .d.cts");
  return out.replace("index.d.ts (ES module entry points) and index.d.cts", "index.d.ts and index.d.cts");
}

function main() {
  const args = parseArgs(process.argv.slice(2));
  const cargo = cargoPackage(fs.readFileSync(path.join(root, "Cargo.toml"), "utf8"));
  if (cargo.name !== "handrig" || !cargo.version) fail("Cargo.toml [package] must have name = \"handrig\" and a version");
  const lockText = fs.readFileSync(path.join(root, "Cargo.lock"), "utf8");
  checkWasmBindgen(lockText);

  const work = path.join(root, "target", "handrig-pkg");
  fs.rmSync(work, { recursive: true, force: true });
  const profile = args.dev ? "--dev" : "--release";
  const wasmPack = (target, outDir, env) =>
    run(
      "wasm-pack",
      ["--log-level", "warn", "build", profile, "--no-pack", "--no-opt", "--target", target,
        "--out-dir", outDir, "--out-name", "handrig_wasm", root],
      env ? { env: { ...process.env, ...env } } : {},
    );
  const rustflags = `${process.env.RUSTFLAGS ?? ""} ${WASM_RUSTFLAGS}`.trim();
  for (const target of ["web", "nodejs"]) wasmPack(target, path.join(work, target), { RUSTFLAGS: rustflags });
  // The SIMD build: its own target dir, so the two builds do not invalidate each other's cache.
  const simdDir = path.join(work, "simd128");
  wasmPack("web", simdDir, {
    RUSTFLAGS: `${rustflags} -C target-feature=+simd128`,
    CARGO_TARGET_DIR: path.join(root, "target", "simd128"),
  });

  const out = args.outDir;
  fs.rmSync(out, { recursive: true, force: true });
  fs.mkdirSync(path.join(out, "wasm"), { recursive: true });
  const web = path.join(work, "web");
  const node = path.join(work, "nodejs");
  const webWasm = fs.readFileSync(path.join(web, "handrig_wasm_bg.wasm"));
  const nodeWasm = fs.readFileSync(path.join(node, "handrig_wasm_bg.wasm"));
  // One name for the WebAssembly file everywhere: wasm/handrig_bg.wasm (export
  // "handrig/handrig_bg.wasm"); both glues are pointed at it.
  const shippedWasm = path.join(out, "wasm", WASM_NAME);
  if (args.dev) fs.writeFileSync(shippedWasm, webWasm);
  else wasmOpt(path.join(web, "handrig_wasm_bg.wasm"), shippedWasm);
  const shippedSimd = path.join(out, "wasm", WASM_SIMD_NAME);
  if (args.dev) fs.copyFileSync(path.join(simdDir, "handrig_wasm_bg.wasm"), shippedSimd);
  else wasmOpt(path.join(simdDir, "handrig_wasm_bg.wasm"), shippedSimd, true);
  // One glue serves both builds: same exports, same imports.
  if (fs.readFileSync(path.join(simdDir, "handrig_wasm.js"), "utf8") !== fs.readFileSync(path.join(web, "handrig_wasm.js"), "utf8")) {
    fail("the SIMD build's wasm-bindgen glue differs from the baseline's: both must export and import the same");
  }
  const renameWasm = (glue, what, from, to) => {
    if (!glue.includes(from)) fail(`${what} glue: cannot find ${from} to rename`);
    return glue.replace(from, to);
  };
  let nodeGlue =
    NODE_CHOOSER +
    "exports.__handrigWasmFile = handrigWasmFile;\n" +
    renameWasm(
      fs.readFileSync(path.join(node, "handrig_wasm.js"), "utf8"),
      "nodejs",
      "${__dirname}/handrig_wasm_bg.wasm`",
      "${__dirname}/${handrigWasmFile()}`",
    );
  // Two literal `new URL(..., import.meta.url)`s, so bundlers that copy such assets copy both.
  const webGlue =
    SIMD_PROBE +
    "export { handrigSimd as __handrigSimd };\n" +
    renameWasm(
      fs.readFileSync(path.join(web, "handrig_wasm.js"), "utf8"),
      "web",
      "new URL('handrig_wasm_bg.wasm', import.meta.url)",
      `(handrigSimd() ? new URL('${WASM_SIMD_NAME}', import.meta.url) : new URL('${WASM_NAME}', import.meta.url))`,
    );
  if (!webWasm.equals(nodeWasm)) {
    // Both glues are made from one compiled module, so the files normally match; if a future
    // wasm-bindgen makes them differ, ship the Node one under its own name.
    nodeGlue = renameWasm(nodeGlue, "nodejs", "${__dirname}/${handrigWasmFile()}`", "${__dirname}/handrig_node_bg.wasm`");
    const nodeShipped = path.join(out, "wasm", "handrig_node_bg.wasm");
    if (args.dev) fs.writeFileSync(nodeShipped, nodeWasm);
    else wasmOpt(path.join(node, "handrig_wasm_bg.wasm"), nodeShipped);
    console.log("build.mjs: web and nodejs .wasm differ; shipping both");
  }
  fs.writeFileSync(path.join(out, "wasm", "handrig_wasm.js"), webGlue);
  fs.copyFileSync(path.join(web, "handrig_wasm.d.ts"), path.join(out, "wasm", "handrig_wasm.d.ts"));
  fs.writeFileSync(path.join(out, "wasm", "handrig_wasm.cjs"), nodeGlue);
  for (const dir of [web, node]) {
    if (fs.existsSync(path.join(dir, "snippets"))) {
      fail(`${dir}/snippets exists (inline JS in the bindings): teach build.mjs to ship it and list it in sideEffects`);
    }
  }

  // The layout comes from the module just built, so the JS constants cannot drift from Rust.
  const layout = createRequire(import.meta.url)(path.join(out, "wasm", "handrig_wasm.cjs")).HandRig.layout();

  const src = path.join(here, "src");
  const types = path.join(here, "types");
  const core = fs.readFileSync(path.join(src, "handrig-core.js"), "utf8");
  const adapter = fs.readFileSync(path.join(src, "three-vrm-core.js"), "utf8");
  const v = cargo.version;
  fs.writeFileSync(path.join(out, "index.js"), esmBrowserEntry(core, v, layout));
  fs.writeFileSync(path.join(out, "index.cjs"), cjsNodeEntry(core, v, layout));
  fs.writeFileSync(path.join(out, "index.mjs"), esmNodeEntry(v));
  fs.writeFileSync(path.join(out, "three-vrm.js"), adapterEsm(adapter, v, layout));
  fs.writeFileSync(path.join(out, "three-vrm.cjs"), adapterCjs(adapter, v, layout));
  const dts = fs.readFileSync(path.join(types, "handrig.d.ts"), "utf8");
  fs.writeFileSync(path.join(out, "index.d.ts"), dts);
  fs.writeFileSync(path.join(out, "index.d.cts"), toCts(dts));
  const adapterDts = fs.readFileSync(path.join(types, "three-vrm.d.ts"), "utf8");
  fs.writeFileSync(path.join(out, "three-vrm.d.ts"), adapterDts);
  fs.writeFileSync(path.join(out, "three-vrm.d.cts"), toCts(adapterDts));

  const manifest = JSON.parse(fs.readFileSync(path.join(here, "package.template.json"), "utf8"));
  manifest.version = v;
  manifest.description = cargo.description ?? "";
  manifest.license = cargo.license ?? "MIT";
  if (cargo.repository) manifest.repository = { type: "git", url: cargo.repository };
  fs.writeFileSync(path.join(out, "package.json"), `${JSON.stringify(manifest, null, 2)}\n`);
  for (const f of ["README.md", "LICENSE"]) {
    if (!fs.existsSync(path.join(root, f))) fail(`${f} missing at the repository root`);
    fs.copyFileSync(path.join(root, f), path.join(out, f));
  }

  // Every file the manifest lists exists, and the Node entry loads and has the API.
  for (const f of manifest.files) {
    if (!fs.existsSync(path.join(out, f))) fail(`package.json lists ${f} but the build did not make it`);
  }
  const api = createRequire(import.meta.url)(path.join(out, "index.cjs"));
  if (typeof api.HandRig !== "function" || typeof api.HandRig.fromVrm !== "function") {
    fail("index.cjs does not export HandRig with fromVrm: do the bindings (src/wasm/mod.rs) export the HandRig class?");
  }
  const kib = (n) => `${(n / 1024).toFixed(1)} KiB`;
  const size = (file) => {
    const bytes = fs.readFileSync(file);
    const gz = zlib.gzipSync(bytes, { level: 9 }).length;
    return `${kib(bytes.length)} raw, ${kib(gz)} gzip` + (gz > WASM_GZIP_BUDGET ? ` (OVER by ${kib(gz - WASM_GZIP_BUDGET)})` : "");
  };
  console.log(
    `build.mjs: ${path.relative(root, out) || "."}/ ready: handrig ${v} (${args.dev ? "dev" : "release"}); ` +
      `wasm (budget ${kib(WASM_GZIP_BUDGET)} gzip): baseline ${size(shippedWasm)}; simd128 ${size(shippedSimd)}`,
  );
}

main();
