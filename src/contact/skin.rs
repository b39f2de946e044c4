//! The avatar's skin as contact surfaces: what the rig learns from the skinned meshes of the
//! avatar (`HandRig.fromVrm` / `fromGltf` read them from the file, `restPoseFromVRM` passes
//! them from three-vrm's loaded meshes: [`SkinMesh`]).
//!
//! The meshes' rest positions are sorted into parts by each vertex's dominant humanoid bone
//! (head with eyes and jaw, neck, upper chest, chest, spine, hips; a shoulder's skin counts as
//! its parent's; the hands for their thickness; what hangs from the head on bones of its own,
//! such as long hair, only down to the neck's joint); a triangle belongs to the part of most of its
//! corners, and is sampled every [`SPACING`] so that large triangles leave no holes. From the
//! samples, at setup ([`BodySurface::new`]):
//!
//! * **Radial maps**, one per torso bone and one for the head, hung on that bone and placed
//!   every frame by forward kinematics: per height (1 cm rows) and direction around a vertical
//!   axis (48 sectors), the skin's largest distance from the axis (the torso bones: a
//!   cylindrical height map), and for the head per direction from the head's center (24 x 48
//!   bins: a spherical one). A point is inside the body where it is nearer the axis (center)
//!   than the skin in its direction; the depth is the difference, the outward direction the
//!   radial one (near a torso axis leaning forward, [`FORWARD_BIAS`]: a hand deep inside
//!   goes out the front). Body parts are close to star-shaped about these axes (a torso's cross
//!   section, a head), so the maps keep the skin to about a bin's size (1 cm; the largest
//!   radius in a bin: a concave spot such as under the nose counts as filled). Bins no sample
//!   falls in take their neighbours' mean.
//! * **Face anchors on the skin**: each derived anchor ([`super::face::AvatarFace::from_rig`]:
//!   the average face placed on the eye bones) is moved onto the head's skin along the face's
//!   forward axis (nose, chin, mouth, cheeks, forehead: the foremost skin point within 5 mm
//!   across) or sideways (the ears: the outermost within 6 mm).
//! * **The hands' thickness**: the finger radius (upper quartile of the distances of
//!   finger-bone skin from its bone) and the palm's half-thickness (upper quartile of the hand
//!   bone's skin's distances from the palm's plane), the margins of the hand's contact points.
//!
//! Nothing here runs per frame except [`BodySurface::depth`] (no allocation).

use glam::{Quat, Vec3};

use crate::humanoid::bones::{Finger, HumanBone, Side};

use crate::humanoid::skeleton::{Skeleton, WorldPose};
use crate::humanoid::SkinMesh;
use crate::math::angle::atan2_fast;
use crate::math::stats::nth_smallest;

/// Triangles are sampled at most this far apart (m).
pub const SPACING: f32 = 0.006;
/// Row height of the torso maps (m).
pub const ROW: f32 = 0.01;
/// Sectors around each map's axis.
pub const SECTORS: usize = 48;
/// Rows (polar angle bins) of the head's map.
pub const HEAD_ROWS: usize = 24;
/// Most rows of a torso map (a torso part over 1.2 m tall is clipped).
const MAX_ROWS: usize = 120;
/// Most samples per triangle side.
const MAX_SPLITS: usize = 16;

/// Which surface a sample belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Part {
    /// A torso or head map: index into [`MAP_BONES`].
    Map(usize),
    /// A hand (for its thickness).
    Hand(Side),
    /// Arms, legs, ...: not a contact surface.
    Other,
}

/// The bones carrying a map, the head's first.
pub const MAP_BONES: [HumanBone; 6] = [
    HumanBone::Head,
    HumanBone::Neck,
    HumanBone::UpperChest,
    HumanBone::Chest,
    HumanBone::Spine,
    HumanBone::Hips,
];

/// Index of the head's map in [`MAP_BONES`].
pub const HEAD_MAP: usize = 0;
/// Index of the neck's map in [`MAP_BONES`].
pub const NECK_MAP: usize = 1;

fn part_of(skeleton: &Skeleton, bone: HumanBone) -> Part {
    use HumanBone as B;
    let mut b = match bone {
        B::Jaw | B::LeftEye | B::RightEye => B::Head,
        B::LeftShoulder | B::RightShoulder => match skeleton.parent(bone) {
            Some(p) => p,
            None => return Part::Other,
        },
        b => b,
    };
    for side in Side::BOTH {
        if b == side.hand() || Finger::ALL.iter().any(|f| side.finger(*f).contains(&b)) {
            return Part::Hand(side);
        }
    }
    // A map bone the avatar lacks: its skin goes to the nearest present one above it.
    loop {
        if let Some(k) = MAP_BONES.iter().position(|m| *m == b) {
            if skeleton.has(b) {
                return Part::Map(k);
            }
            match MAP_BONES.get(k + 1) {
                Some(next) => b = *next,
                None => return Part::Other,
            }
        } else {
            return Part::Other;
        }
    }
}

/// How far a torso map's outward directions lean forward on its axis (m, internal frame: +Z
/// forward), the lean fading to nothing 3 x as far from the axis. Straight out from the axis
/// points every way near it: a hand deep in the belly (a tracked wrist inside a bigger
/// avatar) was pushed out sideways or backwards, and round the body as it moved a centimetre
/// (the Kinect session on the generated woman and child, `eval/rust/eval_turns.rs`: the arm
/// turned up to 63 and 152 degrees in a frame; 16-22 with the lean). Outward is then away
/// from a point 3-4 cm behind the axis near it, and radial from 12 cm out (at an adult torso's
/// skin, or anywhere on a map as odd as the odd-armature avatar's one wide cylinder).
pub const FORWARD_BIAS: f32 = 0.04;

/// How a map measures directions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapKind {
    /// Rows of height, sectors around the vertical axis (torso bones).
    Cylinder,
    /// Rows of polar angle from +Y, sectors around it (the head).
    Sphere,
}

/// One radial map (see the module docs), in its bone's rest frame (internal axes).
#[derive(Clone, Debug, PartialEq)]
pub struct RadialMap {
    /// The bone it hangs on.
    pub bone: HumanBone,
    /// Cylinder or sphere.
    pub kind: MapKind,
    /// The axis's point (cylinder: its x and z) or the sphere's center, rest world.
    pub center: Vec3,
    /// The lowest row's bottom (cylinder; m, rest world).
    pub bottom: f32,
    /// Rows.
    pub rows: usize,
    /// Largest skin radius per bin, `rows x SECTORS`.
    pub radius: Vec<f32>,
    /// The largest of `radius` (plus a rounding allowance): no point farther from the axis
    /// or center than this plus its margin can be inside, whatever its direction, so
    /// [`RadialMap::depth_above`] answers such points without the direction's trigonometry.
    widest: f32,
    /// The bone's rest position (world).
    rest: Vec3,
}

/// Sector of direction `(x, z)` around +Y, continuous (0 at -Z, increasing toward +X...).
#[inline]
fn sector(x: f32, z: f32) -> f32 {
    (atan2_fast(x, z) + core::f32::consts::PI) / core::f32::consts::TAU * SECTORS as f32
}

impl RadialMap {
    fn empty(bone: HumanBone, kind: MapKind, center: Vec3, bottom: f32, rows: usize) -> Self {
        RadialMap {
            bone,
            kind,
            center,
            bottom,
            rows,
            radius: vec![-1.0; rows * SECTORS],
            widest: 0.0,
            rest: Vec3::ZERO,
        }
    }

    /// Row coordinate (continuous) and radius of a rest-frame point.
    #[inline]
    fn coordinates(&self, q: Vec3) -> (f32, f32, f32) {
        let d = q - self.center;
        match self.kind {
            MapKind::Cylinder => {
                let r = (d.x * d.x + d.z * d.z).sqrt();
                ((q.y - self.bottom) / ROW, sector(d.x, d.z), r)
            }
            MapKind::Sphere => {
                let across = (d.x * d.x + d.z * d.z).sqrt();
                let r = (across * across + d.y * d.y).sqrt();
                // The polar angle from +Y (acos(d.y / r), without libm's acos).
                let polar = atan2_fast(across, d.y);
                (
                    polar / core::f32::consts::PI * HEAD_ROWS as f32,
                    sector(d.x, d.z),
                    r,
                )
            }
        }
    }

    fn add(&mut self, q: Vec3) {
        let (row, sec, r) = self.coordinates(q);
        if !(row.is_finite() && sec.is_finite() && r.is_finite()) {
            return;
        }
        let i = (row.max(0.0) as usize).min(self.rows - 1);
        let j = (sec.max(0.0) as usize) % SECTORS;
        let cell = &mut self.radius[i * SECTORS + j];
        *cell = cell.max(r);
    }

    /// Fills bins no sample fell in with their filled neighbours' mean (repeatedly), the
    /// rest with 0 (nothing is inside there).
    fn fill(&mut self) {
        for _ in 0..32 {
            let before = self.radius.clone();
            let mut empty = false;
            for i in 0..self.rows {
                for j in 0..SECTORS {
                    if before[i * SECTORS + j] >= 0.0 {
                        continue;
                    }
                    let mut sum = 0.0;
                    let mut n = 0.0;
                    for di in [-1i32, 0, 1] {
                        let ii = i as i32 + di;
                        if ii < 0 || ii >= self.rows as i32 {
                            continue;
                        }
                        for dj in [SECTORS - 1, 0, 1] {
                            let v = before[ii as usize * SECTORS + (j + dj) % SECTORS];
                            if v >= 0.0 {
                                sum += v;
                                n += 1.0;
                            }
                        }
                    }
                    if n > 0.0 {
                        self.radius[i * SECTORS + j] = sum / n;
                    } else {
                        empty = true;
                    }
                }
            }
            if !empty {
                return;
            }
        }
        for v in &mut self.radius {
            if *v < 0.0 {
                *v = 0.0;
            }
        }
    }

    /// Sets [`RadialMap::widest`] from the filled bins.
    fn measure_widest(&mut self) {
        let widest = self.radius.iter().fold(0.0f32, |a, &r| a.max(r));
        // A bilinear lookup of bins no larger than this cannot exceed it by more than
        // rounding; the allowance keeps the bound an upper bound.
        self.widest = widest + 1e-4;
    }

    /// The skin's radius at continuous bin coordinates (bilinear, sectors wrap).
    #[inline]
    fn lookup(&self, row: f32, sec: f32) -> f32 {
        let u = (row - 0.5).clamp(0.0, (self.rows - 1) as f32);
        let i0 = u as usize;
        let i1 = (i0 + 1).min(self.rows - 1);
        let fu = u - i0 as f32;
        // `sec` is in [0, SECTORS]: one turn added below 0 wraps it (libm's fmod and floor
        // are calls in the `.wasm`).
        let v = sec - 0.5;
        let v = if v < 0.0 { v + SECTORS as f32 } else { v };
        // v is in [0, SECTORS - 0.5] (NaN casts to 0): the bound only spares the index check
        // (a remainder was a multiply and shifts a lookup).
        let whole = v as usize;
        let j0 = whole.min(SECTORS - 1);
        let j1 = if j0 + 1 == SECTORS { 0 } else { j0 + 1 };
        let fv = v - whole as f32;
        let at = |i: usize, j: usize| self.radius[i * SECTORS + j];
        let a = at(i0, j0) + (at(i0, j1) - at(i0, j0)) * fv;
        let b = at(i1, j0) + (at(i1, j1) - at(i1, j0)) * fv;
        a + (b - a) * fu
    }

    /// Depth of a ball (radius `margin`) at world point `p` inside this map's skin with the
    /// bone posed at `position` / `rotation`, and the outward direction (world); `None`
    /// beyond the map's rows (a cylinder's band, with `margin` to spare).
    #[inline]
    #[must_use]
    pub fn depth(
        &self,
        p: Vec3,
        margin: f32,
        position: Vec3,
        rotation: Quat,
    ) -> Option<(f32, Vec3)> {
        self.depth_above(p, margin, position, rotation, f32::NEG_INFINITY)
    }

    /// [`RadialMap::depth`], or `None` also when the ball cannot be deeper than `floor`
    /// (it is farther from the axis or center than the widest skin): the same answer
    /// wherever it matters to a caller looking for depths above `floor`, without the
    /// trigonometry of the ball's direction.
    #[inline]
    #[must_use]
    pub fn depth_above(
        &self,
        p: Vec3,
        margin: f32,
        position: Vec3,
        rotation: Quat,
        floor: f32,
    ) -> Option<(f32, Vec3)> {
        let q = self.rest + rotation.inverse() * (p - position);
        let depth = self.depth_rest(q, margin, floor)?;
        Some((depth, self.outward(q, rotation)))
    }

    /// The outward direction (world) at `q`, a point in the map's rest frame, with the bone
    /// turned by `rotation`.
    #[inline]
    fn outward(&self, q: Vec3, rotation: Quat) -> Vec3 {
        let d = q - self.center;
        let radial = match self.kind {
            MapKind::Cylinder => {
                // Forward by FORWARD_BIAS on the axis, fading to nothing 3 x FORWARD_BIAS out.
                let r = Vec3::new(d.x, 0.0, d.z);
                let fade = (1.0 - r.length() / (3.0 * FORWARD_BIAS)).max(0.0);
                r + Vec3::Z * (FORWARD_BIAS * fade)
            }
            MapKind::Sphere => d,
        };
        let n = radial.try_normalize().unwrap_or(Vec3::Z);
        rotation * n
    }

    /// [`RadialMap::depth_above`]'s depth of a ball at `q`, a point in the map's rest frame
    /// (`rest + rotation⁻¹ (p - position)`).
    #[inline]
    fn depth_rest(&self, q: Vec3, margin: f32, floor: f32) -> Option<f32> {
        let d = q - self.center;
        let reach = match self.kind {
            MapKind::Cylinder => {
                let row = (q.y - self.bottom) / ROW;
                if row < -margin / ROW || row > self.rows as f32 + margin / ROW {
                    return None;
                }
                (d.x * d.x + d.z * d.z).sqrt()
            }
            MapKind::Sphere => d.length(),
        };
        if self.widest + margin - reach <= floor {
            return None;
        }
        let (row, sec, r) = self.coordinates(q);
        Some(self.lookup(row, sec) + margin - r)
    }

    /// Whether [`RadialMap::depth_rest`] surely answers `None` for a ball at world point `p`
    /// (radius `margin`, depths above `floor`), asked in world axes (`at`, `axis`:
    /// [`BodySurface::axes`]) before the ball is rotated into the map: beyond the band or
    /// the widest skin by more than [`AXES_SLACK`], which covers the rounding of both ways of
    /// measuring.
    #[inline]
    fn skips(&self, (at, axis): (Vec3, Vec3), p: Vec3, margin: f32, floor: f32) -> bool {
        let rel = p - at;
        let reach = match self.kind {
            MapKind::Cylinder => {
                let h = rel.dot(axis);
                if h < -margin - AXES_SLACK || h > self.rows as f32 * ROW + margin + AXES_SLACK {
                    return true;
                }
                (rel.length_squared() - h * h).max(0.0).sqrt()
            }
            MapKind::Sphere => rel.length(),
        };
        self.widest + margin - reach + AXES_SLACK <= floor
    }

    /// Whether a hand within `reach` of `q` (rest frame) may have a ball deeper than `floor`
    /// in this map or within a cylinder's band (see [`BodySurface::near`]).
    #[inline]
    fn may_hold(&self, q: Vec3, reach: f32, floor: f32) -> bool {
        let d = q - self.center;
        let r = match self.kind {
            MapKind::Cylinder => {
                let y = q.y - self.bottom;
                if y + reach < -BOUND_SLACK || y - reach > self.rows as f32 * ROW + BOUND_SLACK {
                    return false;
                }
                (d.x * d.x + d.z * d.z).sqrt()
            }
            MapKind::Sphere => d.length(),
        };
        self.widest + reach - r + BOUND_SLACK > floor
    }

    /// [`RadialMap::depth_rest`] for [`LANES`] balls at once (rest-frame points and radii by
    /// coordinate, each lane with its own floor): each lane's depth, and a bit per lane that
    /// has one (`depth_rest` answered `Some`). The same float operations in the same order
    /// per lane, so the same bits; every step a select, so that the loops become vector
    /// instructions (SSE2 natively, simd128 in the SIMD `.wasm`). The trigonometry and the
    /// lookup only run when some lane passes the bounds.
    // The negated comparisons are the one-ball query's, whose NaN answers they keep.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    #[inline]
    fn depths(&self, q: &Lanes, floor: &[f32; LANES]) -> ([f32; LANES], u32) {
        let c = self.center;
        let mut reach = [0.0f32; LANES];
        let mut ok = [0u32; LANES];
        match self.kind {
            MapKind::Cylinder => {
                let top = self.rows as f32;
                for l in 0..LANES {
                    let (dx, dz, margin) = (q.x[l] - c.x, q.z[l] - c.z, q.m[l]);
                    let row = (q.y[l] - self.bottom) / ROW;
                    let r = (dx * dx + dz * dz).sqrt();
                    reach[l] = r;
                    ok[l] = lane_bit(
                        l,
                        !(row < -margin / ROW || row > top + margin / ROW)
                            & !(self.widest + margin - r <= floor[l]),
                    );
                }
            }
            MapKind::Sphere => {
                for l in 0..LANES {
                    let (dx, dy, dz) = (q.x[l] - c.x, q.y[l] - c.y, q.z[l] - c.z);
                    let r = (dx * dx + dy * dy + dz * dz).sqrt();
                    ok[l] = lane_bit(l, !(self.widest + q.m[l] - r <= floor[l]));
                }
            }
        }
        let bits = bits_of(ok);
        let mut depth = [0.0f32; LANES];
        if bits == 0 {
            return (depth, 0);
        }
        let (mut row, mut sec) = ([0.0f32; LANES], [0.0f32; LANES]);
        match self.kind {
            MapKind::Cylinder => {
                for l in 0..LANES {
                    row[l] = (q.y[l] - self.bottom) / ROW;
                    sec[l] = sector(q.x[l] - c.x, q.z[l] - c.z);
                }
            }
            MapKind::Sphere => {
                for l in 0..LANES {
                    let (dx, dy, dz) = (q.x[l] - c.x, q.y[l] - c.y, q.z[l] - c.z);
                    let across = (dx * dx + dz * dz).sqrt();
                    reach[l] = (across * across + dy * dy).sqrt();
                    let polar = atan2_fast(across, dy);
                    row[l] = polar / core::f32::consts::PI * HEAD_ROWS as f32;
                    sec[l] = sector(dx, dz);
                }
            }
        }
        // `lookup` for the lanes kept (its casts do not become vector instructions in SSE2).
        let mut left = bits;
        while left != 0 {
            let l = left.trailing_zeros() as usize;
            left &= left - 1;
            depth[l] = self.lookup(row[l], sec[l]) + q.m[l] - reach[l];
        }
        (depth, bits)
    }
}

/// Balls a map answers at once ([`RadialMap::depths`]): natively 8 floats, two SSE2
/// registers; 4 in the SIMD `.wasm`, one simd128 register (as fast in Node as 8, 1.4 KB of
/// gzip fewer); one in the `.wasm` without SIMD, where the lanes' loops would only be
/// unrolled (4.6 KB of gzip for 8 lanes): there the queries go a ball at a time as before.
#[cfg(not(target_arch = "wasm32"))]
const LANES: usize = 8;
#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
const LANES: usize = 4;
#[cfg(all(target_arch = "wasm32", not(target_feature = "simd128")))]
const LANES: usize = 1;

/// Lane `l`'s bit if `on`, else 0 (a select of a constant: vector instructions, where a
/// shift by the lane would not be in SSE2).
#[inline]
fn lane_bit(l: usize, on: bool) -> u32 {
    const BIT: [u32; LANES] = {
        let mut bit = [0; LANES];
        let mut l = 0;
        while l < LANES {
            bit[l] = 1 << l;
            l += 1;
        }
        bit
    };
    if on {
        BIT[l]
    } else {
        0
    }
}

/// The lanes' bits of [`lane_bit`] together.
#[inline]
fn bits_of(bits: [u32; LANES]) -> u32 {
    bits.iter().fold(0, |a, &b| a | b)
}

/// Chunks of [`LANES`] a hand's balls take.
const CHUNKS: usize = HAND_SPHERES.div_ceil(LANES);

/// Up to [`LANES`] balls: centers by coordinate and radii.
#[derive(Clone, Copy, Debug, Default)]
struct Lanes {
    x: [f32; LANES],
    y: [f32; LANES],
    z: [f32; LANES],
    m: [f32; LANES],
}

impl Lanes {
    /// Balls `from..` of `points` (at most [`LANES`]; the rest of the lanes' balls are at the
    /// origin with radius 0), each at `at + its center`, and the bits of the lanes filled.
    #[inline]
    fn of(at: Vec3, points: &[(Vec3, f32)], from: usize) -> (Lanes, u32) {
        let mut b = Lanes::default();
        let mut n = 0;
        for (l, (p, m)) in points.iter().skip(from).take(LANES).enumerate() {
            let c = at + *p;
            (b.x[l], b.y[l], b.z[l], b.m[l]) = (c.x, c.y, c.z, *m);
            n = l + 1;
        }
        (b, (1u32 << n) - 1)
    }

    /// Lane `l`'s center.
    #[inline]
    fn at(&self, l: usize) -> Vec3 {
        Vec3::new(self.x[l], self.y[l], self.z[l])
    }

    /// The centers moved by `d`, radii kept.
    #[inline]
    fn moved(&self, d: Vec3) -> Lanes {
        Lanes::along(&[self.x, self.y, self.z], self.m, d)
    }

    /// Balls at centers `xyz` (by coordinate) moved by `d`, radii `m`.
    #[inline]
    fn along([x, y, z]: &[[f32; LANES]; 3], m: [f32; LANES], d: Vec3) -> Lanes {
        let mut b = Lanes {
            m,
            ..Lanes::default()
        };
        for l in 0..LANES {
            (b.x[l], b.y[l], b.z[l]) = (x[l] + d.x, y[l] + d.y, z[l] + d.z);
        }
        b
    }
}

/// Everything self-contact learned from the skin (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct BodySurface {
    /// Per [`MAP_BONES`] entry, its map (`None`: the avatar lacks the bone or it has no skin).
    pub maps: [Option<RadialMap>; MAP_BONES.len()],
    /// Finger radius (m), per side `[left, right]`.
    pub finger_radius: [f32; 2],
    /// Palm half-thickness (m), per side.
    pub palm_half: [f32; 2],
    /// How far (m) the hand's skin reaches past its contact balls, per side `[left, right]`
    /// and per kind of ball `[palm, finger]` (those with the palm's half-thickness, those
    /// with the finger radius): with the avatar at rest, the most any hand vertex lies outside
    /// the ball nearest it, among the vertices nearest a ball of that kind. The balls follow
    /// the bones and the hand's thickness, not its outline: a box hand's corners (the figure
    /// of primitives': 22 mm past its wrist ball) or a human palm's edge (19-28 mm) reach
    /// past them, and a hand held [`super::CLEARANCE`] clear of the body by its balls alone
    /// came within 2 cm of it.
    pub hand_excess: [[f32; 2]; 2],
    /// Head samples relative to the head bone (rest, internal frame), kept for placing the
    /// face anchors at setup.
    head_samples: Vec<Vec3>,
    /// Skin vertices and samples used.
    pub samples: usize,
}

impl BodySurface {
    /// Learns the body from `mesh` (internal frame) on `skeleton`; `None` when the skin has
    /// no head or torso.
    #[must_use]
    pub fn new(skeleton: &Skeleton, mesh: &SkinMesh) -> Option<BodySurface> {
        // The head's skin ends at the neck's joint for what hangs from it (long hair, twin
        // tails, a veil: skinned to non-humanoid bones under the head): below it that is not
        // the head a hand can touch, and in the head's map it would fill the space beside the
        // neck and shoulders. (The head bone's own skin is kept wherever it is: a large head's
        // chin can be below the neck's joint.)
        let neck = skeleton
            .rest_world(HumanBone::Neck)
            .map_or(f32::NEG_INFINITY, |n| n.y);
        let parts: Vec<Part> = mesh
            .bones
            .iter()
            .enumerate()
            .map(|(i, b)| match part_of(skeleton, *b) {
                Part::Map(HEAD_MAP)
                    if mesh.hanging.get(i).copied().unwrap_or(false)
                        && mesh.positions[i].y < neck =>
                {
                    Part::Other
                }
                part => part,
            })
            .collect();
        // Samples per part: vertices, plus triangle samples.
        let mut per_map: [Vec<Vec3>; MAP_BONES.len()] = Default::default();
        let mut hand_vertices: [Vec<(Vec3, HumanBone)>; 2] = Default::default();
        for (i, part) in parts.iter().enumerate() {
            match part {
                Part::Map(k) => per_map[*k].push(mesh.positions[i]),
                Part::Hand(s) => hand_vertices[s.index()].push((mesh.positions[i], mesh.bones[i])),
                Part::Other => {}
            }
        }
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| i as usize);
            let part = if parts[b] == parts[c] {
                parts[b]
            } else {
                parts[a]
            };
            let Part::Map(k) = part else { continue };
            let (pa, pb, pc) = (mesh.positions[a], mesh.positions[b], mesh.positions[c]);
            let longest = (pb - pa)
                .length()
                .max((pc - pb).length())
                .max((pa - pc).length());
            let n = ((longest / SPACING).ceil() as usize).clamp(1, MAX_SPLITS);
            if n == 1 {
                continue;
            }
            let inv = 1.0 / n as f32;
            for i in 0..=n {
                for j in 0..=(n - i) {
                    if (i == 0 && j == 0) || i == n || j == n {
                        continue; // the corners are vertices already
                    }
                    per_map[k]
                        .push(pa + (pb - pa) * (i as f32 * inv) + (pc - pa) * (j as f32 * inv));
                }
            }
        }
        let samples = per_map.iter().map(Vec::len).sum::<usize>();
        let mut maps: [Option<RadialMap>; MAP_BONES.len()] = Default::default();
        for (k, points) in per_map.iter().enumerate() {
            let bone = MAP_BONES[k];
            let Some(rest) = skeleton.rest_world(bone) else {
                continue;
            };
            if points.len() < 16 {
                continue;
            }
            let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
            for p in points {
                lo = lo.min(*p);
                hi = hi.max(*p);
            }
            let mid = 0.5 * (lo + hi);
            let mut map = if k == HEAD_MAP {
                RadialMap::empty(bone, MapKind::Sphere, mid, lo.y, HEAD_ROWS)
            } else {
                let rows = (((hi.y - lo.y) / ROW).ceil() as usize).clamp(1, MAX_ROWS);
                RadialMap::empty(
                    bone,
                    MapKind::Cylinder,
                    Vec3::new(mid.x, 0.0, mid.z),
                    lo.y,
                    rows,
                )
            };
            map.rest = rest;
            for p in points {
                map.add(*p);
            }
            map.fill();
            map.measure_widest();
            maps[k] = Some(map);
        }
        if maps.iter().all(Option::is_none) {
            return None;
        }
        let head_samples = match skeleton.rest_world(HumanBone::Head) {
            Some(h) => per_map[HEAD_MAP].iter().map(|p| *p - h).collect(),
            None => Vec::new(),
        };
        let palm = crate::humanoid::measure::avatar_palm_length(skeleton);
        let mut finger_radius = [super::colliders::TIP_MARGIN * palm; 2];
        let mut palm_half = [super::colliders::HAND_MARGIN * palm; 2];
        for side in Side::BOTH {
            if let Some((f, p)) = hand_thickness(skeleton, side, &hand_vertices[side.index()]) {
                finger_radius[side.index()] = f;
                palm_half[side.index()] = p;
            }
        }
        let hand_excess = Side::BOTH.map(|side| {
            let s = side.index();
            hand_excess(
                skeleton,
                side,
                &hand_vertices[s],
                finger_radius[s],
                palm_half[s],
            )
        });
        Some(BodySurface {
            maps,
            finger_radius,
            palm_half,
            hand_excess,
            head_samples,
            samples,
        })
    }

    /// The deepest a ball of radius `margin` at `p` is inside the body (head and torso maps,
    /// posed as `world`), its outward direction, and which map; `None` when no map is near.
    /// `only`: restrict to the maps whose flag is set. Allocates nothing.
    #[must_use]
    pub fn depth(
        &self,
        p: Vec3,
        margin: f32,
        world: &WorldPose,
        only: [bool; MAP_BONES.len()],
    ) -> Option<(f32, Vec3, usize)> {
        self.depth_above(p, margin, world, only, f32::NEG_INFINITY)
    }

    /// [`BodySurface::depth`] for a caller that only wants depths above `floor`: maps the
    /// ball cannot be deeper than `floor` in (nor than a map already seen) are skipped, so
    /// the answer is `None` or any depth at most `floor` where `depth` might have given
    /// another such one, and otherwise the same.
    #[must_use]
    pub fn depth_above(
        &self,
        p: Vec3,
        margin: f32,
        world: &WorldPose,
        only: [bool; MAP_BONES.len()],
        floor: f32,
    ) -> Option<(f32, Vec3, usize)> {
        let only = mask_of(only);
        self.depth_in(p, margin, world, only, &self.axes(world, only), floor)
    }

    /// [`BodySurface::depth_above`] with the maps as a [`Mask`].
    fn depth_in(
        &self,
        p: Vec3,
        margin: f32,
        world: &WorldPose,
        only: Mask,
        axes: &Axes,
        floor: f32,
    ) -> Option<(f32, Vec3, usize)> {
        let (d, q, k) = self.deepest_rest(p, margin, world, only, axes, floor)?;
        let map = self.maps[k].as_ref()?;
        Some((d, map.outward(q, world.rotation[map.bone.index()]), k))
    }

    /// [`BodySurface::depth_above`] without the outward direction: the depth, the point in
    /// the deepest map's rest frame and that map (its direction is worked out for the one
    /// map that wins, not for each map looked at).
    fn deepest_rest(
        &self,
        p: Vec3,
        margin: f32,
        world: &WorldPose,
        only: Mask,
        axes: &Axes,
        floor: f32,
    ) -> Option<(f32, Vec3, usize)> {
        let mut best: Option<(f32, Vec3, usize)> = None;
        // The maps of `only` in order, without a test per map left out.
        let mut bits = only;
        while bits != 0 {
            let k = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let Some(map) = self.maps.get(k).and_then(Option::as_ref) else {
                continue;
            };
            let b = map.bone.index();
            let floor = best.map_or(floor, |(bd, _, _)| bd.max(floor));
            // Beyond the band or the widest skin in world axes: not rotated into the map.
            if map.skips(axes[k], p, margin, floor) {
                continue;
            }
            let q = map.rest + world.rotation[b].inverse() * (p - world.position[b]);
            if let Some(d) = map.depth_rest(q, margin, floor) {
                if best.is_none_or(|(bd, _, _)| d > bd) {
                    best = Some((d, q, k));
                }
            }
        }
        best
    }

    /// [`BodySurface::deepest_rest`] for [`LANES`] balls at once (world centers, each lane's
    /// answer as `deepest_rest` gives it with that lane's `floor`): per lane the depth, the
    /// map (`u8::MAX`: `None`) and the point in that map's rest frame. Each map of `only` in
    /// turn: the lanes' world-axes bounds, their rotation into the map and their depths all
    /// as lanes, then each lane's best kept as `deepest_rest` keeps it (a depth counts when
    /// above the best so far).
    // The negated comparisons are `RadialMap::skips`'s, whose NaN answers they keep.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    fn deepest_lanes(
        &self,
        p: &Lanes,
        live: u32,
        world: &WorldPose,
        only: Mask,
        axes: &Axes,
        floor: [f32; LANES],
    ) -> ([f32; LANES], [u8; LANES], Lanes) {
        let mut best = [f32::NEG_INFINITY; LANES];
        let mut which = [u8::MAX; LANES];
        let mut at = Lanes::default();
        // Each lane's floor: its own, then its best so far.
        let mut fl = floor;
        let mut bits = only;
        while bits != 0 {
            let k = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let Some(map) = self.maps.get(k).and_then(Option::as_ref) else {
                continue;
            };
            // Beyond the band or the widest skin in world axes (`RadialMap::skips`).
            let (a, axis) = axes[k];
            let mut kept = [0u32; LANES];
            match map.kind {
                MapKind::Cylinder => {
                    let top = map.rows as f32 * ROW;
                    for l in 0..LANES {
                        let (rx, ry, rz) = (p.x[l] - a.x, p.y[l] - a.y, p.z[l] - a.z);
                        let margin = p.m[l];
                        let h = rx * axis.x + ry * axis.y + rz * axis.z;
                        let band = !(h < -margin - AXES_SLACK || h > top + margin + AXES_SLACK);
                        let reach = (rx * rx + ry * ry + rz * rz - h * h).max(0.0).sqrt();
                        kept[l] = lane_bit(
                            l,
                            band & !(map.widest + margin - reach + AXES_SLACK <= fl[l]),
                        );
                    }
                }
                MapKind::Sphere => {
                    for l in 0..LANES {
                        let (rx, ry, rz) = (p.x[l] - a.x, p.y[l] - a.y, p.z[l] - a.z);
                        let reach = (rx * rx + ry * ry + rz * rz).sqrt();
                        kept[l] = lane_bit(l, !(map.widest + p.m[l] - reach + AXES_SLACK <= fl[l]));
                    }
                }
            }
            let kept = bits_of(kept) & live;
            if kept == 0 {
                continue;
            }
            // Into the map's rest frame: `rest + rotation⁻¹ (p - position)`, glam's quaternion
            // product written out (its order in every build: scalar, SSE2, simd128).
            let bone = map.bone.index();
            let (pos, rot) = (world.position[bone], world.rotation[bone]);
            let (bx, by, bz, w) = (-rot.x, -rot.y, -rot.z, rot.w);
            let b2 = bx * bx + by * by + bz * bz;
            let (ww, w2) = (w * w - b2, w * 2.0);
            let mut q = Lanes {
                m: p.m,
                ..Lanes::default()
            };
            for l in 0..LANES {
                let (vx, vy, vz) = (p.x[l] - pos.x, p.y[l] - pos.y, p.z[l] - pos.z);
                let t = (vx * bx + vy * by + vz * bz) * 2.0;
                let (cx, cy, cz) = (by * vz - vy * bz, bz * vx - vz * bx, bx * vy - vx * by);
                q.x[l] = map.rest.x + (vx * ww + bx * t + cx * w2);
                q.y[l] = map.rest.y + (vy * ww + by * t + cy * w2);
                q.z[l] = map.rest.z + (vz * ww + bz * t + cz * w2);
            }
            let (depth, some) = map.depths(&q, &fl);
            let mut found = some & kept;
            while found != 0 {
                let l = found.trailing_zeros() as usize;
                found &= found - 1;
                if which[l] == u8::MAX || depth[l] > best[l] {
                    best[l] = depth[l];
                    fl[l] = depth[l].max(floor[l]);
                    which[l] = k as u8;
                    (at.x[l], at.y[l], at.z[l]) = (q.x[l], q.y[l], q.z[l]);
                }
            }
        }
        (best, which, at)
    }

    /// Moves `anchor` (relative to the head bone, rest, internal frame) onto the head's skin:
    /// forward for anchors on the face, sideways for ears (`side`: +1 left, -1 right, 0 the
    /// face). Unchanged when no skin sample lies on that line.
    #[must_use]
    pub fn onto_face(&self, anchor: Vec3, side: f32) -> Vec3 {
        let mut best: Option<f32> = None;
        for s in &self.head_samples {
            if side == 0.0 {
                if (s.x - anchor.x).abs() < 0.005 && (s.y - anchor.y).abs() < 0.005 {
                    best = Some(best.map_or(s.z, |b| b.max(s.z)));
                }
            } else if (s.y - anchor.y).abs() < 0.006 && (s.z - anchor.z).abs() < 0.006 {
                let x = s.x * side;
                best = Some(best.map_or(x, |b| b.max(x)));
            }
        }
        match best {
            None => anchor,
            Some(v) if side == 0.0 => Vec3::new(anchor.x, anchor.y, v),
            Some(v) => Vec3::new(v * side, anchor.y, anchor.z),
        }
    }
}

/// The finger radius and palm half-thickness of one hand's skin, or `None` without enough
/// skin or bones.
fn hand_thickness(
    skeleton: &Skeleton,
    side: Side,
    vertices: &[(Vec3, HumanBone)],
) -> Option<(f32, f32)> {
    let hand = skeleton.rest_world(side.hand())?;
    let mut finger = Vec::new();
    let mut palm = Vec::new();
    let index = skeleton.rest_world(side.finger(Finger::Index)[0]);
    let little = skeleton.rest_world(side.finger(Finger::Little)[0]);
    let normal = index
        .zip(little)
        .and_then(|(i, l)| (i - hand).cross(l - hand).try_normalize());
    for &(p, bone) in vertices {
        if bone == side.hand() {
            if let Some(n) = normal {
                palm.push((p - hand).dot(n).abs());
            }
            continue;
        }
        let Some(a) = skeleton.rest_world(bone) else {
            continue;
        };
        // The bone's segment: to its child joint, else continued as long as the bone itself.
        let child = HumanBone::ALL
            .iter()
            .find(|c| skeleton.has(**c) && skeleton.parent(**c) == Some(bone))
            .and_then(|c| skeleton.rest_world(*c));
        let b = match child {
            Some(c) => c,
            None => {
                let parent = skeleton.parent(bone).and_then(|q| skeleton.rest_world(q))?;
                a + (a - parent) * 0.8
            }
        };
        let ab = b - a;
        let t = if ab.length_squared() > 1e-12 {
            ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        finger.push((p - (a + ab * t)).length());
    }
    // The upper quartile: the hand's thicker parts count (a median let the palm's ball sink
    // into the chest by up to 17 mm on the generated avatars).
    let median = |v: &mut Vec<f32>| -> Option<f32> {
        if v.len() < 8 {
            return None;
        }
        let k = v.len() * 3 / 4;
        nth_smallest(v, k)
    };
    let f = median(&mut finger)?;
    let p = median(&mut palm).unwrap_or(1.6 * f);
    (f > 1e-4 && p > 1e-4).then_some((f, p))
}

/// [`BodySurface::hand_excess`] of one side: the hand's balls placed on the rest skeleton
/// much as [`hand_spheres`] places them at run time (the hand joint, the palm's center between
/// it and the proximal joints, and each finger's first joint with the palm's half-thickness
/// `palm`; the finger's other joints with the finger radius `finger`, and its tip, which run
/// time takes from the alignment's fingertip, here continued from its last bone as
/// [`hand_thickness`] continues it), then per kind of ball the most any hand vertex lies
/// outside the ball nearest it (0 when all are inside, or without the hand joint).
fn hand_excess(
    skeleton: &Skeleton,
    side: Side,
    vertices: &[(Vec3, HumanBone)],
    finger: f32,
    palm: f32,
) -> [f32; 2] {
    let Some(hand) = skeleton.rest_world(side.hand()) else {
        return [0.0; 2];
    };
    // (center, radius, a palm ball): at most the hand joint, the palm's center and four a
    // finger, as many as HAND_SPHERES.
    let mut balls = [(hand, palm, true); HAND_SPHERES];
    let mut n = 1;
    let (mut sum, mut count) = (hand, 1.0);
    for f in [Finger::Index, Finger::Middle, Finger::Ring, Finger::Little] {
        if let Some(p) = skeleton.rest_world(side.finger(f)[0]) {
            sum += p;
            count += 1.0;
        }
    }
    if count > 1.0 {
        balls[n] = (sum / count, palm, true);
        n += 1;
    }
    for f in Finger::ALL {
        let mut last = [None, None];
        for (k, b) in side.finger(f).iter().enumerate() {
            if let Some(p) = skeleton.rest_world(*b) {
                balls[n] = (p, if k == 0 { palm } else { finger }, k == 0);
                n += 1;
                last = [last[1], Some(p)];
            }
        }
        if let [Some(a), Some(b)] = last {
            balls[n] = (b + (b - a) * 0.8, finger, false);
            n += 1;
        }
    }
    let balls = &balls[..n];
    let mut excess = [0.0f32; 2];
    for (v, _) in vertices {
        let nearest = balls
            .iter()
            .fold((f32::INFINITY, true), |best, (c, r, is_palm)| {
                let d = (*v - *c).length() - r;
                if d < best.0 {
                    (d, *is_palm)
                } else {
                    best
                }
            });
        if nearest.0.is_finite() {
            let k = usize::from(!nearest.1);
            excess[k] = excess[k].max(nearest.0);
        }
    }
    excess
}

/// Most contact spheres of a hand: wrist, palm center, three joints and a tip per finger.
pub const HAND_SPHERES: usize = 2 + 5 * 4;

/// A hand's contact spheres (center relative to the wrist target, world axes; radius) into
/// `out`: the wrist and palm center and each finger's joints with the palm's half-thickness at
/// the palm, the finger radius along the fingers. A hand not seen this frame
/// ([`super::SideTarget::held`]) has its wrist, palm center and fingertips only (it is
/// pushed, never placed: 7 spheres instead of 22, for the speed of frames with lost hands).
/// Returns how many.
pub fn hand_spheres(
    surface: &BodySurface,
    side: Side,
    target: &super::SideTarget,
    out: &mut [(Vec3, f32); HAND_SPHERES],
) -> usize {
    hand_spheres_of(
        surface,
        side,
        target.body_points(),
        target.hand.is_some(),
        out,
    )
}

/// [`hand_spheres`] of the points `body` (a target's [`super::SideTarget::body_points`]), all
/// of them when `seen` (the hand was seen this frame), without a target to hold them.
pub fn hand_spheres_of(
    surface: &BodySurface,
    side: Side,
    body: Option<&super::HandPoints>,
    seen: bool,
    out: &mut [(Vec3, f32); HAND_SPHERES],
) -> usize {
    let s = side.index();
    let (palm, finger) = (surface.palm_half[s], surface.finger_radius[s]);
    out[0] = (Vec3::ZERO, palm);
    let mut n = 1;
    if let Some(hand) = body {
        if let Some(c) = hand.avatar[0] {
            out[n] = (c, palm);
            n += 1;
        }
        for (k, j) in hand.joints.iter().enumerate() {
            if let Some(j) = j.filter(|_| seen) {
                // Each finger's first joint is in the palm (the thumb's: at its root).
                let r = if k % 3 == 0 { palm } else { finger };
                out[n] = (j, r);
                n += 1;
            }
        }
        for t in hand.avatar[1..].iter().flatten() {
            out[n] = (*t, finger);
            n += 1;
        }
    }
    n
}

/// Which maps a query looks at: bit k for the map of `MAP_BONES[k]`.
type Mask = u8;

/// Each map placed in world axes ([`BodySurface::axes`]).
type Axes = [(Vec3, Vec3); MAP_BONES.len()];

/// Rounding allowance of [`RadialMap::skips`] (m).
const AXES_SLACK: f32 = 1e-3;

/// The maps whose flag is set, as a [`Mask`].
fn mask_of(only: [bool; MAP_BONES.len()]) -> Mask {
    only.iter()
        .enumerate()
        .fold(0, |m, (k, &on)| m | (u8::from(on) << k))
}

/// Every map.
const ALL_MAPS: Mask = (1 << MAP_BONES.len()) - 1;

/// A ball around a hand's balls: center relative to the wrist, and the largest distance
/// from it to a ball's far side.
#[derive(Clone, Copy, Debug)]
struct Hull {
    center: Vec3,
    reach: f32,
}

impl Hull {
    fn of(points: &[(Vec3, f32)]) -> Hull {
        let n = points.len().max(1) as f32;
        let center = points.iter().fold(Vec3::ZERO, |a, (p, _)| a + *p) / n;
        let reach = points
            .iter()
            .fold(0.0f32, |a, (p, m)| a.max((*p - center).length() + m));
        Hull { center, reach }
    }
}

/// Half the width of the bracket that [`BodySurface::settle`] tries first around the deepest
/// ball's own landing (m).
const NEAR_GUESS: f32 = 0.001;

/// Secant steps [`BodySurface::settle`] takes on the deepest ball's own landing.
const LAND_STEPS: usize = 6;
/// How near 0 (m) that ball's depth must come for its landing to count as found.
const LAND_TOLERANCE: f32 = 1e-6;
/// How far either side of that landing (m) the hand is checked: out just before, in just
/// after (the bisection's last step is about as wide).
const LAND_CHECK: f32 = 4e-6;

/// Rounding allowance of the hand-level bounds (m): they only skip what cannot matter.
const BOUND_SLACK: f32 = 1e-4;

impl BodySurface {
    /// The maps of `only` in which some ball of a hand (its [`Hull`] centered at `center`,
    /// world) might be deeper than `floor` (or inside a cylinder's band): the rest would
    /// answer `None` to [`BodySurface::depth_above`] for every one of its balls, so a query
    /// can skip them, rotating one point per map instead of one per ball.
    fn near(&self, center: Vec3, reach: f32, world: &WorldPose, only: Mask, floor: f32) -> Mask {
        let mut mask = 0;
        for (k, map) in self.maps.iter().enumerate() {
            let Some(map) = map.as_ref().filter(|_| only >> k & 1 != 0) else {
                continue;
            };
            let b = map.bone.index();
            let q = map.rest + world.rotation[b].inverse() * (center - world.position[b]);
            mask |= u8::from(map.may_hold(q, reach, floor)) << k;
        }
        mask
    }

    /// Each map of `only` placed in world axes for [`RadialMap::skips`]: a point of its axis
    /// (a cylinder's at its lowest row's bottom) or its center, and its axis's direction.
    fn axes(&self, world: &WorldPose, only: Mask) -> Axes {
        let mut axes = [(Vec3::ZERO, Vec3::Y); MAP_BONES.len()];
        for (k, map) in self.maps.iter().enumerate() {
            let Some(map) = map.as_ref().filter(|_| only >> k & 1 != 0) else {
                continue;
            };
            let b = map.bone.index();
            let r = world.rotation[b];
            let anchor = match map.kind {
                MapKind::Cylinder => Vec3::new(map.center.x, map.bottom, map.center.z),
                MapKind::Sphere => map.center,
            };
            axes[k] = (world.position[b] + r * (anchor - map.rest), r * Vec3::Y);
        }
        axes
    }

    /// How deep the hand's deepest ball (centers relative to `wrist`, world axes) is inside
    /// the body, or `floor` if none is deeper. Allocates nothing.
    #[must_use]
    pub fn deepest(
        &self,
        wrist: Vec3,
        points: &[(Vec3, f32)],
        world: &WorldPose,
        floor: f32,
    ) -> f32 {
        let hull = Hull::of(points);
        let mask = self.near(wrist + hull.center, hull.reach, world, ALL_MAPS, floor);
        // No map near: every ball answers `None` (a hand away from the body).
        if mask == 0 {
            return floor;
        }
        let axes = self.axes(world, mask);
        // The balls LANES at a time, each chunk with the best before it as its floor.
        let mut best = floor;
        for from in (0..points.len()).step_by(LANES) {
            let (balls, live) = Lanes::of(wrist, points, from);
            let (d, which, _) = self.deepest_lanes(&balls, live, world, mask, &axes, [best; LANES]);
            for l in 0..LANES {
                if live >> l & 1 != 0 && which[l] != u8::MAX && d[l] > best {
                    best = d[l];
                }
            }
        }
        best
    }

    /// The translation that moves the hand spheres (centers relative to `wrist`, world axes)
    /// out of the body: each sphere in turn pushed straight out
    /// of the map it is deepest in (Gauss-Seidel, three passes).
    #[must_use]
    pub fn push(&self, wrist: Vec3, points: &[(Vec3, f32)], world: &WorldPose) -> Vec3 {
        // Only balls deeper than 0 move: the maps no ball of the hand can be that deep in
        // (the hand's hull, where the pushes so far have taken it) are not sampled, which
        // answers as sampling them would (`depth_above` with floor 0 skips them too).
        let hull = Hull::of(points);
        let all = ALL_MAPS;
        let mut total = Vec3::ZERO;
        let mut mask = self.near(wrist + hull.center, hull.reach, world, all, 0.0);
        let mut axes = self.axes(world, mask);
        for _ in 0..3 {
            // No map near: no ball moves (a hand away from the body).
            if mask == 0 {
                break;
            }
            let mut moved = false;
            // The balls LANES at a time where the hand is; a ball that moves it moves the
            // balls after it, which are asked again from there.
            let mut from = 0;
            while from < points.len() {
                let (balls, live) = Lanes::of(wrist, points, from);
                let balls = balls.moved(total);
                let (d, which, q) =
                    self.deepest_lanes(&balls, live, world, mask, &axes, [0.0; LANES]);
                let mut next = from + LANES;
                for l in 0..LANES {
                    let k = usize::from(which[l]);
                    let Some(map) = self.maps.get(k).and_then(Option::as_ref) else {
                        continue;
                    };
                    if live >> l & 1 != 0 && d[l] > 0.0 {
                        let n = map.outward(q.at(l), world.rotation[map.bone.index()]);
                        total += n * d[l];
                        moved = true;
                        mask = self.near(wrist + hull.center + total, hull.reach, world, all, 0.0);
                        axes = self.axes(world, mask);
                        next = from + l + 1;
                        break;
                    }
                }
                from = next;
            }
            if !moved {
                break;
            }
        }
        if total.is_finite() {
            total
        } else {
            Vec3::ZERO
        }
    }

    /// The translation that lands the hand on the skin of the `only` maps: along the skin's
    /// normal at the hand's sphere nearest the skin (or deepest inside), as far as makes the
    /// hand's deepest sphere rest on the skin (bisection: moving one sphere onto the skin
    /// may push another one in).
    #[must_use]
    pub fn settle(
        &self,
        wrist: Vec3,
        points: &[(Vec3, f32)],
        world: &WorldPose,
        only: [bool; MAP_BONES.len()],
    ) -> Vec3 {
        self.land(wrist, points, world, only, false)
    }

    /// [`BodySurface::settle`] outward only: the translation that takes a hand with some
    /// ball inside the body out along one line (the deepest ball's normal) until every ball
    /// is out, zero for a hand already out. One line for the whole hand: pushing each ball
    /// along its own normal ([`BodySurface::push`]) swings a hand near the torso's axis, where
    /// the normals turn fast.
    #[must_use]
    pub fn lift_out(&self, wrist: Vec3, points: &[(Vec3, f32)], world: &WorldPose) -> Vec3 {
        self.land(wrist, points, world, [true; MAP_BONES.len()], true)
    }

    // One lane in the `.wasm` without SIMD: a ball's lane is then `i % 1`.
    #[cfg_attr(
        all(target_arch = "wasm32", not(target_feature = "simd128")),
        allow(clippy::modulo_one)
    )]
    fn land(
        &self,
        wrist: Vec3,
        points: &[(Vec3, f32)],
        world: &WorldPose,
        only: [bool; MAP_BONES.len()],
        out_only: bool,
    ) -> Vec3 {
        let hull = Hull::of(points);
        let only = mask_of(only);
        // Outward only, a hand whose deepest ball is not inside stays: its deepest is only
        // looked for above 0, where the bounds skip the maps and balls that cannot be inside
        // (the deepest above 0 is the deepest, found in the same order).
        let least = if out_only { 0.0 } else { f32::NEG_INFINITY };
        let deepest = |shift: Vec3| -> Option<(f32, Vec3, usize, usize)> {
            let mask = self.near(wrist + hull.center + shift, hull.reach, world, only, least);
            if mask == 0 {
                return None;
            }
            let axes = self.axes(world, mask);
            // The depth, the point in its map's rest frame, the map and the ball.
            let mut best: Option<(f32, Vec3, usize, usize)> = None;
            // The balls LANES at a time, each chunk with the best before it as its floor.
            for from in (0..points.len()).step_by(LANES) {
                let (balls, live) = Lanes::of(wrist, points, from);
                let floor = best.map_or(least, |(bd, ..)| bd.max(least));
                let (d, which, q) = self.deepest_lanes(
                    &balls.moved(shift),
                    live,
                    world,
                    mask,
                    &axes,
                    [floor; LANES],
                );
                for l in 0..LANES {
                    if live >> l & 1 != 0
                        && which[l] != u8::MAX
                        && best.is_none_or(|(bd, ..)| d[l] > bd)
                    {
                        best = Some((d[l], q.at(l), usize::from(which[l]), from + l));
                    }
                }
            }
            // The outward normal of the deepest ball's map.
            let (d, q, k, i) = best?;
            let map = self.maps[k].as_ref()?;
            Some((d, map.outward(q, world.rotation[map.bone.index()]), k, i))
        };
        let Some((d0, n, k0, i0)) = deepest(Vec3::ZERO) else {
            return Vec3::ZERO;
        };
        if out_only && d0 <= 0.0 {
            return Vec3::ZERO;
        }
        let (mut lo, mut hi) = if d0 < 0.0 {
            (0.0, -2.0 * d0 + 0.01)
        } else {
            (-2.0 * d0 - 0.01, 0.0)
        };
        // Every move looked at below lies within [lo, hi] widened by NEAR_GUESS (and the
        // checks' few micrometers): maps that no ball can reach anywhere on that stretch of
        // the line answer no to every `reaches` and are neither rotated into nor sampled.
        let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo) + NEAR_GUESS + BOUND_SLACK);
        let only = self.near(
            wrist + hull.center - n * mid,
            hull.reach + half,
            world,
            only,
            -f32::from_bits(1),
        );
        // The balls (at most HAND_SPHERES) and the hull's center in each map's rest frame,
        // and the direction of the move there: the hand moved by -s n puts a ball at
        // `base + s dir`, so the search below rotates nothing.
        let balls = &points[..points.len().min(HAND_SPHERES)];
        // By coordinate, per map and chunk (the radii in `margins`: under 2 KB to clear, which
        // `memset` does without `rep stos`).
        let mut base = [[[[0.0f32; LANES]; 3]; CHUNKS]; MAP_BONES.len()];
        let mut margins = [[0.0f32; LANES]; CHUNKS];
        for (i, (_, m)) in balls.iter().enumerate() {
            margins[i / LANES][i % LANES] = *m;
        }
        // The lanes of each chunk that hold a ball.
        let live = |c: usize| -> u32 {
            let n = balls.len().saturating_sub(c * LANES).min(LANES);
            (1u32 << n) - 1
        };
        let mut hub = [Vec3::ZERO; MAP_BONES.len()];
        let mut dir = [Vec3::ZERO; MAP_BONES.len()];
        for (k, map) in self.maps.iter().enumerate() {
            let Some(map) = map.as_ref().filter(|_| only >> k & 1 != 0) else {
                continue;
            };
            let b = map.bone.index();
            let inv = world.rotation[b].inverse();
            let at = |p: Vec3| map.rest + inv * (p - world.position[b]);
            dir[k] = inv * -n;
            hub[k] = at(wrist + hull.center);
            for (i, (p, _)) in balls.iter().enumerate() {
                let ([x, y, z], l) = (&mut base[k][i / LANES], i % LANES);
                let q = at(wrist + *p);
                (x[l], y[l], z[l]) = (q.x, q.y, q.z);
            }
        }
        // With the hand moved by -s n (in for s > 0): is the deepest ball deeper than 0
        // (`reaches(s, false)`), or at least 0 (`reaches(s, true)`)? Only the sign of the
        // deepest depth is asked, so the first ball that answers ends the search, and maps
        // the hand cannot be that deep in are not sampled.
        let reaches = |s: f32, or_zero: bool| -> bool {
            // The largest float below 0: a bound at most it is below 0.
            let floor = if or_zero { -f32::from_bits(1) } else { 0.0 };
            self.maps.iter().enumerate().any(|(k, map)| {
                let Some(map) = map.as_ref().filter(|_| only >> k & 1 != 0) else {
                    return false;
                };
                map.may_hold(hub[k] + dir[k] * s, hull.reach, floor)
                    && base[k].iter().enumerate().any(|(c, lanes)| {
                        let live = live(c);
                        if live == 0 {
                            return false;
                        }
                        let lanes = Lanes::along(lanes, margins[c], dir[k] * s);
                        let (d, some) = map.depths(&lanes, &[floor; LANES]);
                        let mut inside = [0u32; LANES];
                        for l in 0..LANES {
                            inside[l] = lane_bit(l, if or_zero { d[l] >= 0.0 } else { d[l] > 0.0 });
                        }
                        some & live & bits_of(inside) != 0
                    })
            })
        };
        // The deepest ball alone lands where its own depth along the move is 0: a few secant
        // steps on that one ball (its map, its rest-frame line) find it to a micrometer (from
        // outside, its first steps lie between 0 and that ball's own distance).
        let ball = self.maps[k0]
            .as_ref()
            .zip(balls.get(i0))
            .map(|(map, (_, margin))| {
                let [x, y, z] = &base[k0][i0 / LANES];
                let start = Vec3::new(x[i0 % LANES], y[i0 % LANES], z[i0 % LANES]);
                (map, start, *margin)
            });
        let along = |s: f32| {
            ball.and_then(|(map, start, margin)| {
                map.depth_rest(start + dir[k0] * s, margin, f32::NEG_INFINITY)
            })
        };
        let own_landing = || {
            let (mut s0, mut f0) = (0.0f32, d0);
            let mut s1 = -d0;
            for _ in 0..LAND_STEPS {
                let Some(f1) = along(s1) else { break };
                if f1.abs() <= LAND_TOLERANCE || f1 == f0 {
                    break;
                }
                let next = s1 - f1 * (s1 - s0) / (f1 - f0);
                (s0, f0, s1) = (s1, f1, next);
            }
            s1
        };
        let mut landing = None;
        if d0 < 0.0 && !reaches(hi, true) {
            // No ball inside at the bracket's far end: the hand misses the body along this
            // line, or passes through it (a hand far in front of a body thinner than its
            // distance: the far end is behind the body, and landing there put a hand 30 cm
            // before the man's chest 2 cm behind his back). Where the deepest ball's own
            // landing is found and that ball is inside just after it, the line enters the body
            // there: the bracket ends just past it, and the hand lands at the first crossing.
            let s1 = own_landing();
            let enters = along(s1).is_some_and(|f| f.abs() <= LAND_TOLERANCE)
                && (lo..=hi).contains(&s1)
                && along(s1 + LAND_CHECK).is_some_and(|f| f > 0.0);
            if !enters {
                return -n * hi;
            }
            hi = s1 + LAND_CHECK;
            landing = Some(s1);
        }
        if d0 >= 0.0 && reaches(lo, false) {
            return -n * lo;
        }
        // Where the deepest ball alone would land (moved by its depth along the normal) is
        // where the hand lands unless another ball comes first: when the landing lies within
        // a millimeter of it, that bracket needs 9 halvings; otherwise the whole one 16 (at
        // most twice the depth plus 1 cm), to a few micrometers either way (coarser, the
        // landing differed by a bisection step between the SIMD and the baseline builds: 2e-4
        // in the arm's rotations on `eat`).
        // When no other ball comes first (none inside just before the deepest ball's own
        // landing, one just after), that is the hand's landing, for 2 checks of the hand
        // instead of the 11-18 of a bisection.
        if let Some((map, start, margin)) = ball {
            let s1 = landing.unwrap_or_else(own_landing);
            // In just after: the deepest ball is inside there by construction, so it is asked
            // first (its map's bound, then its depth, as `reaches` asks them); the whole hand
            // only when it says no (`reaches` is true when any ball is).
            let after = s1 + LAND_CHECK;
            let first_in = || {
                only >> k0 & 1 != 0
                    && map.may_hold(hub[k0] + dir[k0] * after, hull.reach, 0.0)
                    && map
                        .depth_rest(start + dir[k0] * after, margin, 0.0)
                        .is_some_and(|d| d > 0.0)
            };
            if along(s1).is_some_and(|f| f.abs() <= LAND_TOLERANCE)
                && (lo..=hi).contains(&s1)
                && !reaches(s1 - LAND_CHECK, false)
                && (first_in() || reaches(after, false))
            {
                let total = -n * (s1 - LAND_CHECK);
                if total.is_finite() {
                    return total;
                }
            }
        }
        let mut halvings = 16;
        let guess = -d0;
        if (lo..=hi).contains(&guess)
            && !reaches(guess - NEAR_GUESS, false)
            && reaches(guess + NEAR_GUESS, false)
        {
            (lo, hi) = (guess - NEAR_GUESS, guess + NEAR_GUESS);
            halvings = 9;
        }
        for _ in 0..halvings {
            let mid = 0.5 * (lo + hi);
            if reaches(mid, false) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        let total = -n * lo;
        if total.is_finite() {
            total
        } else {
            Vec3::ZERO
        }
    }
}

/// Share of the spheres' radii that [`close`] brings together: the radii are the hand's
/// thicker parts (upper quartiles), so spheres just touching left the skins of touching hands
/// 13-17 mm apart (median) on the generated adults.
pub const CLOSE_RADII: f32 = 0.7;

/// One hand's balls in [`close`], world centers by coordinate (so that a hand's balls against
/// one of the other hand are a loop the compiler turns into vector instructions).
struct Balls {
    x: [f32; HAND_SPHERES],
    y: [f32; HAND_SPHERES],
    z: [f32; HAND_SPHERES],
    radius: [f32; HAND_SPHERES],
    n: usize,
}

impl Balls {
    fn of(wrist: Vec3, points: &[(Vec3, f32)]) -> Balls {
        let mut b = Balls {
            x: [0.0; HAND_SPHERES],
            y: [0.0; HAND_SPHERES],
            z: [0.0; HAND_SPHERES],
            radius: [0.0; HAND_SPHERES],
            n: points.len().min(HAND_SPHERES),
        };
        for (i, (p, r)) in points.iter().take(HAND_SPHERES).enumerate() {
            let at = wrist + *p;
            (b.x[i], b.y[i], b.z[i], b.radius[i]) = (at.x, at.y, at.z, *r);
        }
        b
    }

    fn at(&self, i: usize) -> Vec3 {
        Vec3::new(self.x[i], self.y[i], self.z[i])
    }
}

/// The translation `D` that closes the gap between two hands' spheres (centers relative to
/// their wrists `left` and `right`, world axes): with the left hand moved by `D / 2` and the
/// right by `-D / 2`, their nearest spheres touch (at [`CLOSE_RADII`] of their radii), along
/// the line between the spheres nearest now. Each pair of spheres touches where a quadratic
/// in the move says (the hands move along one line), so the first pair to touch on the way
/// in (or, for hands overlapping now, the last to part on the way out) is found exactly,
/// without a search. Zero when either hand has no spheres.
#[must_use]
pub fn close(left: Vec3, l: &[(Vec3, f32)], right: Vec3, r: &[(Vec3, f32)]) -> Vec3 {
    close_meeting(left, l, right, r).0
}

/// [`close`], and the pair of spheres nearest each other now (an index into `l`, one into
/// `r`), which sets the line the hands move along: where the hands meet. `None` with [`close`]'s
/// zero for hands without spheres.
#[must_use]
pub fn close_meeting(
    left: Vec3,
    l: &[(Vec3, f32)],
    right: Vec3,
    r: &[(Vec3, f32)],
) -> (Vec3, Option<(usize, usize)>) {
    // At most HAND_SPHERES balls a hand (more are not looked at).
    let (a, b) = (Balls::of(left, l), Balls::of(right, r));
    let n = b.n;
    // The pair with the smallest surface gap now sets the line (the first such pair in the
    // order of `l` then `r`): each ball of `l` against all of `r` at once, then the least.
    let (mut g0, mut best) = (f32::INFINITY, (0, 0));
    let mut gaps = [0.0f32; HAND_SPHERES];
    for i in 0..a.n {
        let (x, y, z, ra) = (a.x[i], a.y[i], a.z[i], a.radius[i]);
        for (j, g) in gaps[..n].iter_mut().enumerate() {
            let (dx, dy, dz) = (b.x[j] - x, b.y[j] - y, b.z[j] - z);
            *g = (dx * dx + dy * dy + dz * dz).sqrt() - CLOSE_RADII * (ra + b.radius[j]);
        }
        for (j, g) in gaps[..n].iter().enumerate() {
            if *g < g0 {
                (g0, best) = (*g, (i, j));
            }
        }
    }
    if !g0.is_finite() {
        return (Vec3::ZERO, None);
    }
    let u = (b.at(best.1) - a.at(best.0))
        .try_normalize()
        .unwrap_or(Vec3::Z);
    // With the hands moved together by s, a pair's centers are `d - s u` apart: they touch
    // for s in [b - w, b + w], b = d.u, w = sqrt(b^2 - |d|^2 + R^2) (no s when negative).
    // Hands apart now (g0 > 0): the smallest entry at or after 0 (at most g0, where the
    // nearest pair touches). Overlapping: the start of the run of overlapping s that holds
    // 0, found by extending it down over every pair's interval that meets it. The pairs'
    // intervals are worked out once, in the order of `l` then `r` (those with none left out).
    let mut spans = [(0.0f32, 0.0f32); HAND_SPHERES * HAND_SPHERES];
    let mut m = 0;
    let (mut enter, mut leave) = ([0.0f32; HAND_SPHERES], [0.0f32; HAND_SPHERES]);
    for i in 0..a.n {
        let (x, y, z, ra) = (a.x[i], a.y[i], a.z[i], a.radius[i]);
        for j in 0..n {
            let (dx, dy, dz) = (b.x[j] - x, b.y[j] - y, b.z[j] - z);
            let rr = CLOSE_RADII * (ra + b.radius[j]);
            let along = dx * u.x + dy * u.y + dz * u.z;
            let c = (dx * dx + dy * dy + dz * dz) - rr * rr;
            let w = (along * along - c).sqrt();
            // The smaller root without cancellation when b is large and c small.
            enter[j] = if along > 0.0 {
                c / (along + w)
            } else {
                along - w
            };
            leave[j] = along + w;
        }
        // No real root (NaN: the square root of a negative): no interval. Hands apart now
        // only look at entries at or after 0, overlapping ones at intervals starting below
        // the run (which starts at 0 and only goes down): the rest are never looked at.
        let below = if g0 > 0.0 { f32::INFINITY } else { 0.0 };
        for j in 0..n {
            if !leave[j].is_nan() && enter[j] < below {
                spans[m] = (enter[j], leave[j]);
                m += 1;
            }
        }
    }
    let spans = &spans[..m];
    let s = if g0 > 0.0 {
        let mut first = g0;
        for &(enter, leave) in spans {
            if leave >= 0.0 && enter < first {
                first = enter.max(0.0);
            }
        }
        first
    } else {
        let mut start = 0.0f32;
        // Each pass extends the run by the intervals that meet it; the run only grows, and
        // a few passes settle it (every pair is looked at each pass).
        for _ in 0..4 {
            let mut moved = false;
            for &(enter, leave) in spans {
                if leave >= start && enter < start {
                    start = enter;
                    moved = true;
                }
            }
            if !moved {
                break;
            }
        }
        start
    };
    let total = u * s;
    if total.is_finite() {
        (total, Some(best))
    } else {
        (Vec3::ZERO, None)
    }
}

#[cfg(all(test, not(target_arch = "wasm32")))]
mod tests {
    use super::*;

    /// A stream of numbers in `[0, 1)` from a seed (xorshift), for maps and balls made up
    /// whole from one proptest seed.
    struct Draw(u64);

    impl Draw {
        fn next(&mut self) -> f32 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 40) as f32 / (1u64 << 24) as f32
        }

        fn within(&mut self, lo: f32, hi: f32) -> f32 {
            lo + (hi - lo) * self.next()
        }

        fn around(&mut self, c: Vec3, r: f32) -> Vec3 {
            c + Vec3::new(self.within(-r, r), self.within(-r, r), self.within(-r, r))
        }
    }

    /// A body of random maps (the head's a sphere, the torso's cylinders; skin radii 3-12
    /// cm, rows of a cylinder's band 5-30), each bone posed at a random place and turn near
    /// the others, so that balls scattered among them are inside some, near others' skin
    /// and outside or beyond the band of the rest.
    fn body(d: &mut Draw) -> (BodySurface, WorldPose) {
        let mut world = WorldPose::default();
        let maps = core::array::from_fn(|k| {
            if d.next() < 0.2 {
                return None;
            }
            let bone = MAP_BONES[k];
            let (kind, rows) = if k == HEAD_MAP {
                (MapKind::Sphere, HEAD_ROWS)
            } else {
                (MapKind::Cylinder, 5 + (d.next() * 25.0) as usize)
            };
            let rest = d.around(Vec3::new(0.0, 1.3, 0.0), 0.2);
            let center = d.around(rest, 0.03);
            let mut map = RadialMap::empty(bone, kind, center, rest.y - d.within(0.0, 0.1), rows);
            for r in &mut map.radius {
                *r = d.within(0.03, 0.12);
            }
            map.measure_widest();
            map.rest = rest;
            let b = bone.index();
            world.position[b] = d.around(Vec3::new(0.0, 1.3, 0.0), 0.1);
            world.rotation[b] = Quat::from_xyzw(
                d.within(-1.0, 1.0),
                d.within(-1.0, 1.0),
                d.within(-1.0, 1.0),
                d.within(-1.0, 1.0),
            )
            .normalize();
            Some(map)
        });
        let surface = BodySurface {
            maps,
            finger_radius: [0.01; 2],
            palm_half: [0.015; 2],
            hand_excess: [[0.0; 2]; 2],
            head_samples: Vec::new(),
            samples: 0,
        };
        (surface, world)
    }

    /// Random balls among the maps (world), and a floor per lane: none, 0, or a depth.
    fn balls(d: &mut Draw) -> (Lanes, [f32; LANES]) {
        let mut b = Lanes::default();
        let mut floor = [0.0; LANES];
        for (l, floor) in floor.iter_mut().enumerate() {
            let c = d.around(Vec3::new(0.0, 1.3, 0.0), 0.3);
            (b.x[l], b.y[l], b.z[l], b.m[l]) = (c.x, c.y, c.z, d.within(0.004, 0.03));
            *floor = match (d.next() * 3.0) as u32 {
                0 => f32::NEG_INFINITY,
                1 => 0.0,
                _ => d.within(-0.05, 0.05),
            };
        }
        (b, floor)
    }

    proptest::proptest! {
        /// [`RadialMap::depths`] and [`BodySurface::deepest_lanes`], a map asked for LANES
        /// balls at once, give each ball's answer of [`RadialMap::depth_rest`] and
        /// [`BodySurface::deepest_rest`] asked one ball at a time, to the bit (the depth, the
        /// map, the point in its rest frame, and which balls have none), on random maps and
        /// balls inside, near and far from them.
        #[test]
        fn lanes_give_every_balls_answer_to_the_bit(seed in 1u64.., mask in 1u8..64) {
            let mut d = Draw(seed);
            let (surface, world) = body(&mut d);
            let (p, floor) = balls(&mut d);
            let axes = surface.axes(&world, mask);
            let (best, which, at) = surface.deepest_lanes(&p, 0xff, &world, mask, &axes, floor);
            for l in 0..LANES {
                let one = surface.deepest_rest(p.at(l), p.m[l], &world, mask, &axes, floor[l]);
                let lanes = (which[l] != u8::MAX)
                    .then(|| (best[l].to_bits(), at.at(l).to_array().map(f32::to_bits), usize::from(which[l])));
                let one = one.map(|(d, q, k)| (d.to_bits(), q.to_array().map(f32::to_bits), k));
                proptest::prop_assert_eq!(lanes, one, "ball {}", l);
            }
            for map in surface.maps.iter().flatten() {
                let b = map.bone.index();
                let inv = world.rotation[b].inverse();
                let mut q = p;
                for l in 0..LANES {
                    let r = map.rest + inv * (p.at(l) - world.position[b]);
                    (q.x[l], q.y[l], q.z[l]) = (r.x, r.y, r.z);
                }
                let (depth, some) = map.depths(&q, &floor);
                for l in 0..LANES {
                    let lanes = (some >> l & 1 != 0).then(|| depth[l].to_bits());
                    let one = map.depth_rest(q.at(l), q.m[l], floor[l]).map(f32::to_bits);
                    proptest::prop_assert_eq!(lanes, one, "ball {}", l);
                }
            }
        }
    }
}
