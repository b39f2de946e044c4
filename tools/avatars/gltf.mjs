// A minimal glTF 2.0 binary (GLB) writer for one skinned mesh: float positions and normals,
// u8 or u16 joints, float weights, u16 indices per primitive, float inverse bind matrices.
// Output bytes depend only on the input: JSON keys in a fixed order, no timestamps.

const FLOAT = 5126;
const UNSIGNED_BYTE = 5121;
const UNSIGNED_SHORT = 5123;
const ARRAY_BUFFER = 34962;
const ELEMENT_ARRAY_BUFFER = 34963;

class BinWriter {
  constructor() {
    this.chunks = [];
    this.length = 0;
    this.views = [];
  }

  /** Appends a typed array as its own bufferView (4-byte aligned); returns its index. */
  view(typed, target) {
    const bytes = new Uint8Array(typed.buffer, typed.byteOffset, typed.byteLength);
    const offset = this.length;
    this.chunks.push(bytes);
    this.length += bytes.length;
    const pad = (4 - (this.length % 4)) % 4;
    if (pad) {
      this.chunks.push(new Uint8Array(pad));
      this.length += pad;
    }
    const v = { buffer: 0, byteOffset: offset, byteLength: bytes.length };
    if (target) v.target = target;
    this.views.push(v);
    return this.views.length - 1;
  }

  bytes() {
    const out = new Uint8Array(this.length);
    let o = 0;
    for (const c of this.chunks) {
      out.set(c, o);
      o += c.length;
    }
    return out;
  }
}

function minMax(values, n) {
  const min = new Array(n).fill(Infinity);
  const max = new Array(n).fill(-Infinity);
  for (let i = 0; i < values.length; i += n) {
    for (let k = 0; k < n; k++) {
      min[k] = Math.min(min[k], values[i + k]);
      max[k] = Math.max(max[k], values[i + k]);
    }
  }
  return { min, max };
}

/**
 * Writes a GLB.
 * @param {object} o
 * @param {object[]} o.nodes glTF nodes (name, translation, rotation, scale, children, mesh, skin)
 * @param {number[]} o.sceneNodes root node indices
 * @param {{ positions: Float32Array, normals: Float32Array, joints: Uint8Array|Uint16Array,
 *           weights: Float32Array, primitives: { indices: Uint16Array, material: number }[] }} o.mesh
 * @param {{ joints: number[], inverseBindMatrices: Float32Array, skeleton: number }} o.skin
 * @param {object[]} o.materials
 * @param {string} o.meshName
 * @param {object} [o.extensions] top-level extensions (VRM); `extensionsUsed` from its keys
 */
export function writeGlb({ nodes, sceneNodes, mesh, skin, materials, meshName, extensions, generator }) {
  const bin = new BinWriter();
  const accessors = [];
  const accessor = (view, componentType, count, type, extra = {}) => {
    accessors.push(view === undefined ? { componentType, count, type, ...extra } : { bufferView: view, componentType, count, type, ...extra });
    return accessors.length - 1;
  };
  const vertexCount = mesh.positions.length / 3;
  const position = accessor(bin.view(mesh.positions, ARRAY_BUFFER), FLOAT, vertexCount, "VEC3", minMax(mesh.positions, 3));
  const normal = accessor(bin.view(mesh.normals, ARRAY_BUFFER), FLOAT, vertexCount, "VEC3");
  const jointType = mesh.joints instanceof Uint8Array ? UNSIGNED_BYTE : UNSIGNED_SHORT;
  const joints = accessor(bin.view(mesh.joints, ARRAY_BUFFER), jointType, vertexCount, "VEC4");
  const weights = accessor(bin.view(mesh.weights, ARRAY_BUFFER), FLOAT, vertexCount, "VEC4");
  const attributes = { POSITION: position, NORMAL: normal, JOINTS_0: joints, WEIGHTS_0: weights };
  if (mesh.colors) {
    attributes.COLOR_0 = accessor(bin.view(mesh.colors, ARRAY_BUFFER), UNSIGNED_BYTE, vertexCount, "VEC4", { normalized: true });
  }
  // Morph targets: sparse POSITION deltas (zeros but at `indices`), shared by every primitive.
  const targets = (mesh.targets ?? []).map((t) => {
    const { min, max } = minMax(t.deltas, 3);
    for (let k = 0; k < 3; k++) {
      min[k] = Math.min(min[k], 0);
      max[k] = Math.max(max[k], 0);
    }
    const sparse = {
      count: t.indices.length,
      indices: { bufferView: bin.view(t.indices), componentType: UNSIGNED_SHORT },
      values: { bufferView: bin.view(t.deltas) },
    };
    const out = { POSITION: accessor(undefined, FLOAT, vertexCount, "VEC3", { min, max, sparse }) };
    // NORMAL deltas likewise when given (every target then has them: an accessor without data
    // is all zeros).
    if (t.normalIndices) {
      out.NORMAL = t.normalIndices.length
        ? accessor(undefined, FLOAT, vertexCount, "VEC3", {
            sparse: {
              count: t.normalIndices.length,
              indices: { bufferView: bin.view(t.normalIndices), componentType: UNSIGNED_SHORT },
              values: { bufferView: bin.view(t.normalDeltas) },
            },
          })
        : accessor(undefined, FLOAT, vertexCount, "VEC3");
    }
    return out;
  });
  const primitives = mesh.primitives.map((p) => ({
    attributes,
    ...(targets.length ? { targets } : {}),
    indices: accessor(bin.view(p.indices, ELEMENT_ARRAY_BUFFER), UNSIGNED_SHORT, p.indices.length, "SCALAR"),
    material: p.material,
    mode: 4,
  }));
  const ibm = accessor(bin.view(skin.inverseBindMatrices), FLOAT, skin.joints.length, "MAT4");
  const binBytes = bin.bytes();

  const json = {
    asset: { version: "2.0", generator },
    ...(extensions ? { extensionsUsed: Object.keys(extensions) } : {}),
    scene: 0,
    scenes: [{ name: "Scene", nodes: sceneNodes }],
    nodes,
    meshes: [{ name: meshName, primitives, ...(targets.length ? { weights: targets.map(() => 0), extras: { targetNames: mesh.targets.map((t) => t.name) } } : {}) }],
    skins: [{ name: "Armature", joints: skin.joints, inverseBindMatrices: ibm, skeleton: skin.skeleton }],
    materials,
    accessors,
    bufferViews: bin.views,
    buffers: [{ byteLength: binBytes.length }],
    ...(extensions ? { extensions } : {}),
  };
  return packGlb(json, binBytes);
}

/** GLB container: JSON chunk padded with spaces, BIN chunk with zeros (4-byte alignment). */
export function packGlb(json, binBytes) {
  let text = Buffer.from(JSON.stringify(json), "utf8");
  text = Buffer.concat([text, Buffer.alloc((4 - (text.length % 4)) % 4, 0x20)]);
  const binPadded = Buffer.concat([Buffer.from(binBytes), Buffer.alloc((4 - (binBytes.length % 4)) % 4, 0)]);
  const head = Buffer.alloc(12);
  head.write("glTF", 0, "ascii");
  head.writeUInt32LE(2, 4);
  head.writeUInt32LE(12 + 8 + text.length + 8 + binPadded.length, 8);
  const jsonHead = Buffer.alloc(8);
  jsonHead.writeUInt32LE(text.length, 0);
  jsonHead.write("JSON", 4, "ascii");
  const binHead = Buffer.alloc(8);
  binHead.writeUInt32LE(binPadded.length, 0);
  binHead.write("BIN\0", 4, "ascii");
  return Buffer.concat([head, jsonHead, text, binHead, binPadded]);
}

/** The JSON chunk of a GLB (for tests and tools). */
export function readGlbJson(buf) {
  const len = buf.readUInt32LE(12);
  return JSON.parse(buf.subarray(20, 20 + len).toString("utf8"));
}
