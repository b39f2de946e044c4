// Issue 49: hostile input to the package's JS surfaces, seeded and counted.
//
// - MotionRecorder.add with hostile results (NaN and infinite rotations and hips, missing bones,
//   wrong shapes, getters that throw) and times (going back, repeating, NaN, huge), with toVRMA
//   and toBVH now and then on what was let through: every add succeeds or throws an Error naming
//   the field (`timeMs`, `result.bones.leftHand[2]`) and leaves the recording as it was; every
//   .vrma written passes the Khronos glTF validator with no errors; every BVH's frame count
//   matches its frames and holds no NaN or Infinity.
// - serveRig (the worker side of handrig/worker) with messages of every wrong shape: one reply
//   per message, an error naming what is wrong, never a throw or a rejected promise, only
//   ArrayBuffers transferred; the rig keeps solving. The page side ignores messages that are not
//   the worker's replies.
// - The CLI (`handrig export`) on batches of unreadable, empty, huge, malformed and good
//   recordings, and bad flags: an error line naming each failed file, an output for each good
//   one, no partial or temporary file left, exit status 1 (some failed) or 2 (bad command line).
//
// Cases: HANDRIG_NODE_FUZZ_CASES per surface (default 3,000; `make fuzz`: 100,000), and
// HANDRIG_NODE_FUZZ_CLI_FILES recordings through the CLI (default 200; `make fuzz`: 100,000); seed
// HANDRIG_FUZZ_SEED. A time limit per case (2 s; each CLI run 120 s).

import assert from "node:assert/strict";
import { spawnSync } from "node:child_process";
import fs from "node:fs";
import { createRequire } from "node:module";
import os from "node:os";
import path from "node:path";
import { after, describe, it } from "node:test";
import validator from "gltf-validator";
import * as handrig from "handrig";
import { createRigWorker, serveRig } from "handrig/worker";
import { avatars, readBytes, readRecording } from "./support.mjs";

const { HandRig, MotionRecorder, LAYOUT } = handrig;
const CASES = Number(process.env.HANDRIG_NODE_FUZZ_CASES ?? 3000);
// The CLI's cases are recordings, a few thousand to one run of the command.
const CLI_FILES = Number(process.env.HANDRIG_NODE_FUZZ_CLI_FILES ?? 200);
const SEED = Number(process.env.HANDRIG_FUZZ_SEED ?? 20261206);
const CASE_MS = 2000;
const robot = readBytes(avatars.robot);
const frames = readRecording();

/** xorshift32, seeded. */
function rng(seed) {
  let s = seed >>> 0 || 1;
  const next = () => {
    s ^= s << 13;
    s >>>= 0;
    s ^= s >>> 17;
    s ^= s << 5;
    s >>>= 0;
    return s / 4294967296;
  };
  return {
    next,
    below: (n) => Math.floor(next() * n),
    pick: (xs) => xs[Math.floor(next() * xs.length)],
  };
}

const tmp = fs.mkdtempSync(path.join(os.tmpdir(), "handrig-fuzz-"));
after(() => fs.rmSync(tmp, { recursive: true, force: true }));

/** Asserts `e` is an Error whose message starts with one of `fields`. */
function namesField(e, fields, what) {
  assert.ok(e instanceof Error, `${what}: threw ${String(e)}, not an Error`);
  assert.ok(
    fields.some((f) => e.message.startsWith(f)),
    `${what}: the error does not name the field: ${e.message}`,
  );
}

describe("fuzz: MotionRecorder.add, toVRMA and toBVH (issue 49)", () => {
  it(`${CASES} hostile adds; every .vrma let through passes the glTF validator`, async () => {
    const r = rng(SEED);
    const rig = HandRig.fromVrm(robot);
    const driven = rig.drivenBones();
    const good = frames.slice(0, 80).map((f, i) => structuredClone(rig.solve({ ...f, timeMs: i * 33 }, {})));
    let rec = new MotionRecorder(rig);
    let last = 0;
    const VALUES = [NaN, Infinity, -Infinity, 1e300, -1e300, 1e39, 0, -0, 1e-320, "1", null, undefined, {}];
    // (8.64e15 itself, the largest time taken, is in the regressions below: here it would leave
    // most recordings too long for a BVH.)
    const TIMES = [NaN, Infinity, -Infinity, 1e308, -1e308, 8.64e15 + 1, -8.64e15, "33", null, undefined, 1e-300];
    let accepted = 0;
    let rejected = 0;
    let vrmas = 0;
    let bvhs = 0;
    let bvhTried = 0;
    let validated = 0;
    // 60 files in a short run, 1,000 in a long one.
    const validateEvery = Math.max(1, Math.floor(CASES / (CASES > 10000 ? 1000 : 60)));
    for (let c = 0; c < CASES; c++) {
      const t0 = performance.now();
      if (r.below(400) === 0) {
        rec = new MotionRecorder(rig);
        last = 0;
      }
      // The time.
      let time;
      switch (r.below(8)) {
        case 0:
          time = r.pick(TIMES);
          break;
        case 1:
          time = last; // repeats: replaces the last frame
          break;
        case 2:
          time = last - 1 - r.below(100); // back
          break;
        case 3:
          // A jump of 1e12 ms (then no BVH fits a string) rarely, so most BVHs are written.
          time = last + (r.below(400) === 0 ? 1e12 : r.pick([1e-9, 1e-3, 1e4]));
          break;
        default:
          time = last + 33.3;
      }
      // The result: a good one, damaged.
      const result = structuredClone(r.pick(good));
      const bone = r.pick(driven);
      switch (r.below(10)) {
        case 0:
          result.bones[bone][r.below(4)] = r.pick(VALUES);
          break;
        case 1:
          delete result.bones[bone];
          break;
        case 2:
          result.bones[bone] = r.pick([null, "q", [0, 0, 1], [0, 0, 0, 0], new Float64Array(4), new Float32Array([1e30, 1e30, 0, 1]), { length: 4 }]);
          break;
        case 3:
          result.worldPositions.hips = r.pick([[NaN, 0, 0], [1e39, 0, 0], [0, 1e10, 0], [1, 2], null, undefined, "hips"]);
          break;
        case 4:
          Object.defineProperty(result.bones, bone, {
            get() {
              throw new Error("getter");
            },
          });
          break;
        case 5:
          result.bones = r.pick([null, 7, "bones", []]);
          break;
        default:
          break;
      }
      const before = rec.frameCount;
      let threw;
      try {
        rec.add(time, r.below(200) === 0 ? r.pick([null, undefined, 5, "x"]) : result);
      } catch (e) {
        threw = e;
      }
      if (threw) {
        rejected++;
        if (!(threw instanceof Error && threw.message === "getter")) {
          namesField(threw, ["timeMs", "result"], `add(${String(time)})`);
        }
        assert.equal(rec.frameCount, before, "a rejected frame changed the recording");
      } else {
        accepted++;
        assert.ok(rec.frameCount === before || rec.frameCount === before + 1);
        last = time;
      }
      // Now and then, the files.
      if (rec.frameCount > 0 && (c % validateEvery === 0 || c === CASES - 1)) {
        const tolerance = r.pick([undefined, 0, 0.01, 1]);
        const bytes = rec.toVRMA({ tolerance });
        vrmas++;
        const report = await validator.validateBytes(bytes, { maxIssues: 10 });
        validated++;
        assert.equal(report.issues.numErrors, 0, `case ${c}: ${JSON.stringify(report.issues.messages.slice(0, 5))}`);
        let bvh;
        bvhTried++;
        try {
          // At most 120 fps: at 1,000 fps a recording with a few 10 s gaps is a 200 MB text,
          // which takes seconds to write (bounded, but longer than a case may take).
          bvh = rec.toBVH(r.pick([undefined, { fps: 30 }, { fps: 120, unit: "m" }]));
        } catch (e) {
          namesField(e, ["toBVH"], "toBVH");
          assert.match(e.message, /more BVH text than a string holds/);
        }
        if (bvh !== undefined) {
          bvhs++;
          assert.doesNotMatch(bvh, /NaN|Infinity|e\+/);
          const n = Number(/Frames: (\d+)/.exec(bvh)[1]);
          assert.equal(bvh.split("Frame Time:")[1].trim().split("\n").length - 1, n);
        }
      }
      const ms = performance.now() - t0;
      assert.ok(ms < CASE_MS * 5, `case ${c} took ${ms.toFixed(0)} ms`);
    }
    rig.free();
    console.log(`# MotionRecorder fuzz (seed ${SEED}): ${CASES} adds (${accepted} accepted, ${rejected} rejected), ${vrmas} .vrma (${validated} validated), ${bvhs} BVH (${bvhTried - bvhs} refused as too long)`);
    assert.ok(accepted > CASES / 10 && rejected > CASES / 10, "both outcomes are exercised");
  });

  it("regressions: times beyond a Date's range, hips beyond 1e9 m, a BVH of too many frames", async () => {
    const rig = HandRig.fromVrm(robot);
    const result = rig.solve(frames[100], {});
    const rec = new MotionRecorder(rig);
    // Before: a span of 1e308 ms gave infinite key times in the .vrma (the validator's errors).
    assert.throws(() => rec.add(1e308, result), /^RangeError: timeMs: must be within/);
    // Before: hips at 1e39 m became Infinity in the file.
    const far = structuredClone(result);
    far.worldPositions.hips = [1e39, 0, 0];
    assert.throws(() => rec.add(0, far), /^RangeError: result\.worldPositions\.hips\[0\]: must be within/);
    assert.equal(rec.frameCount, 0);
    // Before: hips: null threw "Cannot read properties of null (reading '0')"; now null is
    // absent, as undefined (the rest position is recorded).
    const noHips = structuredClone(result);
    noHips.worldPositions.hips = null;
    rec.add(0, noHips);
    assert.equal(rec.frameCount, 1);
    rec.clear();
    // The largest times taken: a valid .vrma (key times distinct in float32).
    rec.add(-8.64e15, result);
    rec.add(8.64e15 - 1, result);
    rec.add(8.64e15, result);
    const extreme = await validator.validateBytes(rec.toVRMA(), { maxIssues: 10 });
    assert.equal(extreme.issues.numErrors, 0, JSON.stringify(extreme.issues.messages.slice(0, 5)));
    rec.clear();
    // Before: 1e12 ms at the median frame time of 33 ms was 3e10 BVH frames (a hang, then out of memory).
    rec.add(0, result);
    rec.add(33, result);
    rec.add(66, result);
    rec.add(1e12, result);
    const t = performance.now();
    assert.throws(() => rec.toBVH(), /^RangeError: toBVH: \d+ frames .* more BVH text than a string holds/);
    assert.ok(performance.now() - t < 1000);
    rig.free();
  });
});

describe("fuzz: worker messages of every wrong shape (issue 49)", () => {
  it(`${CASES} messages to serveRig: one reply each, errors naming what is wrong, the rig keeps solving`, async () => {
    const r = rng(SEED + 1);
    const replies = [];
    const scope = {
      onmessage: null,
      postMessage(m, transfer) {
        for (const t of transfer) assert.ok(t instanceof ArrayBuffer && t.byteLength > 0, "only live ArrayBuffers are transferred");
        replies.push(m);
      },
    };
    serveRig(handrig, scope);
    const send = async (data) => {
      const n = replies.length;
      await scope.onmessage(data === "no event" ? undefined : { data });
      assert.equal(replies.length, n + 1, `one reply to ${String(data?.type ?? data)}`);
      return replies[n];
    };
    const ready = await send({ type: "init", avatar: robot.slice().buffer });
    assert.equal(ready.type, "ready");
    const buffer = () => new ArrayBuffer(4 * LAYOUT.output.length);
    const solveOk = async () => {
      const m = await send({ type: "solve", frame: frames[100], output: buffer() });
      assert.equal(m.type, "solved", m.message);
    };
    await solveOk();
    const junk = [undefined, null, 0, 7, "solve", [], {}, () => 1, new ArrayBuffer(8), Symbol.iterator.description];
    let errors = 0;
    for (let c = 0; c < CASES; c++) {
      const t0 = performance.now();
      let msg;
      switch (r.below(9)) {
        case 0:
          msg = r.pick(junk);
          break;
        case 1:
          msg = { type: r.pick(["Solve", "init ", "ready", 1, null, undefined, "error"]) };
          break;
        case 2:
          msg = { type: "solve", frame: frames[r.below(frames.length)], output: r.pick([undefined, null, 1, new ArrayBuffer(0), new ArrayBuffer(12), new Float32Array(LAYOUT.output.length), "buf"]) };
          break;
        case 3:
          msg = { type: "solve", frame: r.pick([undefined, null, 5, "frame", [], {}, { timeMs: NaN }, { hands: 3 }, { timeMs: 0, hands: [{ landmarks: [1, 2] }] }]), output: buffer() };
          break;
        case 4:
          // An init with a bad avatar or bad options: fatal for that init, the old rig stays.
          msg = {
            type: "init",
            avatar: r.pick([undefined, null, "robot.vrm", new ArrayBuffer(0), robot.slice(0, r.below(robot.length)).buffer, robot.slice().buffer]),
            options: r.pick([undefined, { mirror: "yes" }, { nope: 1 }, 5, { torso: undefined }]),
            wasm: r.pick([undefined, undefined, 5]),
          };
          break;
        case 5:
          msg = "no event";
          break;
        default:
          msg = { type: "solve", frame: frames[r.below(frames.length)], output: buffer() };
      }
      const reply = await send(msg);
      if (reply.type === "error") {
        errors++;
        assert.equal(typeof reply.message, "string");
        assert.ok(reply.message.length > 10, reply.message);
        assert.doesNotMatch(reply.message, /undefined is not|Cannot read prop|is not a function|Reflect\.get/, reply.message);
      } else {
        assert.ok(reply.type === "solved" || reply.type === "ready", JSON.stringify(reply));
      }
      if (c % 50 === 0) await solveOk();
      assert.ok(performance.now() - t0 < CASE_MS, `case ${c}`);
    }
    await solveOk();
    console.log(`# worker fuzz (seed ${SEED}): ${CASES} messages, ${errors} answered with an error`);
    assert.ok(errors > CASES / 4);
  });

  it("a second init frees the first rig: 400 inits, wasm memory flat", async () => {
    const scope = { onmessage: null, postMessage() {} };
    serveRig(handrig, scope);
    const wasmBytes = () => {
      const probe = HandRig.fromVrm(robot);
      const n = probe.input.buffer.byteLength;
      probe.free();
      return n;
    };
    for (let i = 0; i < 5; i++) await scope.onmessage({ data: { type: "init", avatar: robot.slice() } });
    const before = wasmBytes();
    for (let i = 0; i < 400; i++) await scope.onmessage({ data: { type: "init", avatar: robot.slice() } });
    const grew = wasmBytes() - before;
    assert.ok(grew <= 1 << 20, `wasm memory grew ${grew} bytes over 400 inits`);
  });

  it("the page side ignores messages that are not the worker's replies", async () => {
    const sent = [];
    const worker = {
      onmessage: null,
      onerror: null,
      postMessage(m) {
        sent.push({ ...m }); // the page side reuses its message object
      },
      terminate() {},
    };
    const started = createRigWorker(worker, { avatar: robot.slice() });
    worker.onmessage({ data: { type: "ready", bones: ["hips"], length: LAYOUT.output.length } });
    const rig = await started;
    for (const data of [undefined, null, 5, "solved", {}, { type: "nope" }, { type: "ready" }]) {
      assert.doesNotThrow(() => worker.onmessage({ data }));
      assert.doesNotThrow(() => worker.onmessage(data));
    }
    assert.equal(rig.stats.solved, 0);
    assert.equal(rig.stats.failed, 0);
    // An error reply whose output is not an ArrayBuffer: counted, and the next frame still goes
    // out with a real buffer (before: the value was taken as a free buffer and posted).
    rig.solve(frames[0]);
    assert.ok(sent.at(-1).output instanceof ArrayBuffer);
    worker.onmessage({ data: { type: "error", message: "frame: bad", output: 5, fatal: false } });
    assert.equal(rig.stats.failed, 1);
    rig.solve(frames[1]);
    assert.ok(sent.at(-1).output instanceof ArrayBuffer, `posted ${String(sent.at(-1).output)}`);
    await assert.rejects(createRigWorker(worker, undefined), /^TypeError: options: must be an object/);
    await assert.rejects(createRigWorker(worker, { avatar: "x.vrm" }), /^TypeError: options\.avatar: must be the bytes/);
  });
});

describe("fuzz: the CLI on hostile files and flags (issue 49)", () => {
  const require = createRequire(import.meta.url);
  const pkgDir = path.dirname(require.resolve("handrig/package.json"));
  const cli = path.join(pkgDir, JSON.parse(fs.readFileSync(path.join(pkgDir, "package.json"), "utf8")).bin.handrig);
  const avatar = path.join(tmp, "robot.vrm");
  fs.writeFileSync(avatar, robot);
  const run = (args) => {
    const res = spawnSync(process.execPath, [cli, ...args], { encoding: "utf8", cwd: tmp, timeout: 120_000 });
    assert.equal(res.error, undefined, `handrig ${args.join(" ")}: ${res.error}`);
    return res;
  };

  it("bad flags: exit 2, a message naming the flag, nothing written", () => {
    const rec = path.join(tmp, "one.json");
    fs.writeFileSync(rec, JSON.stringify(frames.slice(0, 3)));
    const out = path.join(tmp, "flags-out");
    const cases = [
      [["export", rec, "--avatar", avatar, "--out-dir", out, "--jobs", "0"], /--jobs/],
      [["export", rec, "--avatar", avatar, "--out-dir", out, "--jobs", "x"], /--jobs/],
      [["export", rec, "--avatar", avatar, "--out-dir", out, "--fps", "-1"], /--fps/],
      [["export", rec, "--avatar", avatar, "--out-dir", out, "--fps", "1e400"], /--fps/],
      [["export", rec, "--avatar", avatar, "--out-dir", out, "--tolerance", "NaN"], /--tolerance/],
      [["export", rec, "--avatar", avatar, "--out-dir", out, "--unit", "mm"], /--unit/],
      [["export", rec, "--avatar", avatar, "--out-dir", out, "--format", "fbx"], /--format/],
      [["export", rec, "--avatar", avatar, "--out-dir", out, "--options", "{"], /--options/],
      [["export", rec, "--avatar", avatar, "--out-dir", out, "--options", '{"mirror":"yes"}'], /--options.*mirror/],
      [["export", rec, "--avatar", avatar, "--out-dir", out, "--options", "[1]"], /--options/],
      [["export", rec, "--avatar", avatar, "--out", path.join(out, "x.txt")], /--out/],
      [["export", rec, "--avatar", avatar], /--out/],
      [["export", rec, "--avatar", path.join(tmp, "none.vrm"), "--out-dir", out], /--avatar.*no such file/],
      [["export", rec, "--avatar", tmp, "--out-dir", out], /--avatar.*directory/],
      [["export", rec, "--avatar", rec, "--out-dir", out], /--avatar/],
      [["export", rec, "--avatr", avatar], /Unknown option '--avatr'/],
      [["exprot", rec], /unknown command/],
      [[], /no command/],
    ];
    for (const [args, re] of cases) {
      const res = run(args);
      assert.equal(res.status, 2, `handrig ${args.join(" ")}: ${res.stderr}`);
      assert.match(res.stderr, re, args.join(" "));
      assert.equal(fs.existsSync(out), false, `handrig ${args.join(" ")} wrote ${out}`);
    }
    // A FIFO as the avatar: refused at once (reading it would wait forever).
    const fifo = path.join(tmp, "avatar.fifo");
    spawnSync("mkfifo", [fifo]);
    const res = run(["export", rec, "--avatar", fifo, "--out-dir", out]);
    assert.equal(res.status, 2);
    assert.match(res.stderr, /--avatar .*avatar\.fifo: not a regular file/);
  });

  it(`batches of hostile recordings (${CLI_FILES} files): each fails alone with a message naming it, or is written whole`, () => {
    const r = rng(SEED + 2);
    const total = CLI_FILES;
    const perBatch = 2000;
    let written = 0;
    let failed = 0;
    for (let start = 0, batch = 0; start < total; start += perBatch, batch++) {
      const dir = path.join(tmp, `in${batch}`);
      const out = path.join(tmp, `out${batch}`);
      fs.mkdirSync(dir);
      const expectOk = new Map();
      const files = [];
      for (let i = start; i < Math.min(total, start + perBatch); i++) {
        const file = path.join(dir, `r${i}.json`);
        const good = frames.slice(r.below(frames.length - 10), undefined).slice(0, 1 + r.below(8));
        let ok = false;
        switch (r.below(12)) {
          case 0:
            fs.writeFileSync(file, "");
            break;
          case 1:
            fs.writeFileSync(file, JSON.stringify(good).slice(0, 1 + r.below(200)));
            break;
          case 2:
            fs.writeFileSync(file, r.pick(["null", "[]", "{}", '{"frames": 3}', "7", '"x"', '{"frames": []}', "[null]", "[[1]]"]));
            break;
          case 3:
            fs.writeFileSync(file, Buffer.from(Array.from({ length: 1 + r.below(300) }, () => r.below(256))));
            break;
          case 4: {
            const bad = structuredClone(good);
            const f = r.pick(bad);
            if (f.hands?.[0]) f.hands[0].worldLandmarks[r.below(21)] = r.pick([{ x: NaN }, null, [1, 2], "p"]);
            else f.timeMs = "t";
            fs.writeFileSync(file, JSON.stringify(bad).replace(/null/g, r.pick(["null", "NaN"])));
            break;
          }
          case 5: {
            const back = good.map((f, k) => ({ ...f, timeMs: 1000 - 10 * k }));
            fs.writeFileSync(file, JSON.stringify(back));
            ok = back.length === 1;
            break;
          }
          case 6:
            if (batch === 0 && i < start + 3) {
              // Huge: a sparse file larger than one string can be.
              fs.writeFileSync(file, "[");
              fs.truncateSync(file, 2 ** 30);
            } else fs.writeFileSync(file, " ".repeat(1 + r.below(1000)));
            break;
          case 7:
            // A FIFO (reading it would wait forever) or a file that cannot be read.
            if (i % 3 === 0) spawnSync("mkfifo", [file]);
            else fs.symlinkSync(path.join(dir, "nowhere"), file);
            break;
          default:
            fs.writeFileSync(file, JSON.stringify(r.below(2) ? good : { width: 640, height: 480, frames: good }));
            ok = true;
        }
        expectOk.set(`r${i}`, ok);
        files.push(file);
      }
      const res = run(["export", ...files, "--avatar", avatar, "--out-dir", out, "--jobs", String(1 + (batch % 2)), "--quiet"]);
      assert.ok(res.status === 0 || res.status === 1, `exit ${res.status}: ${res.stderr.slice(0, 500)}`);
      const errLines = res.stderr.split("\n").filter((l) => l.startsWith("handrig: "));
      const outs = fs.existsSync(out) ? fs.readdirSync(out) : [];
      assert.deepEqual(
        outs.filter((f) => !f.endsWith(".vrma")),
        [],
        "no temporary or partial file is left",
      );
      for (const [name, ok] of expectOk) {
        const written_ = outs.includes(`${name}.vrma`);
        const named = errLines.filter((l) => l.includes(`${name}.json`));
        if (ok) {
          assert.ok(written_, `${name}: good, not written: ${named.join(" | ")}`);
          const bytes = fs.readFileSync(path.join(out, `${name}.vrma`));
          assert.equal(bytes.readUInt32LE(8), bytes.length, `${name}.vrma is whole`);
          written++;
        } else {
          assert.ok(written_ !== (named.length === 1), `${name}: written ${written_}, ${named.length} error lines`);
          if (!written_) {
            assert.match(named[0], new RegExp(`${name}\\.json: \\S`), named[0]);
            failed++;
          } else written++;
        }
      }
      fs.rmSync(dir, { recursive: true, force: true });
      fs.rmSync(out, { recursive: true, force: true });
    }
    console.log(`# CLI fuzz (seed ${SEED}): ${total} recordings, ${written} written, ${failed} failed with an error naming the file`);
    assert.ok(written > 0 && failed > 0);
  });

  it("a recording larger than one string is refused before it is read", () => {
    const huge = path.join(tmp, "huge.json");
    fs.writeFileSync(huge, "[");
    fs.truncateSync(huge, 2 ** 30); // sparse: no disk used
    const t = performance.now();
    const res = run(["export", huge, "--avatar", avatar, "--out-dir", path.join(tmp, "huge-out"), "--quiet"]);
    assert.equal(res.status, 1);
    assert.match(res.stderr, /huge\.json: too large \(1073741824 bytes/);
    assert.ok(performance.now() - t < 20_000);
    fs.rmSync(huge);
  });

  it("a failed write leaves no partial file and the older output as it was", () => {
    const rec = path.join(tmp, "atomic.json");
    fs.writeFileSync(rec, JSON.stringify(frames.slice(0, 20)));
    const out = path.join(tmp, "atomic-out");
    fs.mkdirSync(out);
    // The output's name is taken by a directory: the rename fails after the data was written.
    fs.mkdirSync(path.join(out, "atomic.vrma"));
    const res = run(["export", rec, "--avatar", avatar, "--out-dir", out, "--quiet"]);
    assert.equal(res.status, 1);
    assert.match(res.stderr, /atomic\.vrma: cannot write it/);
    assert.deepEqual(fs.readdirSync(out), ["atomic.vrma"], "no temporary file left");
    // A failed export (a bad frame) leaves an older output untouched.
    fs.rmSync(path.join(out, "atomic.vrma"), { recursive: true });
    fs.writeFileSync(path.join(out, "atomic.vrma"), "older");
    fs.writeFileSync(rec, JSON.stringify([...frames.slice(0, 5), { timeMs: "late" }]));
    const again = run(["export", rec, "--avatar", avatar, "--out-dir", out, "--quiet"]);
    assert.equal(again.status, 1);
    assert.equal(fs.readFileSync(path.join(out, "atomic.vrma"), "utf8"), "older");
  });
});
