//! Small numerical helpers every method shares: [`clamp`] without a panic path, angles on the
//! circle ([`angle`]), rotations split and measured ([`rotation`]), and robust statistics of
//! calibration samples ([`stats`]). Imports nothing of the crate.

pub mod angle;
pub mod rotation;
pub mod stats;

pub use angle::{clamp_angle, wrap};
pub use rotation::{angle_between, swing_twist, twist_angle};
pub use stats::{insert_sorted, robust_mean, robust_mean_sorted};

/// `x` limited to `lo..=hi`: the same result as `f32::clamp` (NaN stays NaN), without its
/// panic when `lo > hi` or a bound is NaN. That panic's message formats the bounds, which
/// alone keeps Rust's float formatting (over 10 KiB gzipped) in the `.wasm`.
#[inline]
#[must_use]
pub fn clamp(x: f32, lo: f32, hi: f32) -> f32 {
    let mut x = x;
    if x < lo {
        x = lo;
    }
    if x > hi {
        x = hi;
    }
    x
}

#[cfg(test)]
mod tests {
    #[test]
    fn clamp_agrees_with_the_standard_one() {
        for x in [
            -2.0f32,
            -1.0,
            -0.0,
            0.0,
            0.5,
            1.0,
            3.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ] {
            for (lo, hi) in [(-1.0f32, 1.0), (0.0, 0.0), (-0.0, 0.0), (0.5, 2.0)] {
                assert_eq!(
                    super::clamp(x, lo, hi).to_bits(),
                    x.clamp(lo, hi).to_bits(),
                    "{x} in {lo}..{hi}"
                );
            }
        }
        assert!(super::clamp(f32::NAN, 0.0, 1.0).is_nan());
        // Where the standard one panics: no panic.
        assert_eq!(super::clamp(0.5, 1.0, 0.0), 0.0);
        assert_eq!(super::clamp(0.5, f32::NAN, 1.0), 0.5);
    }
}
