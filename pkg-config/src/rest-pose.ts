// What `new HandRig()` and `HandRig.fromVrm()` read besides the options: a rest pose (bone name
// -> rest world position, checked and packed into the flat array the raw constructor takes) or a
// .vrm file's bytes.

import { describe, fail, isObject, readUser, reading, tag } from "./errors.js";
import { BONE_COUNT, BONE_INDEX } from "./layout.js";
import { readVec3 } from "./points.js";

/** A rest pose as the raw constructor takes it: per bone [present, x, y, z], and the VRM version. */
export interface FlatRestPose {
  rest: Float64Array;
  version: number;
  /** `restPose.lookAtOffset`, when given. */
  lookAt?: Float32Array;
  /** `restPose.skin` as typed arrays (checked further in Rust). */
  skin?: { positions: Float32Array; bones: Uint8Array; triangles: Uint32Array };
}

export function restPoseToFlat(restPose: unknown): FlatRestPose {
  return readUser("restPose", () => readRestPose(restPose));
}

function readRestPose(restPose: unknown): FlatRestPose {
  if (!isObject(restPose) || Array.isArray(restPose)) {
    fail("restPose", 'must be an object { bones: { [boneName]: [x, y, z] }, vrmVersion?: "0" | "1" }');
  }
  const v = restPose.vrmVersion;
  let version = 1;
  if (v !== undefined && v !== null) {
    if (v === "0" || v === 0) version = 0;
    else if (v !== "1" && v !== 1) fail("restPose.vrmVersion", `must be "0" or "1", got ${describe(v)}`);
  }
  reading.part = "restPose.bones";
  const bones = restPose.bones;
  if (!isObject(bones) || Array.isArray(bones)) {
    fail("restPose.bones", "must be an object { [boneName]: [x, y, z] }");
  }
  const rest = new Float64Array(4 * BONE_COUNT);
  for (const name of Object.keys(bones)) {
    const i = BONE_INDEX.get(name);
    if (i === undefined) {
      fail("restPose.bones", `unknown bone name ${JSON.stringify(name)} (expected a VRM 1.0 humanoid bone name such as "leftHand")`);
    }
    rest[4 * i] = 1;
    reading.part = `restPose.bones.${name}`;
    readVec3(bones[name], reading.part, rest, 4 * i + 1);
  }
  let lookAt: Float32Array | undefined;
  if (restPose.lookAtOffset !== undefined && restPose.lookAtOffset !== null) {
    reading.part = "restPose.lookAtOffset";
    lookAt = new Float32Array(3);
    readVec3(restPose.lookAtOffset, "restPose.lookAtOffset", lookAt, 0);
  }
  const skin = restPose.skin;
  if (skin === undefined || skin === null) return lookAt ? { rest, version, lookAt } : { rest, version };
  reading.part = "restPose.skin";
  if (!isObject(skin) || Array.isArray(skin)) {
    fail("restPose.skin", "must be an object { positions, bones, triangles } (see restPoseFromVRM)");
  }
  return {
    rest,
    version,
    ...(lookAt ? { lookAt } : {}),
    skin: {
      positions: typedArray(skin.positions, "restPose.skin.positions", Float32Array),
      bones: typedArray(skin.bones, "restPose.skin.bones", Uint8Array),
      triangles: typedArray(skin.triangles ?? [], "restPose.skin.triangles", Uint32Array),
    },
  };
}

/** A number list as the typed array the raw constructor takes (copied only when needed). */
function typedArray<T extends Float32Array | Uint8Array | Uint32Array>(
  v: unknown,
  field: string,
  Type: { new (n: number | ArrayLike<number>): T; name: string },
): T {
  if (v instanceof Type) return v;
  if (Array.isArray(v) || ArrayBuffer.isView(v)) {
    const list = v as ArrayLike<unknown>;
    for (let i = 0; i < list.length; i++) {
      if (typeof list[i] !== "number" || !Number.isFinite(list[i])) fail(field, `entry ${i} is not a finite number (got ${describe(list[i])})`);
    }
    return new Type(list as ArrayLike<number>);
  }
  return fail(field, `must be a ${Type.name} or an array of numbers, got ${describe(v)}`);
}

/** Accepts what file/fetch/fs APIs hand out; checks by tag so other realms' buffers work. */
export function vrmBytes(bytes: unknown): Uint8Array {
  if (bytes instanceof Uint8Array) return bytes;
  const t = tag(bytes);
  if (t === "ArrayBuffer" || t === "SharedArrayBuffer") return new Uint8Array(bytes as ArrayBuffer);
  if (ArrayBuffer.isView(bytes)) return new Uint8Array(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  throw new TypeError(
    "bytes: must be the .vrm file's contents as a Uint8Array, ArrayBuffer, Buffer or typed array" +
      (bytes === undefined ? " (got undefined)" : ` (got ${t})`),
  );
}
