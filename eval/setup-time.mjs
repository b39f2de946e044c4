// What a rig costs to make from a file: `HandRig.fromVrm` (a `.vrm`) or `HandRig.fromGltf` (a
// `.glb`) on every generated avatar (tests/fixtures/avatars: 13,524 vertices, 27,036 triangles
// each), then `rig.free()`. With two builds, they are timed in turns (A then B each round) so
// that the shared machine's load slows both alike. The figure is the median over rounds, ms.
//
//   node eval/setup-time.mjs --a DIR [--b DIR] [--rounds N] [--avatar FILE ...]
//
// DIR: a built package, e.g. pkg/; --avatar (repeatable): time these files instead, e.g. the
// 108k-triangle copy of the woman that `node eval/dense-avatar.mjs` writes.
//
// Used for issue 26 (the skin read from the file): before (a build without it) and after.

import { readFileSync, readdirSync } from "node:fs";
import { createRequire } from "node:module";
import { basename, dirname, resolve } from "node:path";
import { fileURLToPath } from "node:url";

const here = dirname(fileURLToPath(import.meta.url));
const require = createRequire(import.meta.url);
const arg = (name, dflt) => {
  const i = process.argv.indexOf(name);
  return i > 0 ? process.argv[i + 1] : dflt;
};
if (arg("--a") === undefined) {
  console.error("usage: node eval/setup-time.mjs --a DIR [--b DIR] [--rounds N]");
  process.exit(1);
}
const builds = [["A", arg("--a")], ["B", arg("--b")]]
  .filter(([, d]) => d !== undefined)
  .map(([label, d]) => ({ label, dir: d, HandRig: require(resolve(d)).HandRig }));
const rounds = Number(arg("--rounds", 15));
const dir = resolve(here, "..", "tests", "fixtures", "avatars");
const chosen = process.argv.flatMap((a, i) => (process.argv[i - 1] === "--avatar" ? [resolve(a)] : []));
const files = (chosen.length ? chosen : readdirSync(dir).filter((f) => /\.(vrm|glb)$/.test(f)).sort().map((f) => resolve(dir, f))).map((f) => ({
  name: basename(f),
  bytes: new Uint8Array(readFileSync(f)),
}));

const make = (HandRig, f) => (f.name.endsWith(".vrm") ? HandRig.fromVrm(f.bytes) : HandRig.fromGltf(f.bytes));
const times = new Map();
for (let round = -2; round < rounds; round++) {
  for (const f of files) {
    for (const b of builds) {
      const t0 = performance.now();
      make(b.HandRig, f).free();
      const t = performance.now() - t0;
      if (round < 0) continue; // warm-up
      const key = `${f.name}\t${b.label}`;
      if (!times.has(key)) times.set(key, []);
      times.get(key).push(t);
    }
  }
}
const median = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  return s[Math.floor(s.length / 2)];
};
for (const b of builds) console.log(`${b.label}: ${b.dir}`);
console.log(`median of ${rounds} rounds, ms\n`);
console.log(["file", ...builds.map((b) => b.label)].join("\t"));
for (const f of files) console.log([f.name, ...builds.map((b) => median(times.get(`${f.name}\t${b.label}`)).toFixed(2))].join("\t"));
