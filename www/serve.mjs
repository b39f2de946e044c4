#!/usr/bin/env node
// Tiny static server for the handrig demo (node:http, no dependencies).
//
//   node www/serve.mjs            -> http://127.0.0.1:8080/ (or a free port if 8080 is taken)
//   PORT=9000 node www/serve.mjs  -> that port (falls back to a free one if taken)
//   PORT=0 node www/serve.mjs     -> a free port
//
// Serves www/ at / (the page, its assets and www/node_modules for the import map), the
// generated human avatars (tests/fixtures/avatars) at /avatars/, and the
// built handrig package at /handrig/: $HANDRIG_PKG if set (e.g. `node pkg-config/build.mjs
// --out-dir DIR`), else the repository's pkg/ (what `make demo` builds). Only 127.0.0.1 is
// bound: this is a development server, not something to expose.
//
// Responses carry COOP/COEP headers so the page is cross-origin isolated: that makes
// performance.now() fine-grained enough to show per-frame solve times in microseconds.
// COEP is "credentialless" so model files the user points the webcam mode at on other
// origins still load.

import { createServer } from "node:http";
import { createReadStream, existsSync, statSync } from "node:fs";
import { dirname, extname, join, normalize, resolve, sep } from "node:path";
import { fileURLToPath } from "node:url";

const WWW = dirname(fileURLToPath(import.meta.url));
const REPO = resolve(WWW, "..");
/** tests/fixtures/avatars (tools/avatars/generate.mjs), served at /avatars/. */
const AVATARS = join(REPO, "tests", "fixtures", "avatars");

const TYPES = {
  ".html": "text/html; charset=utf-8",
  ".js": "text/javascript; charset=utf-8",
  ".mjs": "text/javascript; charset=utf-8",
  ".cjs": "text/javascript; charset=utf-8",
  ".css": "text/css; charset=utf-8",
  ".json": "application/json; charset=utf-8",
  ".map": "application/json; charset=utf-8",
  ".md": "text/markdown; charset=utf-8",
  ".ts": "text/plain; charset=utf-8",
  ".wasm": "application/wasm",
  ".vrm": "model/gltf-binary",
  ".glb": "model/gltf-binary",
  ".png": "image/png",
  ".svg": "image/svg+xml",
  ".ico": "image/x-icon",
  ".task": "application/octet-stream",
  ".tflite": "application/octet-stream",
};

/** The directory served at /handrig/: the first candidate holding a built package. */
export function findPackageDir(env = process.env) {
  const candidates = [env.HANDRIG_PKG, join(REPO, "pkg")];
  for (const dir of candidates) {
    if (dir && existsSync(join(dir, "package.json")) && existsSync(join(dir, "index.js"))) return resolve(dir);
  }
  return null;
}

/** Maps a URL path to a file inside `root`, or null when it would leave `root`. */
function inside(root, urlPath) {
  const rel = normalize(decodeURIComponent(urlPath)).replace(/^([/\\])+/, "");
  const full = resolve(root, rel);
  if (full !== root && !full.startsWith(root + sep)) return null;
  return full;
}

function send(res, status, text) {
  res.writeHead(status, { "Content-Type": "text/plain; charset=utf-8" });
  res.end(text);
}

/**
 * Starts the server. Resolves to { server, port, url, packageDir }.
 * `port` 0 picks a free port; any other port that is taken falls back to a free one.
 */
export function startServer({ port = 8080, host = "127.0.0.1", packageDir } = {}) {
  const pkgDir = packageDir === undefined ? findPackageDir() : packageDir;
  const handler = (req, res) => {
    let url;
    try {
      url = new URL(req.url, "http://localhost");
    } catch {
      return send(res, 400, "bad request");
    }
    if (req.method !== "GET" && req.method !== "HEAD") return send(res, 405, "method not allowed");
    let path = url.pathname;
    let file;
    try {
      if (path === "/handrig" || path.startsWith("/handrig/")) {
        if (!pkgDir) {
          return send(res, 404, "handrig package not built: run `make demo` (or see www/README.md)");
        }
        file = inside(pkgDir, path.slice("/handrig".length));
      } else if (path.startsWith("/avatars/")) {
        // The generated human avatars, served from where they are committed (no copy in www/).
        file = inside(AVATARS, path.slice("/avatars".length));
        if (file === AVATARS) return send(res, 404, "not found");
      } else {
        if (path.endsWith("/")) path += "index.html";
        file = inside(WWW, path);
      }
    } catch {
      return send(res, 400, "bad path");
    }
    if (!file) return send(res, 403, "forbidden");
    let st;
    try {
      st = statSync(file);
    } catch {
      return send(res, 404, "not found");
    }
    if (st.isDirectory()) {
      res.writeHead(301, { Location: url.pathname.replace(/\/?$/, "/") });
      return res.end();
    }
    res.writeHead(200, {
      "Content-Type": TYPES[extname(file).toLowerCase()] || "application/octet-stream",
      "Content-Length": st.size,
      "Cache-Control": "no-store",
      "Cross-Origin-Opener-Policy": "same-origin",
      "Cross-Origin-Embedder-Policy": "credentialless",
      "Cross-Origin-Resource-Policy": "same-origin",
    });
    if (req.method === "HEAD") return res.end();
    createReadStream(file).pipe(res);
  };

  const listen = (p) =>
    new Promise((ok, fail) => {
      const server = createServer(handler);
      server.once("error", fail);
      server.listen(p, host, () => ok(server));
    });

  return listen(port)
    .catch((err) => {
      if (err.code !== "EADDRINUSE" || port === 0) throw err;
      console.error(`port ${port} is in use; using a free port instead`);
      return listen(0);
    })
    .then((server) => {
      const actual = server.address().port;
      return { server, port: actual, url: `http://${host}:${actual}/`, packageDir: pkgDir };
    });
}

if (process.argv[1] && resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const raw = process.env.PORT;
  const port = raw === undefined || raw === "" ? 8080 : Number(raw);
  if (!Number.isInteger(port) || port < 0 || port > 65535) {
    console.error(`PORT must be an integer 0..65535, got "${raw}"`);
    process.exit(2);
  }
  const { url, packageDir } = await startServer({ port });
  if (!packageDir) {
    console.error("warning: no built handrig package in pkg/ (or $HANDRIG_PKG): run `make demo` or `node pkg-config/build.mjs`");
  } else {
    console.log(`handrig package: ${packageDir}`);
  }
  console.log(`handrig demo: ${url}`);
}
