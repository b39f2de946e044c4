//! The **legs** stage: each leg from the pose's lower body ([`crate::legs`]) when its hip,
//! knee and ankle are seen (`legs.minVisibility`, inside the image), held then eased to the
//! standing rest pose when they are not, blended back in when they return (the dropout
//! timings of the arms, [`crate::filter::dropout`]). A head-and-shoulders webcam sees no legs:
//! they stay exactly at rest. Runs after the torso stage (the hips as posed); the observe stage
//! filtered the leg landmarks.

use glam::{Quat, Vec3};

use crate::filter::dropout::{Blend, Presence};
use crate::filter::PointFilters;
use crate::humanoid::bones::Side;
use crate::humanoid::skeleton::Skeleton;
use crate::input::mediapipe::PoseObservation;
use crate::legs::{leg_bones, leg_landmarks, Leg, LegRest, LegTarget, Soles};

use super::frame::{Context, Frame};
use super::output::SolveOutput;

/// Largest height (m) of a foot's lowest sole point above the floor, and speed (m/s) of its
/// tracked ankle, at which the foot counts as planted (bearing weight). A planted foot stays
/// planted until it rises past [`LIFT_HEIGHT`] or its tracked ankle moves faster than
/// [`LIFT_SPEED`] on two frames running: the gaps keep noise from planting and lifting it
/// frame to frame.
const PLANT_HEIGHT: f32 = 0.03;
const PLANT_SPEED: f32 = 0.5;
const LIFT_HEIGHT: f32 = 0.05;
const LIFT_SPEED: f32 = 0.6;
/// How long (ms) the hips take to follow the planted feet across (a time constant).
const FOLLOW_MS: f32 = 100.0;
/// How high (m) above the floor a planted foot's lowest sole may stay (its lock's height
/// follows the tracked foot's turn within this of the floor).
const HOVER: f32 = 0.01;
/// How fast two planted feet's locks slide toward their tracked ankles by what the hips
/// cannot take (a time constant, ms, and the largest speed, m/s).
const SLIDE_MS: f32 = 300.0;
const SLIDE_SPEED: f32 = 0.05;
const SLIDE_FREE: f32 = 0.01;
/// The user's own thigh length in the image (in torso lengths) is learned as this upper
/// quantile of its image length, at this rate (torso lengths per second), on the frames where
/// MediaPipe's world landmarks put the thigh within 5 degrees of the image plane (`OWN_FLAT`,
/// about the sine of 5 degrees: the image length is then the thigh's own within 0.4%; a thigh
/// they put deeper may be foreshortened for real, as the synthetic landmarks' standing thighs,
/// 6-14 degrees forward, are).
const OWN_QUANTILE: f32 = 0.9;
const OWN_RATE: f32 = 0.3;
const OWN_FLAT: f32 = 0.087;

/// The camera's pitch (`camera.pitch: null`) is estimated from the user's straight legs: the
/// lean in depth of the hips' midpoint to the ankles' midpoint in the world landmarks, on
/// frames where both legs are seen and each spans at least `STRAIGHT` of its thigh and shin
/// (the knee bent less than about 36 degrees), averaged over `TILT_SECONDS`, less
/// `LEVEL_LEAN`: the lean MediaPipe gives straight legs seen by a level camera (the bench's
/// woman, the tuning avatar: 7-9 degrees, the feet further than the hips).
const STRAIGHT: f32 = 0.95;
const TILT_SECONDS: f32 = 2.0;
const LEVEL_LEAN: f32 = 8.5 * (core::f32::consts::PI / 180.0);
/// The estimate's dead zone (radians): only its excess over this is taken out, so that a
/// level camera's legs are solved as they were (the woman's level leg clips: the estimate
/// within 1.7 degrees of `LEVEL_LEAN` throughout).
const TILT_FREE: f32 = 2.0 * (core::f32::consts::PI / 180.0);

/// The legs stage: per side the leg solver, its presence, the rotations shown last frame and
/// the blend's anchors; the grounding's state (the avatar's soles, the hips' offset, the
/// image reference of the root motion, each planted foot's lock).
#[derive(Clone, Debug)]
pub(super) struct Legs {
    legs: [Option<Leg>; 2],
    presence: [Presence; 2],
    shown: [[Quat; 4]; 2],
    anchor: [[Quat; 4]; 2],
    soles: Option<Soles>,
    /// The hips' offset shown last frame (internal frame).
    offset: Vec3,
    /// The hip midpoint in the image and the camera distance (m, user scale) when the root
    /// motion started (a leg seen after none was).
    reference: Option<(Vec3, f32)>,
    /// What the planted feet moved the hips across beyond the image's motion (x and z): the
    /// hips follow a planted foot, the image moves them while no foot is planted.
    drift: Vec3,
    /// How far the planted feet hold the hips above the floor's rule (m, eased).
    rise: f32,
    /// The planted feet the hips followed last frame, and what of their ask the hips have
    /// yet to take (a change of planted feet is eased over FOLLOW_MS, the tracked feet's
    /// motion under the same planted feet is followed at once).
    following: [bool; 2],
    carry: Vec3,
    /// Each tracked ankle last frame, the hips at rest (how far it moved from the hips).
    last_reach: [Option<Vec3>; 2],
    root_filter: PointFilters<1>,
    /// Each planted foot's ankle, world (with the offset); the tracked ankle last frame.
    lock: [Option<Vec3>; 2],
    last_ankle: [Option<Vec3>; 2],
    /// Each tracked ankle in the image last frame (x in heights).
    last_seen_ankle: [Option<Vec3>; 2],
    /// Each tracked ankle in the image two frames back, and the time between it and the last.
    before_seen_ankle: [Option<Vec3>; 2],
    last_dt: f32,
    /// Whether each tracked ankle moved at [`LIFT_SPEED`] or faster last frame.
    fast: [bool; 2],
    /// How each leg is read from the image.
    reading: [Reading; 2],
    /// The user's own thigh length in the image, in torso lengths (learned, [`target`]): one
    /// for both legs.
    own: Option<f32>,
    /// The straight legs' lean in depth in the world landmarks (radians, averaged over time;
    /// [`Legs::estimate_tilt`]) and the seconds of it seen, up to [`TILT_SECONDS`].
    tilt: f32,
    tilt_time: f32,
    /// The torso's image length (heights) on the last frame with a pose and on the last frame
    /// not held ([`Legs::held`]).
    torso: [f32; 2],
}

/// How one leg is read from the image: its thigh and shin directions' filters (the image
/// landmarks are not filtered with the world landmarks by the observe stage) and the user's
/// own thigh length in the image, in torso lengths (learned, [`target`]).
#[derive(Clone, Copy, Debug, Default)]
struct Reading {
    filter: PointFilters<2>,
}

impl Legs {
    pub(super) fn new(skeleton: &Skeleton) -> Self {
        Legs {
            legs: Side::BOTH.map(|side| Leg::new(skeleton, side)),
            presence: [Presence::default(); 2],
            shown: [[Quat::IDENTITY; 4]; 2],
            anchor: [[Quat::IDENTITY; 4]; 2],
            soles: Soles::new(skeleton),
            offset: Vec3::ZERO,
            reference: None,
            drift: Vec3::ZERO,
            rise: 0.0,
            following: [false; 2],
            carry: Vec3::ZERO,
            last_reach: [None; 2],
            root_filter: PointFilters::default(),
            lock: [None; 2],
            last_ankle: [None; 2],
            last_seen_ankle: [None; 2],
            before_seen_ankle: [None; 2],
            last_dt: 0.0,
            fast: [false; 2],
            reading: [Reading::default(); 2],
            own: None,
            tilt: LEVEL_LEAN,
            tilt_time: 0.0,
            torso: [f32::NAN; 2],
        }
    }

    pub(super) fn restart(&mut self) {
        for leg in self.legs.iter_mut().flatten() {
            leg.reset();
        }
        self.presence = [Presence::default(); 2];
        self.shown = [[Quat::IDENTITY; 4]; 2];
        self.anchor = [[Quat::IDENTITY; 4]; 2];
        self.offset = Vec3::ZERO;
        self.reference = None;
        self.drift = Vec3::ZERO;
        self.rise = 0.0;
        self.following = [false; 2];
        self.carry = Vec3::ZERO;
        self.last_reach = [None; 2];
        self.root_filter.reset();
        self.lock = [None; 2];
        self.last_ankle = [None; 2];
        self.last_seen_ankle = [None; 2];
        self.before_seen_ankle = [None; 2];
        self.last_dt = 0.0;
        self.fast = [false; 2];
        self.reading = [Reading::default(); 2];
        self.own = None;
        self.tilt = LEVEL_LEAN;
        self.tilt_time = 0.0;
        self.torso = [f32::NAN; 2];
    }

    /// Each leg's bones into `out.local` (solved, held, easing or at rest), the legs' world
    /// pose when any leg is off rest, the hips' offset and the planted feet.
    pub(super) fn run(&mut self, cx: &Context, f: &Frame, out: &mut SolveOutput) {
        let o = &cx.options.legs;
        if !o.enabled {
            return;
        }
        let timing = cx.options.dropout.effective();
        let pose = f.pose.as_ref();
        if self.held(cx, pose) {
            // Last frame's legs, hips and planted feet, the state untouched.
            for side in Side::BOTH {
                for (k, bone) in leg_bones(side).iter().enumerate() {
                    if cx.skeleton.has(*bone) {
                        out.local[bone.index()] = self.shown[side.index()][k];
                    }
                }
            }
            cx.skeleton.forward_body(&out.local, &mut out.world);
            out.hips_offset = self.offset;
            out.planted = self.lock.map(|l| l.is_some());
            return;
        }
        let mut targets = [None; 2];
        let hips = cx
            .skeleton
            .parent(leg_bones(Side::Left)[0])
            .map_or(Quat::IDENTITY, |p| out.world.rotation[p.index()]);
        // The camera's pitch taken out of the world landmarks (camera axes: about +x): as set,
        // or as estimated up to the last frame.
        let lean = self.tilt - LEVEL_LEAN;
        let pitch = (cx.options.camera.pitch).unwrap_or(lean - lean.clamp(-TILT_FREE, TILT_FREE));
        // The view is the same for both legs, and made only for a leg that is seen: a
        // head-and-shoulders frame sees none and pays nothing for it.
        let mut view = None;
        for side in Side::BOTH {
            if let (Some(leg), Some(p)) = (&self.legs[side.index()], pose) {
                if leg_seen(cx, p, side) {
                    let view = view.get_or_insert_with(|| {
                        // The camera's axes to the avatar's commute with a turn about +x (they
                        // negate y and z, and x too or not): the pitch goes into the turn.
                        let level = Quat::from_rotation_x(-pitch);
                        View {
                            turn: pelvis_turn(cx, p, hips, level) * level,
                            meters: meters_per_height(cx, p),
                        }
                    });
                    let reading = &mut self.reading[side.index()];
                    let own = &mut self.own;
                    targets[side.index()] =
                        target(cx, view, p, side, leg.lengths(), out, reading, own);
                }
            }
        }
        if let (Some(p), [Some(_), Some(_)]) = (pose, targets) {
            self.estimate_tilt(cx, p);
        }
        // A leg not seen while the other is shows its rest: its first detection blends in
        // from it (the real walking video: a knee shown at rest, then bent 93 degrees).
        if targets.iter().any(Option::is_some) {
            for (p, t) in self.presence.iter_mut().zip(&targets) {
                if t.is_none() {
                    p.shown_at_rest();
                }
            }
        }
        let blends = Side::BOTH.map(|side| {
            let live = targets[side.index()].is_some();
            self.presence[side.index()].update(cx.now_ms, live, &timing)
        });
        // Sideways and toward the camera: from the pose's image, filtered.
        let mut offset = self.offset;
        let across = match (o.move_hips && targets.iter().any(Option::is_some), pose) {
            (true, Some(p)) => self.across(cx, p),
            _ => None,
        };
        match across {
            Some(v) => (offset.x, offset.z) = (v.x + self.drift.x, v.z + self.drift.z),
            None => {
                // Not tracked: back to the rest position as the legs ease to rest.
                self.reference = None;
                self.drift = Vec3::ZERO;
                let k = cx.dt.map_or(1.0, |dt| {
                    (dt * 1000.0 / timing.fade_out_ms.max(1.0)).min(1.0)
                });
                offset.x -= k * offset.x;
                offset.z -= k * offset.z;
            }
        }
        // The legs as tracked, then the hips' height that puts the lower foot on the floor.
        let mut moved = false;
        for side in Side::BOTH {
            moved |= self.pose_leg(cx, side, targets[side.index()], &blends, out);
        }
        if moved {
            cx.skeleton.forward_body(&out.local, &mut out.world);
        }
        let soles = self.soles.filter(|_| o.move_hips);
        // The feet that stand the hips on the floor: those shown as tracked, both when none
        // is. A leg not seen shows a guess, held or easing to rest: it held a seen foot that
        // stood still up to 10 cm in the air (the real walking video's T13). A leg blending in
        // bears as far as it is blended in.
        let shown = [0, 1].map(|s| targets[s].is_some() && blends[s].is_exact());
        let alone = match shown {
            [true, false] => Some(0),
            [false, true] => Some(1),
            _ => None,
        };
        let bearing = alone.map_or([0, 1], |b| [b, b]);
        offset.y = match (moved, soles) {
            // Seated legs that are not seen leave the hips where they rest (on the chair).
            _ if o.rest == LegRest::Seated && targets.iter().all(Option::is_none) => {
                let k = cx.dt.map_or(1.0, |dt| {
                    (dt * 1000.0 / timing.fade_out_ms.max(1.0)).min(1.0)
                });
                offset.y - k * offset.y
            }
            (true, Some(soles)) => {
                let both = soles.floor - self.lowest(&soles, out, [0, 1]);
                match alone {
                    Some(b) if targets[1 - b].is_some() => {
                        let one = soles.floor - self.lowest(&soles, out, bearing);
                        one + blends[1 - b].weight.clamp(0.0, 1.0) * (both - one)
                    }
                    Some(_) => soles.floor - self.lowest(&soles, out, bearing),
                    None => both,
                }
            }
            _ => 0.0,
        };
        // Each tracked foot's height above the floor (a planted foot lifts when the tracked
        // one rises: after the re-solve below it stands on its lock).
        // (Read only for a tracked leg.)
        let heights = [0, 1].map(|s| match (soles, targets[s]) {
            (Some(soles), Some(_)) => self.lowest(&soles, out, [s, s]) + offset.y - soles.floor,
            _ => f32::INFINITY,
        });
        // A planted foot's ankle stays where it was put down: the hips low enough for the
        // leg to reach it, the leg solved again toward it. A tracked ankle moving fast lifts
        // it first.
        let tracked_ankle = targets.map(|t| t.map(|t| t.ankle + offset));
        // With the image, planting and lifting go by the ankle's speed across the image (at
        // the user's depth, in the avatar's scale; the image landmarks are not filtered): the
        // tracked ankle is filtered, lags a landing by 3-5 frames and moves with the leg's
        // depth as read, so a foot put down was planted late and slid meanwhile (the bench's
        // woman: 1.53 -> 0.30 mm of sliding per stance frame with the lock's height below).
        let seen_ankle = Side::BOTH.map(|side| {
            let image = cx.input.pose_image?;
            targets[side.index()]?;
            let [_, _, a, _, _] = leg_landmarks(cx.camera.pose_side_for(side));
            Some(Vec3::new(
                image[a].x * cx.input.image_aspect,
                image[a].y,
                0.0,
            ))
        });
        let to_meters = pose
            .filter(|_| seen_ankle.iter().any(Option::is_some))
            .and_then(|p| Some(meters_per_height(cx, p)? * self.scale(cx, p)?));
        // On the session's first frame no speed is known: a foot on the floor is planted
        // (else it moved, unlocked, while the next frame measured it: the bench's woman, 3-8
        // mm of sliding on the first frames of every clip).
        let mut speed = [if cx.dt.is_none() { 0.0 } else { f32::INFINITY }; 2];
        for s in 0..2 {
            // Over the last two frames: a jump there and back again moves the ankle nowhere.
            let mut away = true;
            if let (Some(a), Some(b), Some(dt), Some(m)) =
                (seen_ankle[s], self.last_seen_ankle[s], cx.dt, to_meters)
            {
                speed[s] = (a - b).length() * m / dt.max(1e-3);
                if let Some(c) = self.before_seen_ankle[s] {
                    away = (a - c).length() * m / (dt + self.last_dt).max(1e-3) >= LIFT_SPEED;
                }
            } else if let (Some(a), Some(b), Some(dt)) =
                (tracked_ankle[s], self.last_ankle[s], cx.dt)
            {
                speed[s] = (a - b).length() / dt.max(1e-3);
            }
            // A planted foot lifts by its speed only when it was fast the frame before too and
            // has moved away over both frames (or its speed is unknown): one frame's jump of
            // the image ankle lifted and planted it again (the bench's figure of primitives: 41
            // of its 50 lifts planted again within 2 frames, each a slide), and so did a still
            // foot's image jitter of 2-3 pixels back and forth at 10 frames a second (the real
            // walking video: a person 20 pixels from shoulders to hips).
            // (A leg not seen has no speed: its lock is kept or dropped below.)
            let fast = targets[s].is_some() && speed[s] >= LIFT_SPEED;
            if fast && ((self.fast[s] && away) || speed[s].is_infinite()) {
                self.lock[s] = None;
            }
            self.fast[s] = fast;
        }
        self.last_ankle = tracked_ankle;
        self.before_seen_ankle = self.last_seen_ankle;
        self.last_seen_ankle = seen_ankle;
        self.last_dt = cx.dt.unwrap_or(0.0);
        // A planted foot's lock stays within [`HOVER`] of the floor as the tracked foot turns
        // (its ankle no lower than where the tracked foot's lowest sole meets the floor, nor
        // more than HOVER above that): a foot planted early, up to PLANT_HEIGHT above the
        // floor, stayed there while the hips held its lock (the bench's woman: 46 of 480
        // frames with a standing foot over 2 cm above the floor, 0 with this).
        for s in 0..2 {
            if let (Some(lock), Some(a)) = (self.lock[s].as_mut(), tracked_ankle[s]) {
                if heights[s].is_finite() {
                    let floor = a.y - heights[s];
                    lock.y = lock.y.max(floor).min(floor + HOVER);
                }
            }
        }
        // The hips follow the planted feet across (the mean of what each lock asks, eased
        // over [`FOLLOW_MS`]: a foot lifting off hands the hips to the other without a jump):
        // the leg keeps its tracked shape, the IK below holds the foot on its lock. Re-solving
        // the leg toward a lock the image's hips motion disagrees with bent the knee (the
        // bench's sidestep).
        // Up and down too: the hips where the planted legs, as tracked, put their ankles on
        // their locks (the mean of both), never lower than the floor's rule (no sole under the
        // floor), eased the same. By the floor's rule alone, a foot lifting off handed the
        // hips' height to the other foot's tracked sole and lowered them under its lock, which
        // bent the planted knee (the bench's oneleg: the standing knee 4 degrees more bent
        // than as tracked).
        let (mut sum, mut n, mut low) = (Vec3::ZERO, 0.0, f32::INFINITY);
        for (lock, target) in self.lock.iter().zip(&targets) {
            if let (true, Some(lock), Some(t)) = (o.plant, lock, target) {
                sum += lock - t.ankle - offset;
                low = low.min(lock.y - t.ankle.y - offset.y);
                n += 1.0;
            }
        }
        let k = cx.dt.map_or(1.0, |dt| (dt * 1000.0 / FOLLOW_MS).min(1.0));
        let set = [0, 1].map(|s| o.plant && self.lock[s].is_some() && targets[s].is_some());
        if n > 0.0 && across.is_some() {
            let ask = Vec3::new(sum.x, 0.0, sum.z) / n;
            if set != self.following {
                self.carry = ask;
            }
            let d = ask - (1.0 - k) * self.carry;
            self.carry *= 1.0 - k;
            offset += d;
            self.drift += d;
        }
        self.following = set;
        // Two planted feet whose locks lie further apart (or closer, or turned) than the
        // tracked feet cannot both be met by moving the hips: the re-solve below would turn
        // each leg toward its lock. Each lock slides toward its tracked ankle by the part the
        // hips leave (what it asks less the mean of both), at most SLIDE_SPEED.
        let down = heights.iter().all(|h| *h < PLANT_HEIGHT);
        if n > 1.0 && down && across.is_some() && cx.dt.is_some() {
            let dt = cx.dt.unwrap_or(0.0);
            // What the locks ask less the part of their mean the hips did not take this
            // frame: their differential, and part of the frame's common tracked motion (which
            // the hips took at once). (The differential alone, `self.carry`, slid the
            // synthetic test's standing foot 2.1 mm while the other rose: the hips follow the
            // rising foot's ask at once and the standing leg cannot reach.)
            let mean = Vec3::new(sum.x, 0.0, sum.z) * ((1.0 - k) / n);
            // The feet share the slide as their tracked ankles move from the hips: a foot
            // that starts to lift takes it, the foot that stays does not.
            let moved = [0, 1].map(|s| match (targets[s], self.last_reach[s]) {
                (Some(t), Some(last)) => (t.ankle - last).length(),
                _ => 0.0,
            });
            let total = moved[0] + moved[1];
            let share = |s: usize| {
                if total > 0.0 {
                    2.0 * moved[s] / total
                } else {
                    1.0
                }
            };
            for (s, (lock, target)) in self.lock.iter_mut().zip(&targets).enumerate() {
                if let (Some(lock), Some(t)) = (lock.as_mut(), target) {
                    let ask = *lock - t.ankle - offset;
                    let e = Vec3::new(ask.x, 0.0, ask.z) - mean;
                    let step = (e.length() - SLIDE_FREE).max(0.0)
                        * share(s)
                        * (dt * 1000.0 / SLIDE_MS).min(1.0);
                    *lock -= e.normalize_or_zero() * step.min(SLIDE_SPEED * dt);
                }
            }
        }
        self.last_reach = targets.map(|t| t.map(|t| t.ankle));
        let up = if n > 0.0 && across.is_some() {
            low.max(0.0)
        } else {
            0.0
        };
        self.rise += k * (up - self.rise);
        offset.y += self.rise;
        let mut relocked = false;
        for side in Side::BOTH {
            let s = side.index();
            if let (true, Some(lock), Some(leg), Some(_)) =
                (o.plant, self.lock[s], &self.legs[s], targets[s])
            {
                let hip = out.world.position[leg_bones(side)[0].index()];
                // From the hip (in the room: moved by the offset across) to the lock.
                let d = lock - hip - Vec3::new(offset.x, 0.0, offset.z);
                let reach = leg.length();
                let level = reach * reach - d.x * d.x - d.z * d.z;
                if level > 0.0 {
                    offset.y = offset.y.min(d.y + level.sqrt());
                }
                relocked = true;
            }
        }
        if relocked {
            for side in Side::BOTH {
                let s = side.index();
                if let (Some(lock), Some(mut t)) = (self.lock[s], targets[s]) {
                    t.ankle = lock - offset;
                    self.pose_leg(cx, side, Some(t), &blends, out);
                }
            }
            cx.skeleton.forward_body(&out.local, &mut out.world);
            // No sole under the floor (a planted foot turned by its ankle may dip).
            if let Some(soles) = soles {
                offset.y = offset
                    .y
                    .max(soles.floor - self.lowest(&soles, out, bearing));
            }
        }
        // A leg not bearing while the other is: its foot kept out of the floor, the leg bent up
        // (its ankle raised by what its sole is under) with its foot turned as shown. A foot
        // planted when its leg was lost stays on its lock while the leg is held (not seen is
        // not lifted: the real walking video's T13, a man standing still with one knee hidden,
        // showed that leg held bent with its foot 5-7 cm up), while the leg reaches it.
        if let (Some(soles), Some(b)) = (soles, alone) {
            let s = 1 - b;
            let side = Side::BOTH[s];
            let bones = leg_bones(side);
            let at = |k: usize| out.world.position[bones[k].index()];
            let held = !blends[s].to_solved && blends[s].weight <= 0.0;
            let lock = self.lock[s].filter(|_| o.plant && held && targets[s].is_none());
            let reach = self.legs[s].as_ref().map_or(0.0, Leg::length);
            let under = soles.floor - self.lowest(&soles, out, [s, s]) - offset.y;
            let lock = lock.filter(|l| (*l - offset - at(0)).length() < reach);
            self.lock[s] = lock.or(self.lock[s].filter(|_| targets[s].is_some()));
            let goal = match lock {
                Some(l) => Some(l - offset),
                None => (under > 0.0).then(|| at(2) + Vec3::Y * under),
            };
            if let (Some(ankle), Some(leg)) = (goal, self.legs[s].as_mut()) {
                let t = LegTarget {
                    hip: at(0),
                    knee: at(1),
                    ankle,
                    foot: None,
                };
                let parent = cx.skeleton.parent(bones[0]).map_or(0, |p| p.index());
                let hips = out.world.rotation[parent];
                let solved = leg.solve(hips, &t);
                let [upper, lower, _] = solved.local;
                let turned = out.world.rotation[bones[2].index()];
                out.local[bones[0].index()] = upper;
                out.local[bones[1].index()] = lower;
                out.local[bones[2].index()] =
                    ((hips * upper * lower).conjugate() * turned).normalize();
                cx.skeleton.forward_body(&out.local, &mut out.world);
                // Where the leg cannot bend that far (its hip's range), the hips rise.
                offset.y = offset.y.max(soles.floor - self.lowest(&soles, out, [s, s]));
            }
        }
        // Commit what is shown.
        for side in Side::BOTH {
            for (k, bone) in leg_bones(side).iter().enumerate() {
                let q = out.local[bone.index()];
                let s = side.index();
                if blends[s].capture {
                    self.anchor[s][k] = self.shown[s][k];
                }
                self.shown[s][k] = q;
            }
        }
        if soles.is_none() {
            return;
        }
        // Planting: on the floor and slow; lifted when high or fast.
        for side in Side::BOTH {
            let s = side.index();
            let speed = speed[s];
            let height = heights[s];
            // A lock still held was not lifted by its speed above (two fast frames running).
            let planted = if self.lock[s].is_some() {
                height < LIFT_HEIGHT
            } else {
                height < PLANT_HEIGHT && speed < PLANT_SPEED
            };
            let ankle = out.world.position[leg_bones(side)[2].index()] + offset;
            // A lost leg's lock was kept or dropped above.
            if targets[s].is_some() || alone.is_none() {
                self.lock[s] = (o.plant && planted && targets[s].is_some())
                    .then(|| self.lock[s].unwrap_or(ankle));
            }
            out.planted[s] = self.lock[s].is_some();
        }
        self.offset = offset;
        out.hips_offset = offset;
    }

    /// Whether this frame's pose is held (last frame's legs shown, nothing learned from it): its
    /// torso's image length more than twice or less than half both last frame's and the last
    /// frame used, a leg seen. No body changes its distance or its torso's lean that much in one frame;
    /// MediaPipe's pose of such a frame is no person's (the real walking video, T15 578: the
    /// torso 33 -> 5 -> 30 px, the ankles above the hips, the thighs turned 150-160 degrees
    /// and back). A new size that stays is taken on its second frame.
    fn held(&mut self, cx: &Context, pose: Option<&PoseObservation>) -> bool {
        let (Some(p), Some(now)) = (pose, image_torso(cx)) else {
            return false;
        };
        let jump = |r: f32| !(0.5..=2.0).contains(&(now / r));
        let held = jump(self.torso[0])
            && jump(self.torso[1])
            && self.torso[1].is_finite()
            && Side::BOTH.into_iter().any(|side| leg_seen(cx, p, side));
        self.torso[0] = now;
        if !held {
            self.torso[1] = now;
        }
        held
    }

    /// The straight legs' lean in depth (the hips' midpoint to the ankles', world landmarks,
    /// camera axes) averaged into [`Legs::tilt`]: a running mean over the first
    /// [`TILT_SECONDS`] of frames with both legs seen and nearly straight, then an exponential
    /// average with that time constant.
    fn estimate_tilt(&mut self, cx: &Context, pose: &PoseObservation) {
        let w = &pose.world;
        let [lh, lk, la, ..] = leg_landmarks(Side::Left);
        let [rh, rk, ra, ..] = leg_landmarks(Side::Right);
        let straight = |h: usize, k: usize, a: usize| {
            w[h].distance(w[a]) >= STRAIGHT * (w[h].distance(w[k]) + w[k].distance(w[a]))
        };
        let d = w[la] + w[ra] - w[lh] - w[rh];
        if !(straight(lh, lk, la) && straight(rh, rk, ra) && d.y > 0.0) {
            return;
        }
        let lean = d.z.atan2(d.y);
        self.tilt_time = (self.tilt_time + cx.dt.unwrap_or(0.0)).min(TILT_SECONDS);
        let k = cx.dt.map_or(1.0, |dt| dt / self.tilt_time.max(dt));
        if lean.is_finite() && k.is_finite() {
            self.tilt += k.min(1.0) * (lean - self.tilt);
        }
    }

    /// Solves `side`'s leg toward `target` (none: rest) and writes it into `out.local` as
    /// `blends` shows it (the history is committed by [`Legs::run`]). Whether it is off rest.
    // Out of line: called from two places per side (inlined, 2 KiB more .wasm).
    #[inline(never)]
    fn pose_leg(
        &mut self,
        cx: &Context,
        side: Side,
        target: Option<LegTarget>,
        blends: &[Blend; 2],
        out: &mut SolveOutput,
    ) -> bool {
        let s = side.index();
        let Some(leg) = self.legs[s].as_mut() else {
            return false;
        };
        let bones = leg_bones(side);
        let parent = cx.skeleton.parent(bones[0]).map_or(0, |p| p.index());
        let mut solved = [Quat::IDENTITY; 4];
        if let Some(t) = &target {
            solved[..3].copy_from_slice(&leg.solve(out.world.rotation[parent], t).local);
        }
        let rest = leg.rest_pose(cx.options.legs.rest);
        let mut moved = false;
        for (k, bone) in bones.iter().enumerate() {
            let mut anchor = self.anchor[s][k];
            let q = blends[s].show_with_rest(solved[k], rest[k], &mut anchor, self.shown[s][k]);
            if cx.skeleton.has(*bone) {
                out.local[bone.index()] = q;
                out.solved[bone.index()] = target.is_some();
                moved |= q != Quat::IDENTITY;
            }
        }
        moved
    }

    /// The height of the lowest sole point of the feet `sides` (indices) as posed in `out`,
    /// the hips at rest.
    fn lowest(&self, soles: &Soles, out: &SolveOutput, sides: [usize; 2]) -> f32 {
        sides
            .map(|s| {
                let side = Side::BOTH[s];
                let foot = leg_bones(side)[2].index();
                soles
                    .lowest(side, out.world.position[foot], out.world.rotation[foot])
                    .y
            })
            .into_iter()
            .fold(f32::INFINITY, f32::min)
    }

    /// The user's legs scaled to the avatar's (the first tracked leg's ratio).
    fn scale(&self, cx: &Context, pose: &PoseObservation) -> Option<f32> {
        let w = &pose.world;
        Side::BOTH.into_iter().find_map(|side| {
            let leg = self.legs[side.index()].as_ref()?;
            let [h, k, a, _, _] = leg_landmarks(cx.camera.pose_side_for(side));
            let user = w[h].distance(w[k]) + w[k].distance(w[a]);
            (user > 1e-3).then(|| leg.length() / user)
        })
    }

    /// The hips' sideways and forward offset (avatar scale, internal frame) from the hip
    /// midpoint's image position and the camera distance the pose's size gives, relative to
    /// where the root motion started; `None` without image landmarks or a measurable torso.
    fn across(&mut self, cx: &Context, pose: &PoseObservation) -> Option<Vec3> {
        use crate::input::mediapipe::pose_landmark as pl;
        let image = cx.input.pose_image?;
        let mid = |a: usize, b: usize, p: &[Vec3; 33]| 0.5 * (p[a] + p[b]);
        let hip = mid(pl::LEFT_HIP, pl::RIGHT_HIP, &image);
        let aspect = cx.input.image_aspect;
        let meters = meters_per_height(cx, pose).unwrap_or(f32::NAN);
        let fov = cx.options.hands_only.fov;
        // tan(fov / 2) by sin and cos: libm's tanf is 1 KiB of .wasm the rig has no other use for.
        let distance = meters * (0.5 * fov).cos() / (2.0 * (0.5 * fov).sin());
        if !(meters.is_finite() && meters > 0.0) {
            return None;
        }
        let (at, d0) = *self.reference.get_or_insert((hip, distance));
        let scale = self.scale(cx, pose)?;
        let x = (hip.x - at.x) * aspect * meters;
        let x = if cx.camera.flips_x() { -x } else { x };
        let mut v = [Vec3::new(x, 0.0, d0 - distance) * scale];
        if cx.options.filter.enabled {
            let o = cx.options.filter.one_euro();
            self.root_filter.apply(&mut v, cx.now_ms, cx.dt, &o);
        }
        v[0].is_finite().then_some(v[0])
    }
}

/// The turn from the user's pelvis to the avatar's hips (world rotation `hips`), about the
/// vertical only: the hip line's yaw. The upper torso's turn, which places the arms, also takes
/// out the lean MediaPipe's depth gives the shoulders over the hips of a user standing
/// upright (its world landmarks put a rendered avatar's shoulders behind its hips); the legs
/// hang from the pelvis, and turned by that lean they leaned forward (the ground-truth bench's
/// leg clips, docs/measurements/2026-12-06-legs-bench.md).
fn pelvis_turn(cx: &Context, pose: &PoseObservation, hips: Quat, level: Quat) -> Quat {
    let [l, ..] = leg_landmarks(cx.camera.pose_side_for(Side::Left));
    let [r, ..] = leg_landmarks(cx.camera.pose_side_for(Side::Right));
    let d = level * cx.camera.to_avatar(pose.world[l] - pose.world[r]);
    let yaw = |v: Vec3| (-v.z).atan2(v.x);
    let user = if d.x.hypot(d.z) >= crate::torso::MIN_HIP_WIDTH {
        yaw(d)
    } else {
        0.0
    };
    Quat::from_rotation_y(yaw(hips * Vec3::X) - user)
}

/// The torso's world length (m): shoulder midpoint to hip midpoint.
fn torso_length(pose: &PoseObservation) -> f32 {
    use crate::input::mediapipe::pose_landmark as pl;
    let w = &pose.world;
    (0.5 * (w[pl::LEFT_SHOULDER] + w[pl::RIGHT_SHOULDER] - w[pl::LEFT_HIP] - w[pl::RIGHT_HIP]))
        .length()
}

/// Meters per image height at the user's depth: the torso's world length (shoulder midpoint
/// to hip midpoint) over its image length (x in widths, y in heights); `None` without image
/// landmarks or a measurable torso.
fn meters_per_height(cx: &Context, pose: &PoseObservation) -> Option<f32> {
    let meters = chord(&pose.world).length() / image_torso(cx)?;
    (meters.is_finite() && meters > 0.0).then_some(meters)
}

/// The torso's chord: shoulder midpoint less hip midpoint.
fn chord(p: &[Vec3; 33]) -> Vec3 {
    use crate::input::mediapipe::pose_landmark as pl;
    let mid = |a: usize, b: usize| 0.5 * (p[a] + p[b]);
    mid(pl::LEFT_SHOULDER, pl::RIGHT_SHOULDER) - mid(pl::LEFT_HIP, pl::RIGHT_HIP)
}

/// The torso's image length (shoulder midpoint to hip midpoint, x in widths, y in heights,
/// measured in heights); `None` without image landmarks.
fn image_torso(cx: &Context) -> Option<f32> {
    let d = chord(&cx.input.pose_image?);
    Some((d.x * cx.input.image_aspect).hypot(d.y))
}

/// How the user's leg segments are read on a frame: the pelvis' turn and the image's scale
/// (meters per image height), when the image is given.
struct View {
    /// The camera's pitch taken out, then the pelvis' turn.
    turn: Quat,
    meters: Option<f32>,
}

impl View {
    /// The user's segment from landmark `a` to `b` in the avatar's world axes, its world
    /// length. With the image: across and up as the image shows it (MediaPipe's world
    /// landmarks put a squatting user's thighs straight down, and a raised knee's thigh at
    /// full length below the hip, where the image shows them foreshortened), its depth
    /// MediaPipe's, bounded by the depth the image leaves ([`depth`]).
    ///
    /// The depth is not taken from the image's foreshortening: the image's scale (the torso's
    /// world length over its image length) does not hold for the legs of every body (the
    /// bench's man standing still: his thighs read 5-8% short, 20-30 degrees deep, the knees
    /// 19 cm forward). On the bench, MediaPipe's bounded depth put the knee 15-30 mm from the
    /// truth (median, thigh alone) where the foreshortening's put it 34-82 mm
    /// (docs/measurements/2026-12-06-legs-bench.md, third session).
    ///
    /// `own`: the user's own length of the segment in the image (m, at the torso's scale),
    /// which then bounds the depth in place of its world length: MediaPipe's depth of a
    /// standing thigh is 10-20 degrees and the torso's scale reads it a few percent short, so
    /// the bound let it through (sixth session).
    fn segment(
        &self,
        cx: &Context,
        pose: &PoseObservation,
        a: usize,
        b: usize,
        own: Option<f32>,
    ) -> Vec3 {
        let world = pose.world[b] - pose.world[a];
        let to_world = |v: Vec3| self.turn * cx.camera.to_avatar(v);
        let (Some(image), Some(m)) = (cx.input.pose_image, self.meters) else {
            return to_world(world);
        };
        let d = image[b] - image[a];
        let across = Vec3::new(d.x * cx.input.image_aspect * m, d.y * m, 0.0);
        let z = depth(own.unwrap_or(world.length()), across.length());
        to_world(across + Vec3::Z * world.z.clamp(-z, z))
    }
}

/// The depth (m) a segment of `length` has when `across` of it is seen in the image.
fn depth(length: f32, across: f32) -> f32 {
    (length * length - across * across).max(0.0).sqrt()
}

/// Whether pose landmark `i` is seen: visible enough and inside the image (MediaPipe guesses a
/// leg below the frame's edge with a visibility up to 0.84 on the ASL clips).
// Out of line: called for five landmarks per leg (inlined, more .wasm).
#[inline(never)]
fn seen(cx: &Context, pose: &PoseObservation, i: usize) -> bool {
    let inside = |x: f32| (0.0..=1.0).contains(&x);
    pose.visibility[i] >= cx.options.legs.min_visibility
        && cx
            .input
            .pose_image
            .is_none_or(|im| inside(im[i].x) && inside(im[i].y))
}

/// Whether the hip, knee and ankle of the avatar's `side` are seen ([`seen`]).
fn leg_seen(cx: &Context, pose: &PoseObservation, side: Side) -> bool {
    let [hip, knee, ankle, _, _] = leg_landmarks(cx.camera.pose_side_for(side));
    seen(cx, pose, hip) && seen(cx, pose, knee) && seen(cx, pose, ankle)
}

/// Where the tracked leg of the avatar's `side` puts it (the user's thigh and shin directions,
/// read as `view` says, with the avatar's thigh and shin `lengths`), or `None` when its
/// direction is not finite. For a leg that is seen ([`leg_seen`]).
#[allow(clippy::too_many_arguments)]
fn target(
    cx: &Context,
    view: &View,
    pose: &PoseObservation,
    side: Side,
    lengths: (f32, f32),
    out: &SolveOutput,
    reading: &mut Reading,
    own: &mut Option<f32>,
) -> Option<LegTarget> {
    let [hip, knee, ankle, heel, toe] = leg_landmarks(cx.camera.pose_side_for(side));
    let at_hip = out.world.position[leg_bones(side)[0].index()];
    let w = &pose.world;
    let vector = |v| view.turn * cx.camera.to_avatar(v);
    // Each of the user's segments along its direction with the avatar's length: the knee's
    // angle and the leg's direction are the user's (the IK bends the knee forwards, the
    // hinge and the hip's ranges limit it).
    // The user's own thigh length in the image, learned as an upper quantile of its image
    // length while MediaPipe's world landmarks show the thigh in the image plane (a leg never
    // seen so keeps the bound by its world length). The shin's is not learned: at a
    // shin's 10-25 degrees of MediaPipe depth a bent leg's shin cannot be told from a
    // straight one (sixth session).
    let torso = torso_length(pose);
    if let (Some(image), Some(m)) = (cx.input.pose_image, view.meters) {
        let thigh = w[knee] - w[hip];
        let d = image[knee] - image[hip];
        let r = (d.x * cx.input.image_aspect).hypot(d.y) * m / torso;
        if thigh.z.abs() < OWN_FLAT * thigh.length() && r.is_finite() {
            let q = own.get_or_insert(r);
            let below = if r < *q { 1.0 } else { 0.0 };
            // Both legs feed it: each at half the rate.
            *q += 0.5 * OWN_RATE * cx.dt.unwrap_or(0.0) * (OWN_QUANTILE - below);
        }
    }
    let thigh_dir = view.segment(cx, pose, hip, knee, own.map(|q| q * torso));
    let shin = w[ankle].distance(w[knee]);
    let own_shin = own.map(|q| (q * torso * shin / w[knee].distance(w[hip])).min(shin));
    let shin_dir = view.segment(cx, pose, knee, ankle, own_shin);
    let mut dirs = [thigh_dir, shin_dir];
    if cx.options.filter.enabled && view.meters.is_some() && cx.input.pose_image.is_some() {
        let o = cx.options.filter.one_euro();
        reading.filter.apply(&mut dirs, cx.now_ms, cx.dt, &o);
    }
    let (thigh, shin) = lengths;
    let knee_at = at_hip + thigh * dirs[0].try_normalize()?;
    let ankle_at = knee_at + shin * dirs[1].try_normalize()?;
    let t = LegTarget {
        hip: at_hip,
        knee: knee_at,
        ankle: ankle_at,
        foot: (seen(cx, pose, heel) && seen(cx, pose, toe)).then(|| vector(w[toe] - w[heel])),
    };
    (t.knee.is_finite() && t.ankle.is_finite()).then_some(t)
}
