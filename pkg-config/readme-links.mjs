// The packed README's links (build.mjs): the repository's README links to files beside it
// (docs/*.md, CHANGELOG.md, tests/...), which the npm tarball does not carry. Every relative
// link to a file the package does not hold becomes a link to that file in the repository
// (`<repository>/blob/<ref>/<path>`, its #anchor kept), so the README on npm and in
// node_modules/handrig links where it should; links within the README (#...), absolute URLs and
// files the package ships are left as they are. Generic: whatever the docs' layout, a link that
// resolves in the repository resolves on GitHub.

/** `text` (markdown) with its relative links outside `shipped` pointing at `base` + path. */
export function packedReadme(text, base, shipped) {
  const keep = new Set(shipped.map((f) => f.replace(/^\.\//, "")));
  // Inline links and images, [text](target) or [text](target "title"), outside fenced blocks (a
  // fence's lines are copied as they are; a link-like code span is rewritten like a link).
  let fenced = false;
  return text
    .split("\n")
    .map((line) => {
      if (/^\s*```/.test(line)) {
        fenced = !fenced;
        return line;
      }
      if (fenced) return line;
      // From the `](` on: a link's text may start on the line before.
      return line.replace(/(\]\()([^)\s]+)((?:\s+"[^"]*")?\))/g, (all, open, target, close) => {
        if (/^([a-z][a-z0-9+.-]*:|#|\/)/i.test(target)) return all;
        const [file, anchor] = target.split(/(?=#)/);
        const clean = file.replace(/^\.\//, "");
        if (keep.has(clean)) return all;
        return `${open}${base}${clean}${anchor ?? ""}${close}`;
      });
    })
    .join("\n");
}
