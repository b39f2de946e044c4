//! Angles on the circle: wrapping into `(-pi, pi]`, signed differences, and clamping to a
//! range by the nearer end.

use core::f32::consts::PI;

/// Wraps an angle into `(-pi, pi]`.
#[inline]
pub fn wrap(a: f32) -> f32 {
    use core::f32::consts::TAU;
    // The angles met here are within a turn or two of the range: add or subtract a turn
    // before falling back on the remainder (a libm call in wasm).
    let w = if a > PI && a <= PI + TAU {
        a - TAU
    } else if a <= -PI && a > -PI - TAU {
        a + TAU
    } else if a.abs() <= PI {
        a
    } else {
        (a + PI).rem_euclid(TAU) - PI
    };
    if w <= -PI {
        w + TAU
    } else {
        w
    }
}

/// `y.atan2(x)` by a polynomial: within 2e-7 rad of it (float rounding; the polynomial alone
/// is within 2e-8, Abramowitz & Stegun 4.4.49 on `[0, 1]` and the octant identities), for
/// a fraction of the cost (libm's `atan2f` is the largest single cost of skin contact's
/// queries, natively and in the `.wasm`). Plain arithmetic: the same bits in every build.
/// `(0, 0)` gives 0; NaN stays NaN.
#[inline]
#[must_use]
pub fn atan2_fast(y: f32, x: f32) -> f32 {
    use core::f32::consts::FRAC_PI_2;
    let (ax, ay) = (x.abs(), y.abs());
    let steep = ay > ax;
    let (num, den) = if steep { (ax, ay) } else { (ay, ax) };
    // No early return: every step a select, so that a loop over lanes of points (the skin's
    // maps asked for several balls at once) becomes vector instructions. The origin's answer
    // is chosen at the end, over the polynomial's NaN.
    let a = num / den;
    let s = a * a;
    let p = -0.002_866_225_7_f32;
    let p = p * s + 0.016_165_737;
    let p = p * s - 0.042_909_614;
    let p = p * s + 0.075_289_64;
    let p = p * s - 0.106_562_64;
    let p = p * s + 0.142_089;
    let p = p * s - 0.199_935_51;
    let p = p * s + 0.333_331_45;
    let mut r = a - a * s * p;
    if steep {
        r = FRAC_PI_2 - r;
    }
    if x < 0.0 {
        r = PI - r;
    }
    let r = if y < 0.0 { -r } else { r };
    if den == 0.0 {
        if x < 0.0 {
            PI
        } else {
            0.0
        }
    } else {
        r
    }
}

/// Clamps an angle (radians) into `[lo, hi]` on the circle: outside values go to the nearer
/// bound. Returns the clamped angle (in the same turn as `lo..hi`).
#[inline]
pub fn clamp_angle(a: f32, lo: f32, hi: f32) -> f32 {
    if a >= lo && a <= hi {
        return a;
    }
    let to_lo = wrap(lo - a).abs();
    let to_hi = wrap(a - hi).abs();
    if to_lo <= to_hi {
        lo
    } else {
        hi
    }
}

/// `angle` (in `[-pi, pi]`) clamped to `[min, max]` on the circle: outside the range, the
/// end nearer along the circle (by [`angle_distance`]; [`clamp_angle`] measures by [`wrap`]).
pub fn clamp_angle_nearest(angle: f32, min: f32, max: f32) -> f32 {
    if (min..=max).contains(&angle) {
        return angle;
    }
    if angle_distance(angle, min).abs() <= angle_distance(angle, max).abs() {
        min
    } else {
        max
    }
}

/// Signed difference `a - b` wrapped into `(-pi, pi]`.
pub fn angle_distance(a: f32, b: f32) -> f32 {
    let d = (a - b).rem_euclid(2.0 * PI);
    if d > PI {
        d - 2.0 * PI
    } else {
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atan2_fast_follows_atan2_on_every_octant() {
        let mut worst = 0.0f64;
        for i in 0..720 {
            let t = (i as f64 + 0.37) / 720.0 * core::f64::consts::TAU;
            for r in [1e-3f64, 0.07, 1.0, 250.0] {
                let (x, y) = ((t.cos() * r) as f32, (t.sin() * r) as f32);
                let exact = (y as f64).atan2(x as f64);
                worst = worst.max((f64::from(atan2_fast(y, x)) - exact).abs());
            }
        }
        assert!(worst < 3e-7, "worst {worst} rad");
        // The axes, the octants' borders and the origin.
        for (y, x) in [
            (0.0, 1.0),
            (1.0, 0.0),
            (0.0, -1.0),
            (-1.0, 0.0),
            (1.0, 1.0),
            (-2.0, -2.0),
            (0.0, 0.0),
        ] {
            assert!((atan2_fast(y, x) - y.atan2(x)).abs() < 3e-7, "({y}, {x})");
        }
        assert!(atan2_fast(f32::NAN, 1.0).is_nan());
    }

    #[test]
    fn wrap_and_clamp() {
        assert!((wrap(3.0 * PI) - PI).abs() < 1e-5);
        assert!((wrap(-0.5) + 0.5).abs() < 1e-6);
        assert_eq!(wrap(PI), PI);
        assert_eq!(wrap(-PI), PI);
        // Every branch (within a turn, one turn out, several turns out) agrees with the
        // remainder, in (-pi, pi].
        for k in -3000..=3000 {
            let a = k as f32 * 0.0123;
            let w = wrap(a);
            assert!(w > -PI && w <= PI, "{a} -> {w}");
            let turns = (a - w) / (2.0 * PI);
            assert!((turns - turns.round()).abs() < 1e-4, "{a} -> {w}");
        }
        assert_eq!(clamp_angle(0.2, -0.1, 1.0), 0.2);
        assert_eq!(clamp_angle(1.5, -0.1, 1.0), 1.0);
        assert_eq!(clamp_angle(-0.5, -0.1, 1.0), -0.1);
        // -3 rad is nearer to 1.0 going the other way round the circle.
        assert_eq!(clamp_angle(-3.0, -0.1, 1.0), 1.0);
    }
}
