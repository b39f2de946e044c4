// Paths and names shared by the bench scripts (issue 47).

import { dirname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";

export const HERE = dirname(fileURLToPath(import.meta.url));
export const REPO = resolve(HERE, "..", "..");
/** The committed clips, their recordings and frame hashes. */
export const CLIP_DIR = join(HERE, "clips");
/** The rendered avatars: tests/fixtures/avatars/NAME-vrm1.vrm. */
export const AVATARS = ["woman", "child"];
/** The leg clips' avatars (issue 51): tuned on the woman, reported on the others. */
export const LEG_AVATARS = ["woman", "man", "child", "primitive"];
/** The contact clips' avatars (issue 52): the angles were found on the woman (tune); man and child report. */
export const CONTACT_AVATARS = ["woman", "man", "child"];
/** An avatar's file under tests/fixtures/avatars: NAME-vrm1.vrm, the stylized figures in figures/. */
export const avatarPath = (a) => (["primitive", "voxel"].includes(a) ? `figures/${a}-vrm1.vrm` : `${a}-vrm1.vrm`);
export const avatarFile = (a) => join(REPO, "tests", "fixtures", "avatars", avatarPath(a));
export const videoFile = (avatar, clip) => join(CLIP_DIR, `${avatar}-${clip.id}.mp4`);
/** MediaPipe mode per clip: holistic (pose + hands) for body clips, hands (world landmarks) for hand clips. */
export const modeOf = (clip) => (clip.kind === "hand" ? "hands" : clip.kind === "legs" ? "tasks" : "holistic");
export const recordingFile = (avatar, clip, tracker = "legacy") =>
  join(CLIP_DIR, `${avatar}-${clip.id}-${tracker === "tasks" ? "tasks" : modeOf(clip)}.json`);
