// The skin at rest from a three.js scene's skinned meshes, for `restPose.skin`: shared by
// `restPoseFromVRM` (handrig/three-vrm) and `restPoseFromSkeleton` (handrig/three), the same
// reading `HandRig.fromVrm` / `fromGltf` do in Rust from the file (src/humanoid/gltf_skin.rs). Imports
// nothing at run time (inlined into each adapter by build.mjs).

/** Added to a vertex's bone index when its dominant joint is a non-humanoid bone under it. */
const HANGING = 0x80;

/** `restPose.skin`: positions 3 per vertex, each vertex's bone index, triangles. */
export interface SkinArrays {
  positions: Float32Array;
  bones: Uint8Array;
  triangles: Uint32Array;
}

/** A scene to traverse (three's `Object3D.traverse`). */
export interface SceneLike {
  traverse(callback: (object: unknown) => void): void;
}

/** The parts of a three `SkinnedMesh` the adapters read. */
interface SkinnedMeshLike {
  isSkinnedMesh: true;
  bindMatrix: { elements: ArrayLike<number> };
  skeleton: { bones: ArrayLike<{ parent?: unknown }>; boneInverses?: ArrayLike<{ elements: ArrayLike<number> }> };
  geometry: {
    index: { array: ArrayLike<number> } | null;
    attributes: {
      position: { count: number; getX(i: number): number; getY(i: number): number; getZ(i: number): number };
      skinIndex?: { itemSize: number; getComponent(i: number, k: number): number };
      skinWeight?: { itemSize: number; getComponent(i: number, k: number): number };
    };
  };
}

/**
 * The skin at rest: every skinned mesh's vertices in bind pose (the model's frame, as the
 * normalized rest pose), each with its dominant humanoid bone (the nearest humanoid ancestor of
 * the bone with the largest weight; vertices with none are left out), and the triangles.
 *
 * `jointMatrix` (optional): a bone's current transform (column-major 4x4) in the frame wanted.
 * Given, each vertex is skinned as glTF and three do, `sum_k w_k jointMatrix(bone_k)
 * boneInverse_k bindMatrix v` (weights normalized), which is right for a scene at rest whether
 * or not it is its bind pose (a model turned inside, bones rolled); without it, the vertex is
 * `bindMatrix v`, the mesh as it was bound (what three-vrm's rest pose needs, whatever the
 * current pose).
 */
export function skinOfScene(
  scene: SceneLike | undefined,
  boneOfNode: Map<unknown, number>,
  jointMatrix?: (bone: unknown) => ArrayLike<number>,
): SkinArrays | undefined {
  if (!scene || typeof scene.traverse !== "function") return undefined;
  // The nearest humanoid ancestor's index, the bone itself included, plus HANGING when it is an
  // ancestor (the vertex hangs on a non-humanoid bone under it: hair, cloth), as Rust reads it.
  const humanoidIndex = (node: unknown): number => {
    for (let n = node as { parent?: unknown } | undefined, depth = 0; n && depth < 256; n = n.parent as typeof n, depth++) {
      const i = boneOfNode.get(n);
      if (i !== undefined) return depth > 0 ? i | HANGING : i;
    }
    return -1;
  };
  const meshes: SkinnedMeshLike[] = [];
  scene.traverse((o) => {
    const m = o as Partial<SkinnedMeshLike>;
    if (m.isSkinnedMesh && m.geometry?.attributes?.skinIndex && m.geometry.attributes.skinWeight && m.skeleton) {
      meshes.push(m as SkinnedMeshLike);
    }
  });
  let total = 0;
  for (const m of meshes) total += m.geometry.attributes.position.count;
  if (total === 0) return undefined;
  const positions = new Float32Array(3 * total);
  const bones = new Uint8Array(total);
  const keep = new Int32Array(total);
  const triangles: number[] = [];
  let kept = 0;
  let offset = 0;
  // A mesh over the vertices of the last one read (the primitives of one glTF mesh sharing
  // their accessors: three's GLTFLoader makes one attribute per accessor) has that mesh's
  // vertices, counted once, as `HandRig.fromVrm` does.
  let previous: { m: SkinnedMeshLike; offset: number } | undefined;
  const sameVertices = (m: SkinnedMeshLike, o: SkinnedMeshLike): boolean => {
    const [a, b] = [m.geometry.attributes, o.geometry.attributes];
    if (a.position !== b.position || a.skinIndex !== b.skinIndex || a.skinWeight !== b.skinWeight) return false;
    const same = (x: ArrayLike<unknown> | undefined, y: ArrayLike<unknown> | undefined) =>
      x === y || (!!x && !!y && x.length === y.length && Array.prototype.every.call(x, (v, i) => v === y[i]));
    const [ib, ob] = [m.skeleton.boneInverses, o.skeleton.boneInverses];
    return (
      same(m.bindMatrix.elements, o.bindMatrix.elements) &&
      same(m.skeleton.bones, o.skeleton.bones) &&
      (ib === ob || (!!ib && !!ob && ib.length === ob.length && Array.prototype.every.call(ib, (x: { elements: ArrayLike<number> }, i) => same(x.elements, ob[i]!.elements))))
    );
  };
  for (const m of meshes) {
    const a = m.geometry.attributes;
    const earlier = previous && sameVertices(m, previous.m) ? previous : undefined;
    const index = m.geometry.index?.array;
    const count = index ? index.length : a.position.count;
    const base = earlier ? earlier.offset : offset;
    if (!earlier) {
      previous = { m, offset };
      readVertices(m);
      offset += a.position.count;
    }
    for (let t = 0; t + 2 < count; t += 3) {
      const v0 = keep[base + (index ? index[t]! : t)]!;
      const v1 = keep[base + (index ? index[t + 1]! : t + 1)]!;
      const v2 = keep[base + (index ? index[t + 2]! : t + 2)]!;
      if (v0 >= 0 && v1 >= 0 && v2 >= 0) triangles.push(v0, v1, v2);
    }
  }
  if (kept === 0) return undefined;
  return { positions: positions.slice(0, 3 * kept), bones: bones.slice(0, kept), triangles: Uint32Array.from(triangles) };

  // Appends mesh `m`'s vertices (from `offset` in `keep`).
  function readVertices(m: SkinnedMeshLike): void {
    const a = m.geometry.attributes;
    const si = a.skinIndex!;
    const sw = a.skinWeight!;
    const e = m.bindMatrix.elements;
    const boneIndex = Array.from(m.skeleton.bones, (b) => humanoidIndex(b));
    // Per bone: jointMatrix * boneInverse * bindMatrix (when skinning).
    const inverses = m.skeleton.boneInverses;
    const skinning =
      jointMatrix && inverses && inverses.length === m.skeleton.bones.length
        ? Array.from(m.skeleton.bones, (b, k) => mul(mul(jointMatrix(b), inverses[k]!.elements), e))
        : null;
    for (let i = 0; i < a.position.count; i++) {
      let best = -1;
      let bestWeight = -1;
      for (let k = 0; k < si.itemSize; k++) {
        const w = sw.getComponent(i, k);
        if (w > bestWeight) (bestWeight = w), (best = si.getComponent(i, k));
      }
      const bone = boneIndex[best] ?? -1;
      if (bone < 0) {
        keep[offset + i] = -1;
        continue;
      }
      const x = a.position.getX(i);
      const y = a.position.getY(i);
      const z = a.position.getZ(i);
      if (skinning) {
        let sum = 0;
        for (let k = 0; k < sw.itemSize; k++) sum += sw.getComponent(i, k);
        let px = 0;
        let py = 0;
        let pz = 0;
        for (let k = 0; k < sw.itemSize; k++) {
          // Weights normalized as three's GLTFLoader does (all zero: the first joint's).
          const w = sum > 0 ? sw.getComponent(i, k) / sum : k === 0 ? 1 : 0;
          const b = skinning[si.getComponent(i, k)];
          if (w === 0 || !b) continue;
          px += w * (b[0]! * x + b[4]! * y + b[8]! * z + b[12]!);
          py += w * (b[1]! * x + b[5]! * y + b[9]! * z + b[13]!);
          pz += w * (b[2]! * x + b[6]! * y + b[10]! * z + b[14]!);
        }
        positions[3 * kept] = px;
        positions[3 * kept + 1] = py;
        positions[3 * kept + 2] = pz;
      } else {
        // bindMatrix (column-major): the mesh's world transform when it was bound.
        positions[3 * kept] = e[0]! * x + e[4]! * y + e[8]! * z + e[12]!;
        positions[3 * kept + 1] = e[1]! * x + e[5]! * y + e[9]! * z + e[13]!;
        positions[3 * kept + 2] = e[2]! * x + e[6]! * y + e[10]! * z + e[14]!;
      }
      bones[kept] = bone;
      keep[offset + i] = kept++;
    }
  }
}

/** `a * b`, column-major 4x4 (also used by `handrig/three`). */
export function mul(a: ArrayLike<number>, b: ArrayLike<number>): number[] {
  const out = new Array<number>(16);
  for (let c = 0; c < 4; c++) {
    for (let r = 0; r < 4; r++) {
      let v = 0;
      for (let k = 0; k < 4; k++) v += a[4 * k + r]! * b[4 * c + k]!;
      out[4 * c + r] = v;
    }
  }
  return out;
}
