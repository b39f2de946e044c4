//! The One Euro filter (Casiez, Roussel, Vogel, CHI 2012): a low-pass filter whose cutoff rises
//! with speed, so slow motion is smoothed hard (jitter goes) and fast motion little (lag stays
//! small).
//!
//! Per sample, with `dt` seconds since the previous one:
//!
//! ```text
//! alpha(cutoff) = 1 / (1 + tau / dt),  tau = 1 / (2 pi cutoff)
//! dx     = lowpass(dx, (x - x_prev) / dt, alpha(d_cutoff))      speed estimate
//! cutoff = min_cutoff + beta * |dx|
//! x_hat  = lowpass(x_hat, x, alpha(cutoff))
//! ```
//!
//! Points are filtered as vectors (the cutoff follows the point's speed, the same on every
//! axis, so a straight motion stays straight); rotations on the unit sphere (the speed is the
//! angular speed, each step is a slerp toward the sample in the same hemisphere, so the filter
//! never takes the long way round).

use core::f32::consts::PI;

use glam::{Quat, Vec3};

/// Parameters of a One Euro filter. Units: `min_cutoff` and `d_cutoff` in Hz, `beta` in Hz per
/// unit of speed (per m/s for points, per rad/s for rotations).
///
/// In a rig these are `options.filter` (ranges in [`crate::options::table::OPTIONS`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OneEuroOptions {
    /// Cutoff frequency at rest (Hz): lower is smoother and slower.
    pub min_cutoff: f32,
    /// How fast the cutoff rises with speed: higher follows fast motion with less lag.
    pub beta: f32,
    /// Cutoff of the speed estimate (Hz). The paper uses 1.
    pub d_cutoff: f32,
}

/// The smoothing factor of a first-order low-pass at `cutoff` Hz for a step of `dt` seconds.
#[inline]
#[must_use]
pub fn alpha(dt: f32, cutoff: f32) -> f32 {
    let tau = 1.0 / (2.0 * PI * cutoff);
    1.0 / (1.0 + tau / dt)
}

/// What every point filtered over one time step shares: the step and the speed estimate's
/// smoothing factor, computed once for a set of points instead of once per point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Step {
    inv_dt: f32,
    /// `alpha(dt, d_cutoff)`.
    alpha_d: f32,
    /// `2 pi dt`: `alpha(dt, cutoff) = c / (1 + c)` with `c = 2 pi dt cutoff`.
    two_pi_dt: f32,
}

impl Step {
    /// The step of `dt` seconds under options `o`; `None` when `dt` is not a positive number
    /// (the filters restart).
    #[must_use]
    pub fn new(dt: f32, o: &OneEuroOptions) -> Option<Step> {
        (dt > 0.0).then(|| Step {
            inv_dt: 1.0 / dt,
            alpha_d: alpha(dt, o.d_cutoff),
            two_pi_dt: 2.0 * PI * dt,
        })
    }

    /// `alpha(dt, cutoff)` for this step.
    #[inline]
    fn alpha(&self, cutoff: f32) -> f32 {
        let c = self.two_pi_dt * cutoff;
        c / (1.0 + c)
    }
}

/// A One Euro filter on a point (or any 3-vector). Starts empty: the first sample passes
/// through unchanged.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct OneEuroVec3 {
    x: Vec3,
    dx: Vec3,
    primed: bool,
}

impl OneEuroVec3 {
    /// Filters one sample taken `dt` seconds after the previous one (`dt > 0`). Returns the
    /// filtered value. A non-finite result (which finite inputs cannot give) restarts the
    /// filter at the sample.
    pub fn filter(&mut self, value: Vec3, dt: f32, o: &OneEuroOptions) -> Vec3 {
        self.filter_step(value, Step::new(dt, o).as_ref(), o)
    }

    /// [`OneEuroVec3::filter`] with the step's shared factors computed once (`None`: restart).
    #[inline]
    pub fn filter_step(&mut self, value: Vec3, step: Option<&Step>, o: &OneEuroOptions) -> Vec3 {
        let Some(step) = step.filter(|_| self.primed) else {
            return self.restart(value);
        };
        let speed = (value - self.x) * step.inv_dt;
        self.dx += step.alpha_d * (speed - self.dx);
        let cutoff = o.min_cutoff + o.beta * self.dx.length();
        self.x += step.alpha(cutoff) * (value - self.x);
        if !self.x.is_finite() || !self.dx.is_finite() {
            return self.restart(value);
        }
        self.x
    }

    /// Forgets the history; the next sample passes through.
    pub fn reset(&mut self) {
        self.primed = false;
    }

    fn restart(&mut self, value: Vec3) -> Vec3 {
        self.x = value;
        self.dx = Vec3::ZERO;
        self.primed = true;
        value
    }
}

/// A One Euro filter on a rotation: the speed is the angular speed (rad/s), each step a slerp
/// from the filtered rotation toward the sample (taken in the same hemisphere: the filter
/// never goes the long way round, and its output keeps the sign of the previous output).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct OneEuroQuat {
    q: Quat,
    speed: f32,
    primed: bool,
}

impl OneEuroQuat {
    /// Filters one unit quaternion taken `dt` seconds after the previous one.
    pub fn filter(&mut self, value: Quat, dt: f32, o: &OneEuroOptions) -> Quat {
        if !self.primed || dt.is_nan() || dt <= 0.0 {
            return self.restart(value);
        }
        let value = if self.q.dot(value) < 0.0 {
            -value
        } else {
            value
        };
        let angle = 2.0 * (value - self.q).length().atan2((value + self.q).length());
        self.speed += alpha(dt, o.d_cutoff) * (angle / dt - self.speed);
        let cutoff = o.min_cutoff + o.beta * self.speed;
        let q = self.q.slerp(value, alpha(dt, cutoff)).normalize();
        if !q.is_finite() || !self.speed.is_finite() {
            return self.restart(value);
        }
        // glam's slerp may return either sign; keep the previous output's hemisphere.
        self.q = if q.dot(self.q) < 0.0 { -q } else { q };
        self.q
    }

    /// Forgets the history; the next sample passes through.
    pub fn reset(&mut self) {
        self.primed = false;
    }

    fn restart(&mut self, value: Quat) -> Quat {
        self.q = value;
        self.speed = 0.0;
        self.primed = true;
        value
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const O: OneEuroOptions = OneEuroOptions {
        min_cutoff: 1.0,
        beta: 0.0,
        d_cutoff: 1.0,
    };

    #[test]
    fn alpha_is_the_first_order_lowpass_factor() {
        // At the cutoff frequency with dt = tau, alpha is 1/2.
        let cutoff = 2.0;
        let tau = 1.0 / (2.0 * PI * cutoff);
        assert!((alpha(tau, cutoff) - 0.5).abs() < 1e-6);
        assert!(alpha(1e-6, 1.0) < 1e-4 && alpha(1e6, 1.0) > 0.9999);
    }

    #[test]
    fn first_sample_passes_and_a_constant_stays() {
        let mut f = OneEuroVec3::default();
        let p = Vec3::new(0.1, -0.2, 0.3);
        assert_eq!(f.filter(p, 0.033, &O), p);
        for _ in 0..10 {
            assert!((f.filter(p, 0.033, &O) - p).length() < 1e-7);
        }
    }

    #[test]
    fn a_step_is_followed_exponentially_at_min_cutoff_with_beta_zero() {
        let mut f = OneEuroVec3::default();
        f.filter(Vec3::ZERO, 0.01, &O);
        let dt = 0.01;
        let a = alpha(dt, 1.0);
        let mut want = 0.0;
        for _ in 0..50 {
            let got = f.filter(Vec3::X, dt, &O).x;
            want += a * (1.0 - want);
            assert!((got - want).abs() < 1e-5, "{got} vs {want}");
        }
    }

    #[test]
    fn beta_reduces_lag_on_fast_motion() {
        // A ramp at 1 m/s sampled at 100 Hz: with beta the filter trails the ramp by less.
        let lag = |beta: f32| {
            let o = OneEuroOptions { beta, ..O };
            let mut f = OneEuroVec3::default();
            let mut last = 0.0;
            for i in 0..200 {
                let x = i as f32 * 0.01;
                last = x - f.filter(Vec3::new(x, 0.0, 0.0), 0.01, &o).x;
            }
            last
        };
        let (slow, fast) = (lag(0.0), lag(10.0));
        assert!(slow > 0.1 && fast < slow / 5.0, "lag {slow} vs {fast}");
    }

    #[test]
    fn jitter_is_reduced_at_rest() {
        // Alternating +-1 mm noise around a fixed point at 30 Hz.
        let o = OneEuroOptions {
            min_cutoff: 1.0,
            beta: 1.0,
            d_cutoff: 1.0,
        };
        let mut f = OneEuroVec3::default();
        let mut spread: f32 = 0.0;
        for i in 0..300 {
            let n = if i % 2 == 0 { 0.001 } else { -0.001 };
            let y = f.filter(Vec3::new(n, 0.0, 0.0), 1.0 / 30.0, &o);
            if i > 100 {
                spread = spread.max(y.x.abs());
            }
        }
        assert!(spread < 0.0003, "residual jitter {spread}");
    }

    #[test]
    fn rotations_take_the_short_way_and_keep_their_sign() {
        let mut f = OneEuroQuat::default();
        let a = Quat::from_rotation_y(3.0);
        f.filter(a, 0.033, &O);
        // The same rotation with the other sign, then a small step past pi: no long way round.
        let b = -Quat::from_rotation_y(3.2);
        let out = f.filter(b, 0.033, &O);
        assert!(out.dot(a) > 0.0, "kept the previous sign");
        let angle = out.angle_between(a);
        assert!(
            angle < 0.2,
            "moved {angle} rad toward a rotation 0.2 rad away"
        );
        for _ in 0..200 {
            f.filter(b, 0.033, &O);
        }
        assert!(f.filter(b, 0.033, &O).angle_between(b) < 1e-3);
    }

    #[test]
    fn zero_or_negative_dt_restarts_and_nothing_is_nan() {
        let mut f = OneEuroVec3::default();
        f.filter(Vec3::ZERO, 0.03, &O);
        assert_eq!(f.filter(Vec3::ONE, 0.0, &O), Vec3::ONE);
        assert_eq!(f.filter(Vec3::X, -1.0, &O), Vec3::X);
        assert_eq!(f.filter(Vec3::Y, f32::NAN, &O), Vec3::Y);
        let huge = Vec3::splat(3e38);
        let out = f.filter(huge, 1e-30, &O);
        assert!(out.is_finite());
        let mut q = OneEuroQuat::default();
        q.filter(Quat::IDENTITY, 0.03, &O);
        assert!(q.filter(Quat::from_rotation_x(1.0), 1e-30, &O).is_finite());
    }
}
