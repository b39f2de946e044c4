//! Tracking loss, softened: a group of bones (one hand's fingers, one arm) holds its last pose
//! for a while when its tracking disappears, then eases to rest; when tracking returns it
//! blends in from wherever it was shown, instead of snapping.
//!
//! [`Presence`] is the state machine of one group; it says which pose to show as a blend
//! `slerp(anchor, target, weight)`: the anchor is the pose shown when tracking changed (the
//! caller captures it when told to), the target is this frame's solve while tracking is live
//! and the rest pose (identity) while it is lost. Times are the frame's `timeMs`.

use glam::Quat;

/// Timings of the hold and the easing (JS: `options.dropout`). XR Animator uses 250 ms in and
/// 500 ms out; handrig holds a lost group 250 ms first, which bridges MediaPipe's short
/// dropouts (a few frames) without any motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DropoutOptions {
    /// Whether lost groups hold and ease (`false`: they snap to rest, and returning ones snap
    /// in). Default `true`.
    pub enabled: bool,
    /// How long a lost group keeps its last pose (ms). Default 250.
    pub hold_ms: f32,
    /// How long it then takes to ease to rest (ms). Default 500.
    pub fade_out_ms: f32,
    /// How long a returning group blends from the shown pose to the solved one (ms). Default 250.
    pub fade_in_ms: f32,
}

impl DropoutOptions {
    /// No hold, no easing: lost groups snap to rest and returning ones snap in (handrig
    /// before the easing; also what `dropout: false` gives).
    pub const OFF: DropoutOptions = DropoutOptions {
        enabled: false,
        hold_ms: 0.0,
        fade_out_ms: 0.0,
        fade_in_ms: 0.0,
    };

    /// The timings in force: [`DropoutOptions::OFF`]'s when disabled.
    #[must_use]
    pub fn effective(&self) -> DropoutOptions {
        if self.enabled {
            *self
        } else {
            Self::OFF
        }
    }
}

/// What to show this frame for one group: `slerp(anchor, target, weight)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Blend {
    /// Capture the group's currently shown pose as the anchor first (tracking just changed).
    pub capture: bool,
    /// The target is this frame's solve (`true`) or the rest pose (`false`).
    pub to_solved: bool,
    /// 0 shows the anchor, 1 the target.
    pub weight: f32,
}

impl Blend {
    /// Whether the target is shown as it is (nothing to blend).
    #[must_use]
    pub fn is_exact(&self) -> bool {
        self.weight >= 1.0
    }

    /// The rotation to show for one bone of the group: `solved` (or rest, identity) eased in
    /// from `anchor`, which is first set to `shown` (last frame's rotation) on a capture; in
    /// the hemisphere of `shown`, so the rotation never takes the long way round.
    #[must_use]
    pub fn show(&self, solved: Quat, anchor: &mut Quat, shown: Quat) -> Quat {
        self.show_with_rest(solved, Quat::IDENTITY, anchor, shown)
    }

    /// [`Blend::show`] for a bone whose rest is `rest` rather than the avatar's rest pose (an
    /// idle arm, [`crate::ik::ArmIdle`]): a lost bone eases to it.
    #[must_use]
    pub fn show_with_rest(&self, solved: Quat, rest: Quat, anchor: &mut Quat, shown: Quat) -> Quat {
        if self.capture {
            *anchor = shown;
        }
        let target = if self.to_solved { solved } else { rest };
        let q = if self.is_exact() {
            target
        } else if self.weight <= 0.0 {
            *anchor
        } else {
            nlerp(*anchor, target, self.weight)
        };
        if q.dot(shown) < 0.0 {
            -q
        } else {
            q
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum State {
    /// Tracked since the time given (blending in until `fade_in_ms` later).
    Live(f64),
    /// Lost since the time given (holding, then easing out).
    Lost(f64),
}

/// The presence state machine of one bone group.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Presence {
    state: State,
}

impl Default for Presence {
    fn default() -> Self {
        // Never tracked: the first detection is shown as it is (there is nothing to blend
        // from but the rest pose, and a single solved frame should show its solve).
        Presence {
            state: State::Lost(f64::NEG_INFINITY),
        }
    }
}

/// Smoothstep of `x` clamped to 0..1 (C1: no velocity jump where an easing starts or ends).
#[inline]
fn ease(x: f64) -> f32 {
    let t = x.clamp(0.0, 1.0) as f32;
    t * t * (3.0 - 2.0 * t)
}

impl Presence {
    /// Advances to the frame at `now_ms`, in which the group is tracked (`live`) or not.
    /// Returns what to show. The first detection (since creation or [`Presence::reset`]) is
    /// shown as solved; a detection after a loss blends in. A clock that goes backwards
    /// restarts the group.
    // Out of line: called for each side's three groups and its lost hand; inlined at each
    // call it cost 0.2 KiB of .wasm.
    #[inline(never)]
    pub fn update(&mut self, now_ms: f64, live: bool, o: &DropoutOptions) -> Blend {
        let since = match self.state {
            State::Live(t) | State::Lost(t) => t,
        };
        if now_ms < since {
            // Time went backwards (a new session): show this frame as it is.
            self.state = if live {
                State::Live(f64::NEG_INFINITY)
            } else {
                State::Lost(f64::NEG_INFINITY)
            };
        }
        match (self.state, live) {
            (State::Live(t), true) => Blend {
                capture: false,
                to_solved: true,
                weight: fade(now_ms - t, o.fade_in_ms),
            },
            (State::Lost(t), true) if t == f64::NEG_INFINITY => {
                self.state = State::Live(f64::NEG_INFINITY);
                Blend {
                    capture: false,
                    to_solved: true,
                    weight: 1.0,
                }
            }
            (State::Lost(_), true) => {
                self.state = State::Live(now_ms);
                Blend {
                    capture: true,
                    to_solved: true,
                    weight: fade(0.0, o.fade_in_ms),
                }
            }
            (State::Live(_), false) => {
                self.state = State::Lost(now_ms);
                Blend {
                    capture: true,
                    to_solved: false,
                    weight: fade(-f64::from(o.hold_ms), o.fade_out_ms),
                }
            }
            (State::Lost(t), false) => Blend {
                capture: false,
                to_solved: false,
                weight: fade(now_ms - t - f64::from(o.hold_ms), o.fade_out_ms),
            },
        }
    }

    /// Ends a running blend-in: the group shows its solve from now on (a hand returning
    /// into a touch, whose contact placed the solved pose).
    pub fn complete(&mut self) {
        if let State::Live(_) = self.state {
            self.state = State::Live(f64::NEG_INFINITY);
        }
    }

    /// The group's rest pose is on show (another group of the body is tracked): its first
    /// detection then blends in from rest, as a return does, rather than jump to its solve.
    pub fn shown_at_rest(&mut self) {
        if self.state == State::Lost(f64::NEG_INFINITY) {
            self.state = State::Lost(f64::MIN);
        }
    }

    /// Back to rest (as if lost long ago).
    pub fn reset(&mut self) {
        *self = Presence::default();
    }

    /// Whether the group is tracked.
    #[must_use]
    pub fn is_live(&self) -> bool {
        matches!(self.state, State::Live(_))
    }

    /// Since when (ms) the group is tracked: `None` when lost; minus infinity when shown as
    /// solved from its first detection or since its blend-in completed.
    #[must_use]
    pub fn live_since(&self) -> Option<f64> {
        match self.state {
            State::Live(t) => Some(t),
            State::Lost(_) => None,
        }
    }
}

/// Progress of an easing `elapsed` ms into a `duration` ms fade (1 when there is no fade).
fn fade(elapsed: f64, duration: f32) -> f32 {
    if duration <= 0.0 {
        if elapsed >= 0.0 {
            1.0
        } else {
            0.0
        }
    } else {
        ease(elapsed / f64::from(duration))
    }
}

/// Normalized linear interpolation from `a` to `b` (the short way): for easing it looks like a
/// slerp, and costs no trigonometry (software `acos`/`sin` are slow in wasm).
pub(crate) fn nlerp(a: Quat, b: Quat, t: f32) -> Quat {
    let b = if a.dot(b) < 0.0 { -b } else { b };
    (a * (1.0 - t) + b * t).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    const O: DropoutOptions = DropoutOptions {
        enabled: true,
        hold_ms: 200.0,
        fade_out_ms: 400.0,
        fade_in_ms: 100.0,
    };

    #[test]
    fn first_detection_is_shown_then_a_return_blends_in() {
        let mut p = Presence::default();
        assert!(p.update(1000.0, true, &O).is_exact());
        assert!(p.update(1033.0, true, &O).is_exact());
        p.update(1066.0, false, &O);
        let b = p.update(2000.0, true, &O);
        assert!(b.capture && b.to_solved && b.weight == 0.0, "{b:?}");
        let b = p.update(2050.0, true, &O);
        assert!(!b.capture && (b.weight - 0.5).abs() < 1e-6);
        assert!(p.update(2100.0, true, &O).is_exact());
        assert!(p.update(5000.0, true, &O).is_exact());
    }

    #[test]
    fn complete_ends_a_blend_in_and_nothing_else() {
        let mut p = Presence::default();
        p.update(0.0, true, &O);
        p.update(33.0, false, &O);
        let b = p.update(1000.0, true, &O);
        assert!(!b.is_exact());
        p.complete();
        // The rest of the blend-in is skipped: the next frames show the solve.
        assert!(p.update(1010.0, true, &O).is_exact());
        // A lost group stays lost: complete does not bring it back.
        p.update(1100.0, false, &O);
        p.complete();
        let b = p.update(1150.0, false, &O);
        assert!(!b.to_solved && b.weight == 0.0, "{b:?}");
        // And the next return blends in again.
        assert!(!p.update(2000.0, true, &O).is_exact());
    }

    #[test]
    fn loss_holds_then_eases_to_rest() {
        let mut p = Presence::default();
        p.update(0.0, true, &O);
        p.update(500.0, true, &O);
        let b = p.update(1000.0, false, &O);
        assert!(b.capture && !b.to_solved && b.weight == 0.0, "{b:?}");
        assert_eq!(p.update(1199.0, false, &O).weight, 0.0, "holding");
        let mid = p.update(1400.0, false, &O).weight;
        assert!((mid - 0.5).abs() < 1e-6, "half way through the fade: {mid}");
        assert!(p.update(1600.0, false, &O).is_exact(), "at rest");
    }

    #[test]
    fn return_during_the_fade_blends_from_the_shown_pose() {
        let mut p = Presence::default();
        p.update(0.0, true, &O);
        p.update(1000.0, false, &O);
        p.update(1300.0, false, &O);
        let b = p.update(1320.0, true, &O);
        assert!(b.capture && b.to_solved && b.weight == 0.0, "{b:?}");
        assert!(p.update(1420.0, true, &O).is_exact());
    }

    #[test]
    fn off_snaps_and_time_going_back_restarts() {
        let mut p = Presence::default();
        assert!(p.update(0.0, true, &DropoutOptions::OFF).is_exact());
        let b = p.update(33.0, false, &DropoutOptions::OFF);
        assert!(b.is_exact() && !b.to_solved);
        let mut p = Presence::default();
        p.update(1000.0, true, &O);
        let b = p.update(10.0, true, &O);
        assert!(b.is_exact(), "backwards clock: no blend, {b:?}");
    }

    #[test]
    fn easing_is_monotonic_and_smooth() {
        let mut last = 0.0;
        for i in 0..=100 {
            let w = fade(i as f64 * 4.0, 400.0);
            assert!(w >= last && (w - last) < 0.016, "step {} at {i}", w - last);
            last = w;
        }
        assert_eq!(last, 1.0);
    }
}
