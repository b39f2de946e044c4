#!/usr/bin/env node
// The documentation's links resolve: every relative link of README.md, CHANGELOG.md, every
// .md file under docs/ (its subfolders included) and the READMEs of eval/ and tools/ names a
// file that exists and, with a #fragment, a heading in it (GitHub's slugs).
// remark-validate-links (a devDependency of tests/node) does the checking; no network.
//
//   node tests/node/check-links.mjs [FILE.md ...]

import { spawnSync } from "node:child_process";
import fs from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";

const here = path.dirname(fileURLToPath(import.meta.url));
const repo = path.resolve(here, "..", "..");
const remark = path.join(here, "node_modules", ".bin", "remark");
const plugin = path.join(here, "node_modules", "remark-validate-links", "index.js");
if (!fs.existsSync(remark) || !fs.existsSync(plugin)) {
  console.error("tests/node/check-links.mjs: remark-cli or remark-validate-links missing: run `make setup` (npm ci --prefix tests/node)");
  process.exit(1);
}
const files = process.argv.slice(2);
if (files.length === 0) {
  const docs = fs.readdirSync(path.join(repo, "docs"), { recursive: true }).map((f) => f.split(path.sep).join("/"));
  files.push("README.md", "CHANGELOG.md", "eval/README.md", "tools/README.md", ...docs.filter((f) => f.endsWith(".md")).sort().map((f) => `docs/${f}`));
}
// --frail: warnings (a missing file or heading) fail; repository:false: no git remote to read.
const res = spawnSync(remark, ["--no-config", "--no-stdout", "--frail", "--quiet", "--use", `${plugin}=repository:false`, ...files], {
  cwd: repo,
  stdio: "inherit",
});
if (res.status !== 0) {
  console.error("tests/node/check-links.mjs: broken links above");
  process.exit(1);
}
console.log(`check-links: ${files.length} files, every relative link and anchor resolves`);
