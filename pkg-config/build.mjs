#!/usr/bin/env node
// Builds the npm package into pkg/ (rapier.js style): wasm-pack compiles the crate once and
// emits two wasm-bindgen glues for the same .wasm; then the JS layer, TypeScript in
// pkg-config/src, is type-checked (tsc --noEmit, strict), bundled around the glues by esbuild
// (one file per entry point below) and its declarations bundled into the package's .d.ts files
// (dts-bundle-generator). esbuild, typescript and dts-bundle-generator are devDependencies of
// pkg-config (`make setup`); the published package has no runtime dependency.
//
//   node pkg-config/build.mjs [--dev] [--js-only] [--out-dir DIR]
//
//   --dev       wasm-pack --dev (debug build, no wasm-opt): faster, larger, slower.
//   --js-only   keep the wasm/ of the last build in the out dir and rebuild only the JS layer
//               and its types (for work on pkg-config/src; needs one full build first).
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
//   index.d.ts/.d.cts types (emitted from src/index.ts; .d.cts without the default export);
//                     three-vrm.{js,cjs,d.ts,d.cts} the three-vrm adapter (src/three-vrm.ts).
//   cli.mjs           the `handrig` command (bin): `handrig export` (pkg-config/cli.mjs, copied).
//   compat.{js,cjs,d.ts,d.cts}  `handrig/compat` (src/compat.ts): the web glue and the baseline
//                     .wasm inlined as base64 in one file (no fetch, no .wasm to serve).
//                     three.{js,cjs,d.ts,d.cts} the plain three.js adapter (src/three.ts).
//   worker.{js,cjs,d.ts,d.cts}  `handrig/worker` (src/worker.ts): a rig in a module Worker, the
//                     page side and the worker side (which is given `handrig` or `handrig/compat`).
//   wasm/             wasm-bindgen output: handrig_wasm.js (--target web glue),
//                     handrig_wasm.cjs (--target nodejs glue), handrig_bg.wasm (shared; the
//                     package exports it as "handrig/handrig_bg.wasm") and
//                     handrig_simd_bg.wasm ("handrig/handrig_simd_bg.wasm").
//
// Two builds of the crate: the baseline, and one with WebAssembly SIMD
// (`-C target-feature=+simd128`, its own target dir), which runs a full frame about 7% faster
// in V8 (glam's vector math in 128-bit lanes; docs/measurements/2026-12-04-speed.md). The glues are the same for both
// (the build checks), and both glues pick the file when they load: the SIMD build where the
// engine validates a SIMD instruction (Chrome 91+, Firefox 89+, Safari 16.4+, Node 16.4+), the
// baseline elsewhere. In Node HANDRIG_WASM=baseline or simd128 forces one.

import { execFileSync } from "node:child_process";
import { createRequire } from "node:module";
import fs from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";
import zlib from "node:zlib";

import { packedReadme } from "./readme-links.mjs";

// The shipped WebAssembly file's one name (in wasm/, exported as "handrig/handrig_bg.wasm").
const WASM_NAME = "handrig_bg.wasm";
// The SIMD build's file, beside it.
const WASM_SIMD_NAME = "handrig_simd_bg.wasm";

// Size budget of the shipped .wasm, gzipped: 250 KiB. 250 KiB from issue 24 (serde and
// serde-wasm-bindgen read the options, rest poses and the .vrm's JSON at setup: 148.4 KiB
// before, 205 KiB with them); 265 KiB from milestone 4 (the face, issue 50: +4.8 KiB; the legs,
// feet and hips, issue 51: +8.2 KiB; contact's faster skin queries and the chest cue for any
// hand shape, issue 52: +2.4 KiB; 247.1 -> 262.3 KiB, 2.7 KiB of headroom kept); 268 KiB at
// the third session (legs read against the image +2.0 KB, contact's clearance, chest hold and
// faster landing +1.5 KB: 265.8 KiB); 270 KiB at the fifth (the body kept solid after the
// solve +0.9 KB, the legs' planted hips +0.7 KB: 269.1 KiB); 271 KiB at the sixth (the hand's
// outline in contact's clearance +0.5 KB, the legs' locks that slide to the tracking +0.5 KB:
// 270.5 KiB); 272 KiB on 2026-12-07 (the camera's pitch taken out of the legs, issue 51's real
// walking video, +0.75 KB, less the glTF reader built for size -0.16 KB: 271.6 KiB;
// docs/measurements/2026-12-05-size.md); 256 KiB on 2026-12-07, fourth session (the chain
// solver's options and the glTF's top level read without serde_path_to_error, -17 KB: 254.7 KiB,
// 1.3 KiB of headroom; issue 52's 250 KiB less the float formatting serde's messages reach);
// 250 KiB again on 2026-12-07, fifth session (core's float formatting out: handrig's messages
// write numbers with error::Num, serde_core's Unexpected::Float with zmij, vendor/serde_core:
// -8.7 KB; the skin's quartile by a quickselect of handrig's own, -1.7 KB: 244.8 KiB).
// Printed with every build; tests/node guards it.
const WASM_GZIP_BUDGET = 250 * 1024;

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
  const args = { dev: false, jsOnly: false, outDir: path.join(root, "pkg") };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    if (a === "--dev") args.dev = true;
    else if (a === "--js-only") args.jsOnly = true;
    else if (a === "--out-dir") args.outDir = path.resolve(argv[++i] ?? fail("--out-dir needs a value"));
    else if (a === "--help" || a === "-h") {
      console.log("usage: node pkg-config/build.mjs [--dev] [--js-only] [--out-dir DIR]");
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

// wasm-opt's inlining, after LLVM's (which already inlined what pays per frame): no function is
// inlined only because it has one caller (binaryen's default inlines every such function,
// whatever its size: the constructors' and readers' out-of-line parts were copied into their
// one caller and grew there), and the "flexible" inlining stops at 10 bytes of body instead of
// 20. gzip -9 of the SIMD build 255,763 -> 249,583 bytes, the baseline 254,068 -> 247,836, the
// frame no slower (node eval/speed.mjs, woman-vrm1, alternated with main's package:
// docs/measurements/2026-12-05-size.md, 2026-12-08).
const WASM_OPT_INLINING = ["--one-caller-inline-max-function-size=0", "--flexible-inline-max-function-size=10"];

function wasmOpt(input, output, simd = false) {
  const bin = path.join(here, "node_modules", ".bin", "wasm-opt");
  if (!fs.existsSync(bin)) fail(`${bin} is missing; run \`make setup\` (npm ci --prefix pkg-config)`);
  // Names and producers sections only add bytes: with panic=abort there are no symbolized
  // panics to print.
  const features = simd ? [...WASM_FEATURES, "--enable-simd"] : WASM_FEATURES;
  run(bin, ["-O3", ...WASM_OPT_INLINING, ...features, "--strip-debug", "--strip-producers", input, "-o", output]);
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

/** The comment every generated file starts with. */
function banner(version) {
  return `// handrig ${version}. Generated by pkg-config/build.mjs from pkg-config/src (TypeScript); edit those.`;
}

/** A tool installed by `make setup` (npm ci --prefix pkg-config). */
function tool(name) {
  const bin = path.join(here, "node_modules", ".bin", name);
  if (!fs.existsSync(bin)) fail(`${bin} is missing; run \`make setup\` (npm ci --prefix pkg-config)`);
  return bin;
}

// The JS layer: TypeScript in pkg-config/src, one entry per file of the package. esbuild bundles
// each entry with the modules it imports (so every entry has its own copy of the layer, as the
// pasted core had); the wasm-bindgen glue stays a file of its own, imported by the entry under
// the names that src/glue.d.ts declares.
const GLUE = { "handrig:wasm-web": "./wasm/handrig_wasm.js", "handrig:wasm-node": "./wasm/handrig_wasm.cjs" };
// handrig/compat's glue: the web glue with the baseline .wasm inlined as base64 (compatGlue),
// bundled into the entry (not external), so compat.js and compat.cjs are single files.
const COMPAT_GLUE = "handrig:wasm-compat";
const ENTRIES = [
  // Browsers and bundlers (ES module): `await init()` once, then HandRig.
  { src: "index.ts", out: "index.js", format: "esm", platform: "browser" },
  // Node CommonJS: the wasm is compiled synchronously at require time.
  { src: "index-node.ts", out: "index.cjs", format: "cjs", platform: "node" },
  // Node ES module: re-exports index.cjs, so require and import share one WebAssembly instance.
  { src: "index-node-esm.ts", out: "index.mjs", format: "esm", platform: "node" },
  // The three-vrm adapter (`handrig/three-vrm`), which needs no wasm.
  { src: "three-vrm.ts", out: "three-vrm.js", format: "esm", platform: "neutral" },
  { src: "three-vrm.ts", out: "three-vrm.cjs", format: "cjs", platform: "neutral" },
  // `handrig/compat`: the wasm inlined (no fetch, no .wasm file); `await init()` everywhere.
  { src: "compat.ts", out: "compat.js", format: "esm", platform: "neutral" },
  { src: "compat.ts", out: "compat.cjs", format: "cjs", platform: "neutral" },
  // The plain three.js adapter (`handrig/three`), which needs no wasm either.
  { src: "three.ts", out: "three.js", format: "esm", platform: "neutral" },
  { src: "three.ts", out: "three.cjs", format: "cjs", platform: "neutral" },
  // `handrig/worker`: a rig in a module Worker (page side and worker side), no wasm of its own.
  { src: "worker.ts", out: "worker.js", format: "esm", platform: "neutral" },
  { src: "worker.ts", out: "worker.cjs", format: "cjs", platform: "neutral" },
];
// The public types, emitted from the same sources (one bundled .d.ts per entry): index.d.ts and
// three-vrm.d.ts for ES modules, .d.cts (without the default export) for CommonJS.
const DECLARATIONS = [
  {
    src: "index.ts",
    out: "index",
    about:
      "// Types of the handrig package. Conventions: meters, radians, milliseconds; right-handed, +Y up;\n" +
      "// the avatar faces +Z (VRM 1.0; VRM 0.x models face -Z and everything is in the model's own\n" +
      "// frame); quaternions [x, y, z, w].\n",
  },
  {
    src: "compat.ts",
    out: "compat",
    about:
      "// Types of `handrig/compat`: the package's API with the WebAssembly inlined (`await init()` once,\n" +
      "// everywhere; no .wasm file, no fetch). Conventions as in handrig's index.d.ts.\n",
  },
  {
    src: "three-vrm.ts",
    out: "three-vrm",
    about:
      "// Types of `handrig/three-vrm`. The VRM is typed structurally (the members the adapter uses),\n" +
      "// so neither three nor @pixiv/three-vrm is needed to type-check; a three-vrm `VRM` fits.\n",
  },
  {
    src: "three.ts",
    out: "three",
    about:
      "// Types of `handrig/three`. Scene objects are typed structurally (the members the adapter uses),\n" +
      "// so three is not needed to type-check; a three `Object3D` fits.\n",
  },
  {
    src: "worker.ts",
    out: "worker",
    about:
      "// Types of `handrig/worker`: a rig in a module Worker. Workers are typed structurally, so no DOM\n" +
      "// library is needed to type-check; a DOM `Worker` and a worker's `self` fit.\n",
  },
];

/**
 * `tsc --noEmit` (strict, pkg-config/tsconfig.json: no DOM lib) on the sources, then a second
 * program that holds the sources to what was just built: the wasm-bindgen glues' real types
 * fit what src/glue.d.ts declares, and the name unions of src/layout.ts are the wasm's LAYOUT
 * lists (as sets).
 */
function typeCheck(work, layout) {
  const tsc = tool("tsc");
  run(tsc, ["-p", path.join(here, "tsconfig.json")]);
  const dir = path.join(work, "check");
  fs.mkdirSync(dir, { recursive: true });
  // wasm-pack's --target web glue is an ES module (its folder has no package.json to say so).
  fs.writeFileSync(path.join(work, "web", "package.json"), '{ "type": "module" }\n');
  const src = path.join(here, "src");
  const names = (list, type) =>
    `const ${type}List = ${JSON.stringify(list)} as const;\n` +
    `export const ${type}Same: Same<(typeof ${type}List)[number], ${type}> = true;\n`;
  fs.writeFileSync(
    path.join(dir, "check.mts"),
    `// Generated by pkg-config/build.mjs: the sources against the wasm just built.
/// <reference path=${JSON.stringify(path.join(src, "glue.d.ts"))} />
import type * as webGlue from "../web/handrig_wasm.js";
import type * as nodeGlue from "../nodejs/handrig_wasm.js";
import type * as declaredWeb from "handrig:wasm-web";
import type * as declaredNode from "handrig:wasm-node";
import type { BodyJointName, HumanBoneName, TorsoBoneName } from ${JSON.stringify(path.join(src, "layout.js"))};
type Same<A, B> = [A] extends [B] ? ([B] extends [A] ? true : false) : false;
// build.mjs adds __handrigSimd and __handrigWasmFile to the glues.
export const web: Omit<typeof declaredWeb, "__handrigSimd"> = {} as typeof webGlue;
export const node: Omit<typeof declaredNode, "__handrigWasmFile"> = {} as typeof nodeGlue;
${names(layout.bones, "HumanBoneName")}${names(layout.torsoBones, "TorsoBoneName")}${names(layout.bodyJoints, "BodyJointName")}`,
  );
  fs.writeFileSync(
    path.join(dir, "tsconfig.json"),
    `${JSON.stringify(
      {
        extends: path.join(here, "tsconfig.json"),
        // The glues' types name DOM types (fetch's Response, WebAssembly) and Symbol.dispose.
        compilerOptions: { lib: ["es2022", "dom", "esnext.disposable"] },
        include: [path.join(src, "**", "*.ts"), "check.mts"],
      },
      null,
      2,
    )}\n`,
  );
  run(tsc, ["-p", path.join(dir, "tsconfig.json")]);
}

/**
 * handrig/compat's glue (written to `work`/compat/): the package's web glue with its default
 * `new URL(...wasm, import.meta.url)` replaced by the baseline .wasm's bytes, decoded from
 * base64 (rapier's -compat pattern). Returns its path.
 */
function compatGlue(work, out) {
  const glue = fs.readFileSync(path.join(out, "wasm", "handrig_wasm.js"), "utf8");
  const from = `(handrigSimd() ? new URL('${WASM_SIMD_NAME}', import.meta.url) : new URL('${WASM_NAME}', import.meta.url))`;
  if (!glue.includes(from)) fail("web glue: cannot find the .wasm URL to inline for handrig/compat");
  const base64 = fs.readFileSync(path.join(out, "wasm", WASM_NAME)).toString("base64");
  const inlined =
    `// handrig/compat (pkg-config/build.mjs): ${WASM_NAME} inlined as base64.\n` +
    `const HANDRIG_WASM_BASE64 = "${base64}";\n` +
    "function __handrigInlineWasm() {\n" +
    "  const s = atob(HANDRIG_WASM_BASE64);\n" +
    "  const bytes = new Uint8Array(s.length);\n" +
    "  for (let i = 0; i < s.length; i++) bytes[i] = s.charCodeAt(i);\n" +
    "  return bytes;\n" +
    "}\n" +
    "export { __handrigInlineWasm };\n" +
    glue.replace(from, "__handrigInlineWasm()");
  if (inlined.includes("import.meta")) fail("handrig/compat glue still uses import.meta");
  const dir = path.join(work, "compat");
  fs.mkdirSync(dir, { recursive: true });
  const file = path.join(dir, "handrig_wasm_compat.js");
  fs.writeFileSync(file, inlined);
  return file;
}

/** The entry points, bundled by esbuild with the layout and the version inlined. */
async function bundle(out, version, layout, descriptions, compatFile) {
  let esbuild;
  try {
    esbuild = await import("esbuild");
  } catch {
    fail("esbuild is missing; run `make setup` (npm ci --prefix pkg-config)");
  }
  const glue = {
    name: "handrig-glue",
    setup(b) {
      b.onResolve({ filter: /^handrig:wasm-/ }, (a) =>
        a.path === COMPAT_GLUE
          ? { path: compatFile }
          : { path: GLUE[a.path] ?? fail(`unknown glue ${a.path}`), external: true },
      );
    },
  };
  for (const e of ENTRIES) {
    console.log(`$ esbuild src/${e.src} -> ${e.out} (${e.format}, ${e.platform})`);
    await esbuild.build({
      entryPoints: [path.join(here, "src", e.src)],
      outfile: path.join(out, e.out),
      bundle: true,
      format: e.format,
      platform: e.platform,
      target: "es2022",
      external: ["node:module"],
      plugins: [glue],
      define: {
        __HANDRIG_LAYOUT__: JSON.stringify(layout),
        __HANDRIG_OPTIONS__: JSON.stringify(descriptions),
        __HANDRIG_VERSION__: JSON.stringify(version),
      },
      banner: { js: banner(version) },
      legalComments: "none",
      logLevel: "warning",
    });
  }
}

/** One bundled .d.ts per declaration entry (dts-bundle-generator), plus its .d.cts. */
function declarations(work, out, version) {
  const dir = path.join(work, "dts");
  fs.mkdirSync(dir, { recursive: true });
  const config = {
    compilationOptions: { preferredConfigPath: path.join(here, "tsconfig.json") },
    entries: DECLARATIONS.map((d) => ({
      filePath: path.join(here, "src", d.src),
      outFile: path.join(dir, `${d.out}.d.ts`),
      noCheck: false,
      output: { noBanner: true, exportReferencedTypes: false },
    })),
  };
  fs.writeFileSync(path.join(dir, "config.json"), `${JSON.stringify(config, null, 2)}\n`);
  run(tool("dts-bundle-generator"), ["--silent", "--config", path.join(dir, "config.json")]);
  for (const d of DECLARATIONS) {
    const dts = `${banner(version)}\n${d.about}\n${fs.readFileSync(path.join(dir, `${d.out}.d.ts`), "utf8")}`;
    fs.writeFileSync(path.join(out, `${d.out}.d.ts`), dts);
    fs.writeFileSync(path.join(out, `${d.out}.d.cts`), toCts(dts));
  }
}

/** The CommonJS flavor of a .d.ts: no default export (CommonJS has none). */
function toCts(dts) {
  const out = dts.replace(/^export \{\n\t\w+ as default,\n\};\n/m, "");
  if (/ as default\b|^export default/m.test(out)) fail("could not drop the default export for .d.cts");
  return out;
}

/**
 * The two WebAssembly builds and their glues into `out`/wasm/ (the whole of `out` is made anew),
 * with wasm-pack's output in `work`.
 */
function buildWasm(args, work, out, shippedWasm, shippedSimd) {
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

  // core's float formatting (flt2dec: Grisu, Dragon and their tables, 8 KB of the gzipped .wasm)
  // stays out: a `{}` of an f32 or f64 in a message links it again. Its source paths (the names,
  // the panic locations) give it away.
  if (!args.dev && fs.readFileSync(path.join(work, "web", "handrig_wasm_bg.wasm")).includes("flt2dec")) {
    fail(
      "the .wasm links core's float formatting again (flt2dec, 8 KB gzip): some `{}` of an f32 or f64 " +
        "reaches it; write numbers in messages with handrig::error::Num (docs/measurements/2026-12-05-size.md)",
    );
  }
  fs.rmSync(out, { recursive: true, force: true });
  fs.mkdirSync(path.join(out, "wasm"), { recursive: true });
  const web = path.join(work, "web");
  const node = path.join(work, "nodejs");
  const webWasm = fs.readFileSync(path.join(web, "handrig_wasm_bg.wasm"));
  const nodeWasm = fs.readFileSync(path.join(node, "handrig_wasm_bg.wasm"));
  // One name for the WebAssembly file everywhere: wasm/handrig_bg.wasm (export
  // "handrig/handrig_bg.wasm"); both glues are pointed at it.
  if (args.dev) fs.writeFileSync(shippedWasm, webWasm);
  else wasmOpt(path.join(web, "handrig_wasm_bg.wasm"), shippedWasm);
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
}

async function main() {
  const args = parseArgs(process.argv.slice(2));
  const cargo = cargoPackage(fs.readFileSync(path.join(root, "Cargo.toml"), "utf8"));
  if (cargo.name !== "handrig" || !cargo.version) fail("Cargo.toml [package] must have name = \"handrig\" and a version");
  const lockText = fs.readFileSync(path.join(root, "Cargo.lock"), "utf8");
  checkWasmBindgen(lockText);

  const work = path.join(root, "target", "handrig-pkg");
  const out = args.outDir;
  const shippedWasm = path.join(out, "wasm", WASM_NAME);
  const shippedSimd = path.join(out, "wasm", WASM_SIMD_NAME);
  if (!args.jsOnly) buildWasm(args, work, out, shippedWasm, shippedSimd);
  else if (!fs.existsSync(shippedWasm) || !fs.existsSync(path.join(work, "web", "handrig_wasm.d.ts"))) {
    fail("--js-only needs the wasm of a full build in place: run node pkg-config/build.mjs first");
  }

  // The layout's values, generated from its declaration in Rust (src/flat/layout.rs; a Rust test
  // fails when this file is stale), so the JS constants cannot drift from the wasm.
  const layout = JSON.parse(fs.readFileSync(path.join(here, "src", "layout.json"), "utf8"));
  // Every option's path, type, range, default and description, generated from the Rust option
  // table (src/options/table.rs; a Rust test fails when this file is stale): the .wasm carries
  // neither the list nor the text.
  const descriptions = JSON.parse(fs.readFileSync(path.join(here, "src", "options.json"), "utf8"));

  const v = cargo.version;
  typeCheck(work, layout);
  await bundle(out, v, layout, descriptions, compatGlue(work, out));
  declarations(work, out, v);

  const manifest = JSON.parse(fs.readFileSync(path.join(here, "package.template.json"), "utf8"));
  manifest.version = v;
  manifest.description = cargo.description ?? "";
  manifest.license = cargo.license ?? "MIT";
  // repository and homepage: package.template.json spells them as npm wants them; they must
  // name the same place as Cargo.toml's.
  const sameRepo = (url) => url?.replace(/^git\+/, "").replace(/\.git$/, "");
  if (sameRepo(manifest.repository?.url) !== cargo.repository) {
    fail(`package.template.json repository.url ${manifest.repository?.url} is not Cargo.toml's repository ${cargo.repository}`);
  }
  if (manifest.homepage !== cargo.homepage) {
    fail(`package.template.json homepage ${manifest.homepage} is not Cargo.toml's homepage ${cargo.homepage}`);
  }
  fs.writeFileSync(path.join(out, "package.json"), `${JSON.stringify(manifest, null, 2)}\n`);
  for (const f of ["README.md", "LICENSE"]) {
    if (!fs.existsSync(path.join(root, f))) fail(`${f} missing at the repository root`);
    fs.copyFileSync(path.join(root, f), path.join(out, f));
  }
  // The README's links to files the tarball does not carry (docs/, CHANGELOG.md, tests/) point
  // at the repository's main branch (pkg-config/readme-links.mjs).
  const readmeBase = `${cargo.repository}/blob/main/`;
  const readme = fs.readFileSync(path.join(root, "README.md"), "utf8");
  fs.writeFileSync(path.join(out, "README.md"), packedReadme(readme, readmeBase, manifest.files));
  // The command line (`bin`: handrig export ...), plain JavaScript loading ./index.cjs.
  fs.copyFileSync(path.join(here, "cli.mjs"), path.join(out, "cli.mjs"));
  fs.chmodSync(path.join(out, "cli.mjs"), 0o755);

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
  const compatSize = (f) => {
    const bytes = fs.readFileSync(path.join(out, f));
    return `${f} ${kib(bytes.length)} raw, ${kib(zlib.gzipSync(bytes, { level: 9 }).length)} gzip`;
  };
  console.log(
    `build.mjs: ${path.relative(root, out) || "."}/ ready: handrig ${v} (${args.dev ? "dev" : "release"}); ` +
      `wasm (budget ${kib(WASM_GZIP_BUDGET)} gzip): baseline ${size(shippedWasm)}; simd128 ${size(shippedSimd)}; ` +
      `handrig/compat (baseline inlined): ${compatSize("compat.js")} (index.js ${compatSize("index.js").split(" ").slice(1).join(" ")} + ${WASM_NAME})`,
  );
  // The figures README.md's install table states (tests/node/consumer/package.test.mjs holds it
  // to the packed files within 5%).
  const gz = (f) => Math.round(zlib.gzipSync(fs.readFileSync(path.join(out, f)), { level: 9 }).length / 1024);
  console.log(
    `build.mjs: README.md sizes: ${gz("compat.js")} KiB gzip in one file instead of \`index.js\`'s ${gz("index.js")} KiB + ` +
      `the \`.wasm\`'s ${gz(path.join("wasm", WASM_NAME))} KiB (the SIMD build's ${gz(path.join("wasm", WASM_SIMD_NAME))} KiB)`,
  );
}

await main();
