// Figures that are not human-shaped meshes (issue 52): a figure of primitives (boxes and spheres,
// its sphere head twice a human head) and a voxel-style figure (boxes on a grid, a large box
// head, no thumbs and no distal finger bones), on the skeleton of a generated human body in its
// T-pose, every vertex skinned rigidly (weight 1) to one bone.
//
// Each bone's box is the axis-aligned box of the human's T-posed vertices whose largest skin
// weight is that bone (in the T-pose the limbs, hands and fingers run along the axes, so the
// boxes fit them); the head is replaced by the figure's own head.

import { add, cross, normalize, scale, sub } from "./math.mjs";

/** The figures: id, the body whose skeleton they use, and what defines them. */
export const FIGURES = [
  {
    id: "primitive",
    from: "woman",
    title: "handrig figure of primitives (boxes and spheres, sphere head twice a human head; from MakeHuman CC0)",
    headScale: 2,
    grid: 0,
    dropBone: () => false,
  },
  {
    id: "voxel",
    from: "woman",
    title: "handrig voxel figure (boxes on a 2 cm grid, box head 1.5x, no thumbs, no distal finger bones; from MakeHuman CC0)",
    headScale: 1.5,
    grid: 0.02,
    // No thumb at all; the distal finger segments are part of the intermediate bones' boxes.
    dropBone: (name) => /^thumb_/.test(name) || /_03_[lr]$/.test(name),
  },
];

export const figureFileNames = () => FIGURES.map((f) => `${f.id}-vrm1.vrm`);

/** The bone a dropped bone's vertices go to (the distal segment to the intermediate), or -1 (thumbs: no geometry). */
function keptBone(skeleton, figure, bi) {
  const b = skeleton[bi];
  if (!figure.dropBone(b.name)) return bi;
  if (/^thumb_/.test(b.name)) return -1;
  return keptBone(skeleton, figure, b.parentIndex);
}

function boxFaces(min, max) {
  const out = [];
  for (let a = 0; a < 3; a++) {
    const u = (a + 1) % 3;
    const v = (a + 2) % 3;
    for (const s of [-1, 1]) {
      const n = [0, 0, 0];
      n[a] = s;
      const quad = [[0, 0], [1, 0], [1, 1], [0, 1]].map(([i, j]) => {
        const p = [0, 0, 0];
        p[a] = s > 0 ? max[a] : min[a];
        p[u] = i ? max[u] : min[u];
        p[v] = j ? max[v] : min[v];
        return p;
      });
      out.push({ quad, normal: n });
    }
  }
  return out;
}

/** Triangle list of a shape: { positions: [[x,y,z]], normals, triangles: [[i,j,k]] }, outward winding. */
function box(min, max) {
  const positions = [];
  const normals = [];
  const triangles = [];
  for (const { quad, normal } of boxFaces(min, max)) {
    const o = positions.length;
    positions.push(...quad);
    for (let k = 0; k < 4; k++) normals.push(normal);
    triangles.push([o, o + 1, o + 2], [o, o + 2, o + 3]);
  }
  return orient({ positions, normals, triangles }, scale(add(min, max), 0.5));
}

function sphere(center, radius, rings = 12, segments = 16) {
  const positions = [];
  const normals = [];
  const triangles = [];
  for (let i = 0; i <= rings; i++) {
    const t = (Math.PI * i) / rings;
    for (let j = 0; j <= segments; j++) {
      const f = (2 * Math.PI * j) / segments;
      const n = [Math.sin(t) * Math.sin(f), Math.cos(t), Math.sin(t) * Math.cos(f)];
      positions.push(add(center, scale(n, radius)));
      normals.push(n);
    }
  }
  const at = (i, j) => i * (segments + 1) + j;
  for (let i = 0; i < rings; i++) {
    for (let j = 0; j < segments; j++) {
      if (i > 0) triangles.push([at(i, j), at(i + 1, j), at(i, j + 1)]);
      if (i < rings - 1) triangles.push([at(i, j + 1), at(i + 1, j), at(i + 1, j + 1)]);
    }
  }
  return orient({ positions, normals, triangles }, center);
}

/** Turns every triangle to face away from `center` (both shapes are convex). */
function orient(shape, center) {
  shape.triangles = shape.triangles.map(([a, b, c]) => {
    const [pa, pb, pc] = [a, b, c].map((i) => shape.positions[i]);
    const n = cross(sub(pb, pa), sub(pc, pa));
    const mid = scale(add(add(pa, pb), pc), 1 / 3);
    const d = sub(mid, center);
    return n[0] * d[0] + n[1] * d[1] + n[2] * d[2] >= 0 ? [a, b, c] : [a, c, b];
  });
  return shape;
}

const snap = (x, grid) => (grid ? Math.round(x / grid) * grid : x);

/**
 * The figure's shapes in the posed (T-pose) frame and the moved eye bone heads:
 * { shapes: [{ bone, material, shape }], heads } (heads: posed.heads with the eyes moved onto
 * the figure's head).
 */
export function figureShapes(figure, src, prep, posed) {
  const { skeleton, weights, byName } = prep;
  const boxes = new Map();
  src.kept.forEach((v, i) => {
    const top = weights[v][0];
    if (!top) return;
    const bi = keptBone(skeleton, figure, top[0]);
    if (bi < 0) return;
    const p = posed.positions[i];
    const b = boxes.get(bi) ?? { min: [Infinity, Infinity, Infinity], max: [-Infinity, -Infinity, -Infinity] };
    for (let k = 0; k < 3; k++) (b.min[k] = Math.min(b.min[k], p[k])), (b.max[k] = Math.max(b.max[k], p[k]));
    boxes.set(bi, b);
  });
  const head = byName.head.index;
  const eyes = [byName.eye_l.index, byName.eye_r.index];
  const hb = boxes.get(head);
  const shapes = [];
  const heads = posed.heads.slice();
  // The human head scaled about the middle of its lowest point (the chin line).
  const s = figure.headScale;
  const base = [(hb.min[0] + hb.max[0]) / 2, hb.min[1], (hb.min[2] + hb.max[2]) / 2];
  const size = sub(hb.max, hb.min);
  let eyeAt;
  if (figure.grid === 0) {
    // Sphere: diameter s times the human head's height (chin to crown).
    const radius = (s * size[1]) / 2;
    const center = add(base, [0, radius, 0]);
    shapes.push({ bone: head, material: 0, shape: sphere(center, radius, 16, 24) });
    eyeAt = (side) => add(center, scale(normalize([side * 0.35, 0.1, 1]), radius));
    for (const [k, side] of [[0, 1], [1, -1]]) {
      heads[eyes[k]] = eyeAt(side);
      shapes.push({ bone: eyes[k], material: 1, shape: sphere(heads[eyes[k]], radius * 0.12, 8, 12) });
    }
  } else {
    const g = figure.grid;
    const min = [base[0] - (s * size[0]) / 2, base[1], base[2] - (s * size[2]) / 2].map((x) => snap(x, g));
    const max = [base[0] + (s * size[0]) / 2, base[1] + s * size[1], base[2] + (s * size[2]) / 2].map((x) => snap(x, g));
    shapes.push({ bone: head, material: 0, shape: box(min, max) });
    const eyeY = snap(min[1] + 0.55 * (max[1] - min[1]), g);
    for (const [k, side] of [[0, 1], [1, -1]]) {
      const cx = snap(base[0] + side * 0.22 * (max[0] - min[0]), g);
      heads[eyes[k]] = [cx, eyeY, max[2]];
      shapes.push({ bone: eyes[k], material: 1, shape: box([cx - g, eyeY - g, max[2] - g / 2], [cx + g, eyeY + g, max[2] + g / 2]) });
    }
  }
  for (const [bi, b] of [...boxes].sort((x, y) => x[0] - y[0])) {
    if (bi === head || eyes.includes(bi)) continue;
    let { min, max } = b;
    if (figure.grid) {
      min = min.map((x) => snap(x, figure.grid));
      max = max.map((x, k) => Math.max(snap(x, figure.grid), min[k] + figure.grid));
    }
    shapes.push({ bone: bi, material: 0, shape: box(min, max) });
    // The primitive figure's shoulders are balls (radius: half the upper arm's thickness).
    if (figure.grid === 0 && /^upperarm_/.test(skeleton[bi].name)) {
      shapes.push({ bone: bi, material: 0, shape: sphere(posed.heads[bi], (max[1] - min[1]) / 2) });
    }
  }
  return { shapes, heads };
}

/** Mesh arrays (gltf.mjs's writeGlb) of the shapes, every vertex weighted 1 to its bone's joint. */
export function figureMesh(shapes, frame, jointOfBone) {
  const positions = [];
  const normals = [];
  const joints = [];
  const tri = [[], []];
  for (const { bone, material, shape } of shapes) {
    const j = jointOfBone.get(bone);
    if (j === undefined) throw new Error(`figure: bone ${bone} is not a joint`);
    const o = positions.length / 3;
    for (let i = 0; i < shape.positions.length; i++) {
      positions.push(...frame(shape.positions[i]));
      normals.push(...frame(shape.normals[i]));
      joints.push(j, 0, 0, 0);
    }
    for (const t of shape.triangles) tri[material].push(o + t[0], o + t[1], o + t[2]);
  }
  const n = positions.length / 3;
  const weights = new Float32Array(4 * n);
  for (let i = 0; i < n; i++) weights[4 * i] = 1;
  return {
    positions: Float32Array.from(positions),
    normals: Float32Array.from(normals),
    joints: Uint8Array.from(joints),
    weights,
    primitives: tri.map((list, material) => ({ indices: Uint16Array.from(list), material })),
  };
}
