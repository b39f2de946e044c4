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
        points.iter().fold(floor, |best, (p, margin)| {
            match self.deepest_rest(wrist + *p, *margin, world, mask, &axes, best) {
                Some((d, ..)) if d > best => d,
                _ => best,
            }
        })
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
            for (p, margin) in points {
                if let Some((d, n, _)) =
                    self.depth_in(wrist + *p + total, *margin, world, mask, &axes, 0.0)
                {
                    if d > 0.0 {
                        total += n * d;
                        moved = true;
                        mask = self.near(wrist + hull.center + total, hull.reach, world, all, 0.0);
                        axes = self.axes(world, mask);
                    }
                }
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
            for (i, (p, margin)) in points.iter().enumerate() {
                let floor = best.map_or(least, |(bd, ..)| bd.max(least));
                if let Some((d, q, k)) =
                    self.deepest_rest(wrist + *p + shift, *margin, world, mask, &axes, floor)
                {
                    if best.is_none_or(|(bd, ..)| d > bd) {
                        best = Some((d, q, k, i));
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
        let mut base = [[Vec3::ZERO; HAND_SPHERES]; MAP_BONES.len()];
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
            for (q, (p, _)) in base[k].iter_mut().zip(balls) {
                *q = at(wrist + *p);
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
                    && base[k].iter().zip(balls).any(|(q, (_, margin))| {
                        map.depth_rest(*q + dir[k] * s, *margin, floor)
                            .is_some_and(|d| if or_zero { d >= 0.0 } else { d > 0.0 })
                    })
            })
        };
        if d0 < 0.0 && !reaches(hi, true) {
            return -n * hi;
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
        // The deepest ball alone lands where its own depth along the move is 0: a few secant
        // steps on that one ball (its map, its rest-frame line) find it to a micrometer.
        // When no other ball comes first (none inside just before it, one just after), that
        // is the hand's landing, for 2 checks of the hand instead of the 11-18 of a bisection.
        if let (Some(map), Some((_, margin))) = (self.maps[k0].as_ref(), balls.get(i0)) {
            let along =
                |s: f32| map.depth_rest(base[k0][i0] + dir[k0] * s, *margin, f32::NEG_INFINITY);
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
            // In just after: the deepest ball is inside there by construction, so it is asked
            // first (its map's bound, then its depth, as `reaches` asks them); the whole hand
            // only when it says no (`reaches` is true when any ball is).
            let after = s1 + LAND_CHECK;
            let first_in = || {
                only >> k0 & 1 != 0
                    && map.may_hold(hub[k0] + dir[k0] * after, hull.reach, 0.0)
                    && map
                        .depth_rest(base[k0][i0] + dir[k0] * after, *margin, 0.0)
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
