//! Live-tracking smoothing: One Euro filtering of what drives the avatar, and easing over
//! tracking loss.
//!
//! ## What is filtered, and why there
//!
//! handrig filters its **inputs** (hand landmarks per avatar side, the pose landmarks, wrists
//! from other trackers), not its output rotations. Every later stage then works on the smoothed
//! data in the same frame, so the relations handrig promises hold exactly on what is shown:
//! fingertip alignment puts the avatar's finger on the target computed from the same smoothed
//! hand, the arm IK reaches that target, joint limits hold. Filtering output rotations instead
//! would smooth each bone on its own and break those relations (the finger would trail its
//! target). Rotations derived from smoothed points are smooth, and never flip: points have no
//! sign ambiguity. The one rotation input (`wrists.*.rotation`) is filtered on the sphere,
//! always the short way ([`OneEuroQuat`]).
//!
//! Losses are eased on the output side ([`dropout`]): a lost group holds, then eases to rest,
//! and blends back in when found again.
//!
//! ## Time
//!
//! Filters are driven by the frame's `timeMs` through a [`Clock`]: the step is the time since
//! the previous frame. A repeated timestamp (or none: `timeMs` left at 0 every frame) counts as
//! one frame at 30 fps, so an app that never sets the time still gets smoothing; a timestamp
//! that goes backwards, or jumps more than a second ahead, starts the filters afresh (a new
//! session, a seek in a recording).

pub mod dropout;
pub mod one_euro;

use glam::Vec3;

pub(crate) use dropout::nlerp;
pub use dropout::{Blend, DropoutOptions, Presence};
pub use one_euro::{OneEuroOptions, OneEuroQuat, OneEuroVec3};

/// Landmark smoothing (JS: `options.filter`; `filter: false` turns it off).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterOptions {
    /// Whether landmarks are filtered. Default `true`.
    pub enabled: bool,
    /// One Euro cutoff at rest (Hz). Default 1.5.
    pub min_cutoff: f32,
    /// One Euro speed coefficient (Hz per m/s of landmark speed). Default 2.
    pub beta: f32,
    /// Cutoff of the speed estimate (Hz). Default 1.
    pub d_cutoff: f32,
}

impl FilterOptions {
    /// The One Euro parameters.
    #[must_use]
    pub fn one_euro(&self) -> OneEuroOptions {
        OneEuroOptions {
            min_cutoff: self.min_cutoff,
            beta: self.beta,
            d_cutoff: self.d_cutoff,
        }
    }
}

/// Step used for a frame whose timestamp repeats the previous one (s): one frame at 30 fps.
pub const REPEATED_FRAME_DT: f32 = 1.0 / 30.0;

/// Longest step filtered across (ms); a longer gap, or a step back, restarts the filters.
pub const MAX_STEP_MS: f64 = 1000.0;

/// The time step between frames from their `timeMs`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Clock {
    last: Option<f64>,
}

impl Clock {
    /// Advances to `time_ms`: `Some(dt)` in seconds to filter across, or `None` when the
    /// filters must restart (first frame, time going backwards, a gap over [`MAX_STEP_MS`]).
    pub fn advance(&mut self, time_ms: f64) -> Option<f32> {
        let last = self.last.replace(time_ms)?;
        let step = time_ms - last;
        if step == 0.0 {
            Some(REPEATED_FRAME_DT)
        } else if step > 0.0 && step <= MAX_STEP_MS {
            Some((step / 1000.0) as f32)
        } else {
            None
        }
    }

    /// Forgets the last time.
    pub fn reset(&mut self) {
        self.last = None;
    }
}

/// One Euro filters for a fixed set of points (one hand's 21 landmarks, the 33 pose
/// landmarks), with the time the set was last seen so that a set that comes back after a
/// gap starts afresh instead of smoothing from where it was lost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointFilters<const N: usize> {
    points: [OneEuroVec3; N],
    seen: Option<f64>,
}

impl<const N: usize> Default for PointFilters<N> {
    fn default() -> Self {
        PointFilters {
            points: [OneEuroVec3::default(); N],
            seen: None,
        }
    }
}

impl<const N: usize> PointFilters<N> {
    /// Filters `points` in place, seen at `time_ms`, `dt` seconds after the previous frame
    /// (`None`: restart). A set unseen for more than [`MAX_STEP_MS`] restarts too.
    #[inline(never)] // (one copy per set size in the .wasm, not one per caller)
    pub fn apply(
        &mut self,
        points: &mut [Vec3; N],
        time_ms: f64,
        dt: Option<f32>,
        o: &OneEuroOptions,
    ) {
        let step = self.step(time_ms, dt, o);
        for (p, f) in points.iter_mut().zip(self.points.iter_mut()) {
            *p = f.filter_step(*p, step.as_ref(), o);
        }
    }

    /// [`PointFilters::apply`] on the points at `only` (indices below `N`; others are left as
    /// given and their filters untouched): for a set of which a caller reads a few points.
    pub fn apply_to(
        &mut self,
        points: &mut [Vec3; N],
        only: &[usize],
        time_ms: f64,
        dt: Option<f32>,
        o: &OneEuroOptions,
    ) {
        let step = self.step(time_ms, dt, o);
        for &k in only {
            if let (Some(p), Some(f)) = (points.get_mut(k), self.points.get_mut(k)) {
                *p = f.filter_step(*p, step.as_ref(), o);
            }
        }
    }

    /// The step to filter this sighting across; `None` restarts the filters (each restarts
    /// at its next sample: [`OneEuroVec3::filter_step`] with no step).
    fn step(
        &mut self,
        time_ms: f64,
        dt: Option<f32>,
        o: &OneEuroOptions,
    ) -> Option<one_euro::Step> {
        let previous = self.seen.replace(time_ms);
        let dt = match (dt, previous) {
            (Some(dt), Some(seen)) if time_ms >= seen && time_ms - seen <= MAX_STEP_MS => {
                // A set that skipped frames is filtered across the whole gap since it was
                // last seen; a repeated timestamp takes the clock's step.
                let since = ((time_ms - seen) / 1000.0) as f32;
                if since > 0.0 {
                    since
                } else {
                    dt
                }
            }
            _ => 0.0,
        };
        one_euro::Step::new(dt, o)
    }

    /// Forgets the history.
    pub fn reset(&mut self) {
        *self = Self::default();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clock_steps_repeats_and_restarts() {
        let mut c = Clock::default();
        assert_eq!(c.advance(1000.0), None, "first frame");
        assert_eq!(c.advance(1033.0), Some(0.033));
        assert_eq!(c.advance(1033.0), Some(REPEATED_FRAME_DT), "repeated");
        assert_eq!(c.advance(1000.0), None, "backwards");
        assert_eq!(c.advance(3000.0), None, "a gap over a second");
        assert_eq!(c.advance(3016.0), Some(0.016));
        c.reset();
        assert_eq!(c.advance(0.0), None);
        assert_eq!(
            c.advance(0.0),
            Some(REPEATED_FRAME_DT),
            "no timestamps at all"
        );
    }

    #[test]
    fn point_sets_restart_after_a_gap() {
        let o = FilterOptions::default().one_euro();
        let mut f = PointFilters::<2>::default();
        let mut p = [Vec3::ZERO, Vec3::ONE];
        f.apply(&mut p, 0.0, None, &o);
        let mut q = [Vec3::X, Vec3::ONE];
        f.apply(&mut q, 33.0, Some(0.033), &o);
        assert!(q[0].x > 0.0 && q[0].x < 0.9, "smoothed: {}", q[0]);
        // Seen again 2 s later: no smoothing from the old position.
        let mut r = [Vec3::Y, Vec3::ONE];
        f.apply(&mut r, 2033.0, Some(0.033), &o);
        assert_eq!(r[0], Vec3::Y);
    }

    #[test]
    fn a_subset_filters_like_the_whole_set_and_leaves_the_rest() {
        let o = FilterOptions::default().one_euro();
        let (mut all, mut some) = (PointFilters::<3>::default(), PointFilters::<3>::default());
        let only = [0, 2, 7]; // 7: out of range, ignored
        for (t, x) in [
            (0.0, 0.0),
            (33.0, 1.0),
            (66.0, 0.5),
            (3000.0, 2.0),
            (3033.0, 1.0),
        ] {
            let frame = [Vec3::splat(x), Vec3::splat(-x), Vec3::splat(2.0 * x)];
            let (mut a, mut b) = (frame, frame);
            let dt = (t > 0.0 && t != 3000.0).then_some(0.033);
            all.apply(&mut a, t, dt, &o);
            some.apply_to(&mut b, &only, t, dt, &o);
            assert_eq!(
                [b[0], b[2]],
                [a[0], a[2]],
                "t = {t}: the listed points as filtered"
            );
            assert_eq!(b[1], frame[1], "t = {t}: the unlisted point as given");
            // Smoothed between samples, restarted after the gap.
            assert_eq!(
                b[0] == frame[0],
                t == 0.0 || t == 3000.0,
                "t = {t}: {}",
                b[0]
            );
        }
    }
}
