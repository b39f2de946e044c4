// Shared browser-test helpers: the static server on a free port and headless Debian Chromium
// through playwright-core (no browser download: executablePath is the system chromium).

import { mkdtempSync, mkdirSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import { dirname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import { chromium } from "playwright-core";
import { startServer } from "../serve.mjs";

export const WWW = resolve(dirname(fileURLToPath(import.meta.url)), "..");
export const REPO = resolve(WWW, "..");
export const SHARED = process.env.HANDRIG_SHARED ?? resolve(REPO, "..", "shared");
export const SCREENSHOTS = join(REPO, "artifacts", "screenshots");
mkdirSync(SCREENSHOTS, { recursive: true });

export const CHROMIUM = process.env.CHROMIUM ?? "/usr/bin/chromium";

/** Starts the server on a free port and a fresh headless Chromium profile. */
export async function launch() {
  const srv = await startServer({ port: 0 });
  const profile = mkdtempSync(join(tmpdir(), "handrig-chromium-"));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: CHROMIUM,
    headless: true,
    viewport: { width: 1280, height: 800 },
    args: [
      "--headless",
      "--no-sandbox",
      "--disable-gpu",
      "--disable-quic",
      "--no-first-run",
      "--disable-background-networking",
      "--disable-component-update",
      "--disable-sync",
      // WebGL without a GPU: ANGLE on SwiftShader.
      "--use-angle=swiftshader",
      "--enable-unsafe-swiftshader",
    ],
  });
  return {
    url: srv.url,
    context,
    async close() {
      await context.close().catch(() => {});
      await new Promise((r) => srv.server.close(r));
      rmSync(profile, { recursive: true, force: true });
    },
  };
}

/**
 * Opens the demo, collecting console errors and page errors. Waits until the page reports
 * ready (or failed). `query` is appended to the URL (e.g. "?paused").
 */
export async function openDemo(env, query = "?paused") {
  const page = await env.context.newPage();
  const errors = [];
  page.on("console", (m) => {
    if (m.type() === "error") errors.push(`console.error: ${m.text()}`);
  });
  page.on("pageerror", (e) => errors.push(`pageerror: ${e.message}`));
  page.on("requestfailed", (r) => errors.push(`request failed: ${r.url()} ${r.failure()?.errorText}`));
  page.on("response", (r) => {
    if (r.status() >= 400) errors.push(`HTTP ${r.status()}: ${r.url()}`);
  });
  await page.goto(env.url + query);
  await page.waitForFunction(() => window.__handrigDemo && window.__handrigDemo.state !== "loading", null, {
    timeout: 60_000,
  });
  return { page, errors };
}

export const shot = (name) => join(SCREENSHOTS, name);
