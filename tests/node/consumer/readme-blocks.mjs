// The README shipped in the installed package, and its code blocks by section: what the
// README tests run as written.

import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";
import { createRequire } from "node:module";

const require = createRequire(import.meta.url);

/** README.md next to the installed package's package.json (README is not an export). */
export const readme = fs.readFileSync(path.join(path.dirname(require.resolve("handrig/package.json")), "README.md"), "utf8");

/** The fenced blocks of language `lang` in the README section headed exactly `heading`, in order. */
export function codeBlocks(text, heading, lang = "js") {
  const escaped = heading.replace(/[.*+?^${}()|[\]\\]/g, "\\$&");
  const section = text.split(new RegExp(`^${escaped}$`, "m"))[1]?.split(/^##+ /m)[0];
  assert.ok(section, `README has a section "${heading}"`);
  return [...section.matchAll(new RegExp(`^\`\`\`${lang}\\n([\\s\\S]*?)^\`\`\`$`, "gm"))].map((m) => m[1]);
}
