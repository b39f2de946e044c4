// The `handrig` command (the package's bin, docs/guide/export.md): `handrig export` on every shared
// recording in the recording format at once (worker threads), the files it writes read back
// (a recording with a face: expressions and look-at in the .vrma);
// a bad file, a missing avatar and an unknown option each give one line and a non-zero exit, a
// bad file without stopping the others.

import assert from "node:assert/strict";
import { spawnSync } from "node:child_process";
import fs from "node:fs";
import { createRequire } from "node:module";
import os from "node:os";
import path from "node:path";
import { after, describe, it } from "node:test";

import { HandRig, MotionRecorder } from "handrig";
import { BVHLoader } from "three/examples/jsm/loaders/BVHLoader.js";

import { CHILD_TIMEOUT_MS, avatarFiles, readBytes, repo, shared } from "./support.mjs";

const require = createRequire(import.meta.url);
const pkgDir = path.dirname(require.resolve("handrig/package.json"));
const manifest = JSON.parse(fs.readFileSync(path.join(pkgDir, "package.json"), "utf8"));
const cli = path.join(pkgDir, manifest.bin.handrig);

const avatar = avatarFiles(".vrm").find((f) => f.endsWith("woman-vrm1.vrm"));
const asl = path.join(shared, "data", "asl");
const handsFile = path.join(shared, "data", "hands", "right-hand-video-mediapipe.json");
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), "handrig-cli-"));
after(() => fs.rmSync(tmp, { recursive: true, force: true }));

function handrig(...args) {
  const r = spawnSync(process.execPath, [cli, ...args], { encoding: "utf8", cwd: tmp, timeout: CHILD_TIMEOUT_MS });
  return { status: r.status, stdout: r.stdout, stderr: r.stderr };
}

/** The lines of stderr that are not progress lines. */
const errors = (stderr) => stderr.split("\n").filter((l) => l && !l.startsWith("["));

describe("handrig export (the package's bin)", () => {
  it("is the package's bin, linked by npm", () => {
    assert.ok(fs.existsSync(cli), cli);
    assert.match(fs.readFileSync(cli, "utf8"), /^#!\/usr\/bin\/env node\n/);
    if (process.env.HANDRIG_PACK) {
      assert.ok(fs.existsSync(path.join(process.cwd(), "node_modules", ".bin", "handrig")), "node_modules/.bin/handrig");
      assert.ok(JSON.parse(process.env.HANDRIG_PACK).files.some((f) => f.path === "cli.mjs"), "cli.mjs is packed");
    }
    const help = handrig("--help");
    assert.equal(help.status, 0);
    assert.match(help.stdout, /usage: handrig export/);
  });

  it("every shared recording at once, on worker threads: .vrma files identical to MotionRecorder's", () => {
    const out = path.join(tmp, "all");
    const r = handrig("export", asl, handsFile, "--avatar", avatar, "--out-dir", out, "--jobs", "2");
    assert.equal(r.status, 0, r.stderr);
    const names = [...fs.readdirSync(asl).filter((f) => f.endsWith(".json")), path.basename(handsFile)];
    const progress = r.stderr.split("\n").filter((l) => l.startsWith("["));
    assert.equal(progress.length, names.length, r.stderr);
    assert.deepEqual(errors(r.stderr), []);
    const summary = r.stdout.match(/(\d+) of (\d+) written: (\d+) frames, ([\d.]+) s of motion, (\d+) bytes, ([\d.]+) s wall time on 2 worker threads/);
    assert.ok(summary, r.stdout);
    assert.equal(Number(summary[1]), names.length);
    let frames = 0;
    let bytes = 0;
    for (const name of names) {
      const file = path.join(out, name.replace(/\.json$/, ".vrma"));
      assert.ok(fs.existsSync(file), file);
      bytes += fs.statSync(file).size;
      // The same bytes as MotionRecorder on the same frames (with the recording's image aspect).
      const rec = JSON.parse(fs.readFileSync(name === path.basename(handsFile) ? handsFile : path.join(asl, name), "utf8"));
      const list = Array.isArray(rec) ? rec : rec.frames;
      // The README quick start's mirroring, the command's default.
      const rig = HandRig.fromVrm(readBytes(avatar), { mirror: true });
      const recorder = new MotionRecorder(rig);
      for (const f of list) {
        recorder.add(f.timeMs, rig.solve({ ...f, imageAspect: rec.width ? rec.width / rec.height : undefined }));
      }
      rig.free();
      frames += recorder.frameCount;
      assert.ok(Buffer.from(recorder.toVRMA()).equals(fs.readFileSync(file)), `${name}: same bytes as MotionRecorder.toVRMA()`);
    }
    assert.equal(Number(summary[3]), frames);
    assert.equal(Number(summary[5]), bytes);
  });

  it("a recording whose frames carry a FaceLandmarkerResult: the .vrma has the expressions and the look-at, as MotionRecorder writes them", () => {
    // FaceLandmarker on the bench's renders of the woman saying "aa" (tests/fixtures/face):
    // blendshapes, matrices and the package's 20 landmarks, spread into each frame.
    const data = JSON.parse(fs.readFileSync(path.join(repo, "tests", "fixtures", "face", "bench-shots.json"), "utf8"));
    const toFrame = (f, t0) => {
      const landmarks = Array.from({ length: 478 }, () => ({ x: 0.5, y: 0.5, z: 0 }));
      data.meshIndices.forEach((k, i) => (landmarks[k] = { x: f.mesh[i][0], y: f.mesh[i][1], z: f.mesh[i][2] }));
      return {
        timeMs: t0 + f.timeMs,
        faceLandmarks: [landmarks],
        faceBlendshapes: [{ categories: f.blendshapes.map((score, index) => ({ index, score, categoryName: data.names[index], displayName: "" })) }],
        facialTransformationMatrixes: [{ rows: 4, columns: 4, data: f.matrix }],
      };
    };
    const t0 = data.still.length * (1000 / 30);
    const frames = [...data.still.map((f) => toFrame(f, 0)), ...data.shots.find((x) => x.name === "aa").frames.map((f) => toFrame(f, t0))];
    const file = path.join(tmp, "face-aa.json");
    fs.writeFileSync(file, JSON.stringify({ width: 640, height: 480, frames }));
    const out = path.join(tmp, "face-aa.vrma");
    const r = handrig("export", file, "--avatar", avatar, "--out", out, "--quiet");
    assert.equal(r.status, 0, r.stderr);
    const bytes = fs.readFileSync(out);
    const json = JSON.parse(bytes.subarray(20, 20 + bytes.readUInt32LE(12)).toString("utf8"));
    const ext = json.extensions.VRMC_vrm_animation;
    assert.ok(ext.expressions?.preset?.aa && ext.lookAt, JSON.stringify(Object.keys(ext)));
    const rig = HandRig.fromVrm(readBytes(avatar), { mirror: true });
    const recorder = new MotionRecorder(rig);
    let aa = 0;
    for (const f of frames) {
      const res = rig.solve({ ...f, imageAspect: 640 / 480 });
      aa = Math.max(aa, res.expressions.aa);
      recorder.add(f.timeMs, res);
    }
    rig.free();
    assert.ok(aa >= 0.3, `aa reaches ${aa}`);
    assert.ok(Buffer.from(recorder.toVRMA()).equals(bytes), "same bytes as MotionRecorder.toVRMA()");
  });

  it("--out file.bvh: BVH text three's BVHLoader reads; --tolerance makes a smaller .vrma", () => {
    const bvh = path.join(tmp, "eat.bvh");
    const r = handrig("export", path.join(asl, "eat.json"), "--avatar", avatar, "--out", bvh, "--quiet");
    assert.equal(r.status, 0, r.stderr);
    assert.equal(r.stderr, "");
    const { clip } = new BVHLoader().parse(fs.readFileSync(bvh, "utf8"));
    assert.equal(clip.tracks.find((t) => t.name === "hips.position").times.length, 47);
    const full = path.join(tmp, "eat.vrma");
    const small = path.join(tmp, "eat-small.vrma");
    assert.equal(handrig("export", path.join(asl, "eat.json"), "--avatar", avatar, "--out", full).status, 0);
    assert.equal(handrig("export", path.join(asl, "eat.json"), "--avatar", avatar, "--out", small, "--tolerance", "0.5").status, 0);
    assert.ok(fs.statSync(small).size < fs.statSync(full).size, `${fs.statSync(small).size} < ${fs.statSync(full).size}`);
  });

  it("a bad file and a missing recording: one line each naming the file (and frame), exit 1, the others written", () => {
    const bad = path.join(tmp, "bad");
    fs.mkdirSync(bad);
    // A frame with a 20-point hand in a real recording; a file that is not JSON.
    const rec = JSON.parse(fs.readFileSync(path.join(asl, "thanks.json"), "utf8"));
    rec.frames[7].hands[0].worldLandmarks.pop();
    fs.writeFileSync(path.join(bad, "broken.json"), JSON.stringify(rec));
    fs.writeFileSync(path.join(bad, "garbage.json"), "{ not json");
    fs.copyFileSync(path.join(asl, "eat.json"), path.join(bad, "eat.json"));
    const out = path.join(tmp, "bad-out");
    const r = handrig("export", bad, path.join(tmp, "missing.json"), "--avatar", avatar, "--out-dir", out);
    assert.equal(r.status, 1, r.stderr);
    const lines = errors(r.stderr);
    assert.equal(lines.length, 3, r.stderr);
    assert.ok(lines.some((l) => /broken\.json: frames\[7\]: frame\.hands\[0\]\.worldLandmarks: .*21/.test(l)), lines.join("\n"));
    assert.ok(lines.some((l) => /garbage\.json: not JSON/.test(l)), lines.join("\n"));
    assert.ok(lines.some((l) => /missing\.json: no such file/.test(l)), lines.join("\n"));
    assert.deepEqual(fs.readdirSync(out), ["eat.vrma"]);
    assert.match(r.stdout, /1 of 4 written: .*; 3 failed/);
  });

  it("a .glb avatar through HandRig.fromGltf, mirrored like the app by default; --no-mirror, --input-mirrored", () => {
    const glb = avatarFiles(".glb").find((f) => f.endsWith("man-mixamo.glb"));
    const rec = JSON.parse(fs.readFileSync(handsFile, "utf8"));
    const list = Array.isArray(rec) ? rec : rec.frames;
    /** MotionRecorder's .vrma of the hands recording on the .glb with `options`. */
    const expected = (options) => {
      const rig = HandRig.fromGltf(readBytes(glb), options);
      const recorder = new MotionRecorder(rig);
      for (const f of list) recorder.add(f.timeMs, rig.solve({ ...f, imageAspect: rec.width ? rec.width / rec.height : undefined }));
      rig.free();
      return Buffer.from(recorder.toVRMA());
    };
    const exported = (...flags) => {
      const out = path.join(tmp, `glb${flags.join("")}.vrma`);
      const r = handrig("export", handsFile, "--avatar", glb, "--out", out, "--quiet", ...flags);
      assert.equal(r.status, 0, r.stderr);
      return fs.readFileSync(out);
    };
    const app = expected({ mirror: true });
    assert.ok(exported().equals(app), "the default: the quick start's mirror: true");
    assert.ok(exported("--mirror").equals(app));
    assert.ok(!app.equals(expected({ mirror: false })), "mirroring changes the motion");
    assert.ok(exported("--no-mirror").equals(expected({ mirror: false })));
    assert.ok(exported("--input-mirrored").equals(expected({ mirror: true, inputMirrored: true })));
    assert.ok(exported("--options", '{"mirror":false}').equals(expected({ mirror: false })), "--options' mirror is kept");
    const help = handrig("--help").stdout;
    assert.match(help, /--mirror +the avatar mirrors the user \(options\.mirror: true\), as in the README's quick start: the default/);
    assert.match(help, /--input-mirrored/);
    assert.match(help, /\.glb/);
  });

  it("a missing avatar, an unknown option, a bad --options: one line, exit 2, nothing written", () => {
    const out = path.join(tmp, "none");
    const cases = [
      [["--avatar", path.join(tmp, "nobody.vrm")], /^handrig: --avatar .*nobody\.vrm: no such file$/],
      [["--avatar", path.join(asl, "eat.json")], /^handrig: --avatar .*eat\.json: vrm: /],
      [["--avatar", avatar, "--avatr", "x"], /^handrig: Unknown option '--avatr' \(handrig --help lists the options\)$/],
      [["--avatar", avatar, "--options", '{"torsoo":"pose"}'], /^handrig: --options: .*torsoo/],
      [["--avatar", avatar, "--options", "{torso"], /^handrig: --options: not JSON/],
      [["--avatar", avatar, "--format", "fbx"], /^handrig: --format: must be vrma or bvh/],
      [["--avatar", avatar, "--mirror", "--no-mirror"], /^handrig: --mirror and --no-mirror: give one$/],
      [["--avatar", avatar, "--no-mirror", "--options", '{"mirror":true}'], /^handrig: --no-mirror: --options sets mirror: true; give it in one place$/],
      [["--avatar", path.join(tmp, "nobody.glb")], /^handrig: --avatar .*nobody\.glb: no such file$/],
    ];
    for (const [args, pattern] of cases) {
      const r = handrig("export", asl, "--out-dir", out, ...args);
      assert.equal(r.status, 2, `${args.join(" ")}: ${r.stderr}`);
      const lines = r.stderr.trim().split("\n");
      assert.equal(lines.length, 1, r.stderr);
      assert.match(lines[0], pattern);
      assert.equal(r.stdout, "");
    }
    assert.ok(!fs.existsSync(out));
  });
});
