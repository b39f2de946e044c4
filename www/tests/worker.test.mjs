// handrig in a Web Worker (issue 10): the rig solves in a module worker, results come back as
// transferred Float32Arrays in the flat layout, and they equal the main thread's solve.

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { launch } from "./helpers.mjs";

let env;
let page;
const errors = [];

before(async () => {
  env = await launch();
  page = await env.context.newPage();
  page.on("pageerror", (e) => errors.push(e.message));
  page.on("console", (m) => m.type() === "error" && errors.push(m.text()));
  await page.goto(env.url + "worker.html");
  await page.waitForFunction(() => window.__handrigWorker?.solved >= 60 || window.__handrigWorker?.errors.length, null, {
    timeout: 60_000,
  });
});

after(async () => {
  await env?.close();
});

test("a module worker solves 60 frames and transfers the flat output back", async () => {
  const state = await page.evaluate(() => window.__handrigWorker);
  assert.deepEqual(state.errors, []);
  assert.equal(state.solved, 60);
  assert.ok(state.bones.includes("rightIndexDistal"));
  // The worker's output equals the main thread's for the same frames.
  const same = await page.evaluate(async (outputs) => {
    const { default: init, HandRig, LAYOUT } = await import("handrig");
    await init();
    const vrm = new Uint8Array(await (await fetch("./assets/debug-robot.vrm")).arrayBuffer());
    const frames = await (await fetch("./assets/right-hand-video-mediapipe.json")).json();
    const rig = HandRig.fromVrm(vrm);
    let worst = 0;
    outputs.forEach((o, i) => {
      rig.solve(frames[i]);
      const mine = rig.output;
      for (let k = 0; k < LAYOUT.output.length; k++) {
        const a = mine[k];
        const b = o.output[k];
        if (Number.isNaN(a) && Number.isNaN(b)) continue;
        worst = Math.max(worst, Math.abs(a - b));
      }
    });
    const i = LAYOUT.bones.indexOf("rightIndexProximal");
    const flag = outputs[2].output[LAYOUT.output.boneFlags + i];
    return { worst, flag };
  }, state.outputs);
  assert.equal(same.worst, 0, "worker and main thread give the same output");
  assert.equal(same.flag, 1, "the right index finger was solved in the worker");
  const us = [...state.us].sort((a, b) => a - b);
  console.log(`# worker: ${state.solved} frames, median solve ${us[us.length >> 1].toFixed(0)} µs in the worker`);
  assert.deepEqual(errors, []);
});

test("one page driving 100 rigs reports rigs solved per millisecond", async () => {
  const p = await env.context.newPage();
  await p.goto(env.url + "many.html");
  await p.waitForFunction(() => window.__handrigMany, null, { timeout: 120_000 });
  const m = await p.evaluate(() => window.__handrigMany);
  assert.equal(m.rigs, 100);
  assert.equal(m.solved, 3 * 100 * 200);
  assert.ok(m.perMs > 5, `${m.perMs} rigs per ms`);
  console.log(`# 100 rigs in the page: ${m.perMs.toFixed(1)} rigs solved per millisecond`);
  await p.close();
});
