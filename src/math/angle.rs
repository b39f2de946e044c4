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
