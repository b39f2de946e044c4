// The README shipped in the installed package, the docs pages of the repository (docs/), and
// their code blocks by section: what the README and docs tests run as written.

import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";
import { createRequire } from "node:module";

import { repo } from "./support.mjs";

const require = createRequire(import.meta.url);

/** README.md next to the installed package's package.json (README is not an export). */
export const readme = fs.readFileSync(path.join(path.dirname(require.resolve("handrig/package.json")), "README.md"), "utf8");

/** The text of a docs page of the repository, e.g. docPage("guide/frames.md") for docs/guide/frames.md. */
export function docPage(name) {
  return fs.readFileSync(path.join(repo, "docs", ...name.split("/")), "utf8");
}

/** The fenced blocks of language `lang` in the section of `text` (the README or a docs page) headed exactly `heading`, in order. */
export function codeBlocks(text, heading, lang = "js") {
  const escaped = heading.replace(/[.*+?^${}()|[\]\\]/g, "\\$&");
  const section = text.split(new RegExp(`^${escaped}$`, "m"))[1]?.split(/^##+ /m)[0];
  assert.ok(section, `has a section "${heading}"`);
  return [...section.matchAll(new RegExp(`^\`\`\`${lang}\\n([\\s\\S]*?)^\`\`\`$`, "gm"))].map((m) => m[1]);
}
