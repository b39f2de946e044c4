//! The kinematic model of one finger: a 2-DOF base joint described in spherical coordinates
//! about a pole, and hinges about the axis that base carries. Pure math on fixed-size values;
//! allocation-free.
//!
//! A [`Basis`] `(x, y, z)` is orthonormal (either handedness: left and right hands use mirror
//! images of one another). A base direction is
//!
//! ```text
//! d(lon, colat) = sin(colat) (cos(lon) x + sin(lon) y) + cos(colat) z
//! ```
//!
//! with `z` the pole. Its local frame is `north` (toward the pole, perpendicular to `d`) and
//! `east` (increasing longitude). The base joint is the rotation about the pole by the
//! longitude followed by the rotation about the carried `east` axis by the colatitude: it
//! takes the local frame of one direction to the local frame of another, so the finger has no
//! twist other than what the two angles imply.
//!
//! The hinges bend toward the *flexion direction*: `north` for fingers (their pole is the
//! palmar normal, so a hinge bends toward the palm), `east` for the thumb (its pole is the
//! index metacarpal line: the thumb's flexion plane turns with the opposition angle, Kapandji's
//! cone of opposition). The hinge axis is `d x flexion`; a positive hinge angle flexes.

use glam::Vec3;

use crate::math::wrap;

/// An orthonormal basis; `z` is the pole.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Basis {
    pub x: Vec3,
    pub y: Vec3,
    pub z: Vec3,
}

/// Which rule gives the flexion direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Flexion toward the pole (`north`).
    Finger,
    /// Flexion along `east`.
    Thumb,
}

/// The base direction and its hinge plane at some `(lon, colat)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Bone direction.
    pub dir: Vec3,
    /// Unit direction hinges bend toward (perpendicular to `dir`).
    pub flex: Vec3,
    /// Hinge axis, `dir x flex`.
    pub hinge: Vec3,
}

struct Local {
    d: Vec3,
    north: Vec3,
    east: Vec3,
    g: Vec3,
    k: f32,
}

impl Basis {
    /// Gram-Schmidt: `z` as given (normalized), `x` from `x_hint`, `y` from `y_hint` (both
    /// made perpendicular), keeping the hints' orientation. `None` when degenerate.
    pub fn from_hints(z: Vec3, x_hint: Vec3, y_hint: Vec3) -> Option<Basis> {
        let z = z.try_normalize()?;
        let x = (x_hint - x_hint.dot(z) * z).try_normalize()?;
        let y = (y_hint - y_hint.dot(z) * z - y_hint.dot(x) * x).try_normalize()?;
        Some(Basis { x, y, z })
    }

    fn local(&self, lon: f32, colat: f32) -> Local {
        let (sl, cl) = lon.sin_cos();
        let (s, k) = colat.sin_cos();
        let g = cl * self.x + sl * self.y;
        Local {
            d: s * g + k * self.z,
            north: s * self.z - k * g,
            east: -sl * self.x + cl * self.y,
            g,
            k,
        }
    }

    /// Longitude of a direction (the first of [`Basis::spherical`], one `atan2` fewer).
    pub fn longitude(&self, v: Vec3) -> f32 {
        v.dot(self.y).atan2(v.dot(self.x))
    }

    /// Longitude and colatitude of a unit direction (colatitude in `0..=pi`).
    pub fn spherical(&self, v: Vec3) -> (f32, f32) {
        let (a, b, c) = (v.dot(self.x), v.dot(self.y), v.dot(self.z));
        (b.atan2(a), a.hypot(b).atan2(c))
    }

    /// The world axes the base joint turns about when its longitude and its colatitude grow:
    /// `(pole, east)` signed so that `d/dlon R = skew(pole) R` and `d/dcolat R = skew(east) R`
    /// for the base rotation `R` (the whole local frame turns rigidly; the sign carries the
    /// basis' handedness). The tangent-space derivative of seed 003, `R = (I + phi skew(k)) R0`.
    pub fn turn_axes(&self, lon: f32) -> (Vec3, Vec3) {
        let handed = self.x.cross(self.y).dot(self.z).signum();
        let (sl, cl) = lon.sin_cos();
        (handed * self.z, handed * (-sl * self.x + cl * self.y))
    }

    /// The direction, flexion direction and hinge axis at `(lon, colat)`.
    pub fn frame(&self, kind: Kind, lon: f32, colat: f32) -> Frame {
        let l = self.local(lon, colat);
        let flex = match kind {
            Kind::Finger => l.north,
            Kind::Thumb => l.east,
        };
        Frame {
            dir: l.d,
            flex,
            hinge: l.d.cross(flex),
        }
    }
}

/// What one finger's fit sees: up to three unit segment directions (`weight` 0 = no data).
#[derive(Clone, Copy, Debug)]
pub struct Targets {
    pub dir: [Vec3; 3],
    pub weight: [f32; 3],
    /// Longitude the base prefers when the data cannot tell (a straight finger pointing along
    /// the pole); only used with [`Kind::Finger`], with a tiny weight.
    pub lon_prior: f32,
}

/// Weight of the longitude prior: small enough that it moves a well-determined fit by well
/// under a tenth of a degree, large enough to fix the plane of a finger pointing at the pole.
const PRIOR: f32 = 1e-4;

fn residuals(
    basis: &Basis,
    kind: Kind,
    t: &Targets,
    lon: f32,
    colat: f32,
) -> ([f32; 5], [[f32; 2]; 5]) {
    let l = basis.local(lon, colat);
    let [t0, t1, t2] = t.dir;
    let [w0, w1, w2] = t.weight;
    let (h, dh_lon, dh_col) = match kind {
        // d x north = g x z: the hinge depends on the longitude only.
        Kind::Finger => (l.g.cross(basis.z), l.east.cross(basis.z), Vec3::ZERO),
        Kind::Thumb => (l.d.cross(l.east), -l.d.cross(l.g), -l.north.cross(l.east)),
    };
    let mut r = [0.0; 5];
    let mut j = [[0.0; 2]; 5];
    r[0] = w0 * t0.dot(l.north);
    j[0] = [w0 * t0.dot(-l.k * l.east), w0 * t0.dot(l.d)];
    r[1] = w0 * t0.dot(l.east);
    j[1] = [w0 * t0.dot(-l.g), 0.0];
    r[2] = w1 * t1.dot(h);
    j[2] = [w1 * t1.dot(dh_lon), w1 * t1.dot(dh_col)];
    r[3] = w2 * t2.dot(h);
    j[3] = [w2 * t2.dot(dh_lon), w2 * t2.dot(dh_col)];
    if kind == Kind::Finger {
        let p = PRIOR.sqrt();
        r[4] = p * wrap(lon - t.lon_prior);
        j[4] = [p, 0.0];
    }
    (r, j)
}

/// Half the sum of squared residuals at `(lon, colat)`, with the Gauss-Newton normal
/// equations `J'J` (symmetric: `[a, b, c]` for `[[a, b], [b, c]]`) and `J'r`.
// Out of line, like `fit` and `hand::solve_finger`: the WebAssembly build runs a full frame
// about 5% faster in V8 than with them inlined (`node eval/speed.mjs`).
#[inline(never)]
fn cost(basis: &Basis, kind: Kind, t: &Targets, x: [f32; 2]) -> (f32, [f32; 3], [f32; 2]) {
    let (r, j) = residuals(basis, kind, t, x[0], x[1]);
    let mut jtj = [0.0_f32; 3];
    let mut jtr = [0.0_f32; 2];
    let mut sum = 0.0_f32;
    for (r, j) in r.iter().zip(&j) {
        sum += r * r;
        jtj[0] += j[0] * j[0];
        jtj[1] += j[0] * j[1];
        jtj[2] += j[1] * j[1];
        jtr[0] += j[0] * r;
        jtr[1] += j[1] * r;
    }
    (0.5 * sum, jtj, jtr)
}

/// Largest Gauss-Newton iterations of [`fit`].
const FIT_ITERATIONS: u32 = 20;
/// [`fit`] stops when a step moves neither angle by more than this (radians): 0.06 degree,
/// well below what a landmark's noise moves a finger (`eval/rust/eval_hands.rs` is unchanged to
/// 0.01 degree against 1e-4, which takes a third more evaluations).
const FIT_TOLERANCE: f32 = 1e-3;
/// Step halvings [`fit`]'s line search tries before it stops.
const FIT_BACKTRACKS: u32 = 12;
/// Sufficient decrease (Armijo) of [`fit`]'s line search.
const FIT_ARMIJO: f32 = 1e-4;

/// Least-squares base angles: the base direction and hinge plane that best explain all
/// segments (base segment direction, hinge segments' distance from the hinge plane).
/// Gauss-Newton with an Armijo line search on the two angles (unbounded: the angles are
/// clamped to anatomical limits afterwards), for fingers from their closed-form optimum without
/// the prior ([`finger_optimum`]), for the thumb (whose hinge axis turns with both angles) and
/// where that does not apply from the base segment's own direction; where the data cannot fix
/// both angles (a singular model) that start is kept. A step below
/// [`FIT_TOLERANCE`] is taken without a further evaluation. The general bounded solver
/// ([`crate::solve::least_squares`], which the retargeting uses) reaches the same angles; this
/// closed-form 2 x 2 one costs a fraction of it every frame.
#[inline(never)] // See `cost`.
pub fn fit(basis: &Basis, kind: Kind, t: &Targets) -> (f32, f32) {
    let start = match kind {
        Kind::Finger => finger_optimum(basis, t),
        Kind::Thumb => None,
    };
    fit_from(
        basis,
        kind,
        t,
        start.unwrap_or_else(|| basis.spherical(t.dir[0])),
    )
}

/// A finger's least-squares base angles without the longitude prior, in closed form. Its hinge
/// axis `g x z` is perpendicular to the pole, and at the best colatitude for a longitude the
/// base segment's residual is its component along that axis too, so the cost is
/// `sum w_i^2 (t_i . h(lon))^2`: least where `h` is the minor principal axis of the segments'
/// projections on the `x`-`y` plane (`lon` half the angle of `(Sxx - Syy, 2 Sxy)`), and the
/// colatitude then points the base along the base segment's projection on the finger's plane.
/// Of the two longitudes half a turn apart (the same plane) the one nearer the prior. `None`
/// where the projections do not fix a plane (the finger along the pole, or no data): the
/// Gauss-Newton then starts from the base segment as for the thumb. [`fit`] refines it (the
/// prior), typically in one evaluation instead of three to five from the base segment.
fn finger_optimum(basis: &Basis, t: &Targets) -> Option<(f32, f32)> {
    use core::f32::consts::{FRAC_PI_2, PI};
    let (mut sxx, mut syy, mut sxy) = (0.0_f32, 0.0_f32, 0.0_f32);
    for (d, w) in t.dir.iter().zip(t.weight) {
        let (a, b, w2) = (d.dot(basis.x), d.dot(basis.y), w * w);
        sxx += w2 * a * a;
        syy += w2 * b * b;
        sxy += w2 * a * b;
    }
    let half_difference = 0.5 * (sxx - syy);
    // Below this the plane is fixed by the prior more than by the data.
    let spread = half_difference.hypot(sxy);
    if spread.is_nan() || spread <= 1e-4 || t.weight[0] == 0.0 {
        return None;
    }
    let mut lon = 0.5 * sxy.atan2(half_difference);
    if wrap(lon - t.lon_prior).abs() > FRAC_PI_2 {
        lon = wrap(lon + PI);
    }
    let (s, c) = lon.sin_cos();
    let g = c * basis.x + s * basis.y;
    let t0 = t.dir[0];
    Some((lon, t0.dot(g).atan2(t0.dot(basis.z))))
}

/// [`fit`]'s Gauss-Newton from `(lon, colat)`.
fn fit_from(basis: &Basis, kind: Kind, t: &Targets, (lon, colat): (f32, f32)) -> (f32, f32) {
    let mut x = [lon, colat];
    let (mut cost_x, mut jtj, mut jtr) = cost(basis, kind, t, x);
    if !cost_x.is_finite() {
        return (lon, colat);
    }
    for _ in 0..FIT_ITERATIONS {
        // Solve J'J s = -J'r (Cramer's rule in f64: the 2 x 2 system can be ill-conditioned).
        let [a, b, c] = jtj.map(f64::from);
        let det = a * c - b * b;
        if det.is_nan() || det <= 1e-12 * (a + c) * (a + c) {
            break;
        }
        let (g0, g1) = (f64::from(jtr[0]), f64::from(jtr[1]));
        let step = [
            ((-c * g0 + b * g1) / det) as f32,
            ((b * g0 - a * g1) / det) as f32,
        ];
        let size = step[0].abs().max(step[1].abs());
        if !size.is_finite() {
            break;
        }
        if size <= FIT_TOLERANCE {
            x = [x[0] + step[0], x[1] + step[1]];
            break;
        }
        let slope = jtr[0] * step[0] + jtr[1] * step[1];
        let mut alpha = 1.0_f32;
        let mut accepted = false;
        for _ in 0..FIT_BACKTRACKS {
            let trial = [x[0] + alpha * step[0], x[1] + alpha * step[1]];
            let (c, m, g) = cost(basis, kind, t, trial);
            if c.is_finite() && c <= cost_x + FIT_ARMIJO * alpha * slope {
                (x, cost_x, jtj, jtr) = (trial, c, m, g);
                accepted = true;
                break;
            }
            alpha *= 0.5;
        }
        if !accepted || alpha * size <= FIT_TOLERANCE {
            break;
        }
    }
    (x[0], x[1])
}

/// Signed hinge angle of direction `v` in the plane `(dir, flex)`, from `dir` toward `flex`.
#[inline]
pub fn hinge_angle(dir: Vec3, flex: Vec3, v: Vec3) -> f32 {
    v.dot(flex).atan2(v.dot(dir))
}

/// `dir` bent by `angle` toward `flex` (both unit, perpendicular).
#[inline]
pub fn bend(dir: Vec3, flex: Vec3, angle: f32) -> Vec3 {
    let (s, c) = angle.sin_cos();
    c * dir + s * flex
}

#[cfg(test)]
mod tests {
    use super::*;

    fn basis() -> Basis {
        // A left-handed basis on purpose: the math must not care.
        Basis::from_hints(Vec3::NEG_Y, Vec3::X, Vec3::Z).unwrap()
    }

    #[test]
    fn frames_are_orthonormal_and_hinge_bends_toward_flex() {
        let b = basis();
        for kind in [Kind::Finger, Kind::Thumb] {
            for (lon, colat) in [(0.3, 1.2), (-1.0, 0.4), (2.0, 2.5), (0.1, -0.3)] {
                let f = b.frame(kind, lon, colat);
                assert!((f.dir.length() - 1.0).abs() < 1e-5);
                assert!((f.flex.length() - 1.0).abs() < 1e-5);
                assert!(f.dir.dot(f.flex).abs() < 1e-5);
                let q = glam::Quat::from_axis_angle(f.hinge.normalize(), 0.5);
                assert!((q * f.dir - bend(f.dir, f.flex, 0.5)).length() < 1e-5);
            }
        }
    }

    #[test]
    fn turn_axes_are_the_frame_derivatives() {
        let right = Basis::from_hints(Vec3::Y, Vec3::Z, Vec3::X).unwrap();
        for b in [basis(), right] {
            for kind in [Kind::Finger, Kind::Thumb] {
                let (lon, colat, h) = (0.7_f32, 1.1_f32, 1e-3_f32);
                let f = b.frame(kind, lon, colat);
                let (pole, east) = b.turn_axes(lon);
                let dl = b.frame(kind, lon + h, colat);
                let dc = b.frame(kind, lon, colat + h);
                for (v, vl, vc) in [(f.dir, dl.dir, dc.dir), (f.hinge, dl.hinge, dc.hinge)] {
                    assert!(((vl - v) / h - pole.cross(v)).length() < 2e-3, "{kind:?}");
                    assert!(((vc - v) / h - east.cross(v)).length() < 2e-3, "{kind:?}");
                }
            }
        }
    }

    #[test]
    fn fit_recovers_a_planar_finger_exactly() {
        let b = basis();
        for kind in [Kind::Finger, Kind::Thumb] {
            let (lon, colat) = (0.4_f32, 0.9_f32);
            let f = b.frame(kind, lon, colat);
            let t = Targets {
                dir: [f.dir, bend(f.dir, f.flex, 0.7), bend(f.dir, f.flex, 1.3)],
                weight: [1.0; 3],
                lon_prior: 0.0,
            };
            let (l, c) = fit(&b, kind, &t);
            assert!((l - lon).abs() < 2e-3, "{kind:?} lon {l}");
            assert!((c - colat).abs() < 2e-3, "{kind:?} colat {c}");
        }
    }

    #[test]
    fn fit_balances_an_out_of_plane_segment() {
        // The distal segment leans sideways: the best hinge plane leans part of the way.
        let b = basis();
        let f = b.frame(Kind::Finger, 0.0, 1.0);
        let side = f.hinge.normalize();
        let t = Targets {
            dir: [
                f.dir,
                bend(f.dir, f.flex, 0.6),
                (bend(f.dir, f.flex, 1.2) + 0.3 * side).normalize(),
            ],
            weight: [1.0; 3],
            lon_prior: 0.0,
        };
        let (l, _) = fit(&b, Kind::Finger, &t);
        assert!(
            l.abs() > 0.01,
            "plane should lean toward the outlier, lon {l}"
        );
        let g = b.frame(Kind::Finger, l, 1.0);
        let before = t.dir[2].dot(f.hinge).abs();
        let after = t.dir[2].dot(g.hinge).abs();
        assert!(after < before);
    }

    #[test]
    fn the_closed_form_finger_start_reaches_the_fit_from_the_base_segment() {
        // Noisy, out-of-plane fingers on bases of both handedness: the fit from the closed-form
        // optimum and the plain Gauss-Newton from the base segment's direction find the same
        // base direction and hinge plane.
        let right = Basis::from_hints(Vec3::Y, Vec3::Z, Vec3::X).unwrap();
        let mut seed = 0x2545_f491_u32;
        let mut next = move || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0
        };
        let mut closed_form = 0;
        for b in [basis(), right] {
            for _ in 0..500 {
                let (lon, colat) = (next() * 1.2, 0.9 + 0.7 * next());
                let f = b.frame(Kind::Finger, lon, colat);
                let (h1, h2) = (0.8 + 0.8 * next(), 0.6 + 0.6 * next());
                let noise = 0.15;
                let mut jitter =
                    |v: Vec3| (v + noise * Vec3::new(next(), next(), next())).normalize();
                let t = Targets {
                    dir: [
                        jitter(f.dir),
                        jitter(bend(f.dir, f.flex, h1)),
                        jitter(bend(f.dir, f.flex, h1 + h2)),
                    ],
                    weight: [1.0; 3],
                    lon_prior: lon + 0.4 * next(),
                };
                let start = finger_optimum(&b, &t);
                closed_form += usize::from(start.is_some());
                let (l1, c1) = fit(&b, Kind::Finger, &t);
                let (l2, c2) = fit_from(&b, Kind::Finger, &t, b.spherical(t.dir[0]));
                // Never a worse fit (both stop within the tolerance of a minimum).
                let (e1, e2) = (
                    cost(&b, Kind::Finger, &t, [l1, c1]).0,
                    cost(&b, Kind::Finger, &t, [l2, c2]).0,
                );
                assert!(e1 <= e2 + 1e-6, "{t:?}: cost {e1} vs {e2}");
                // The same finger where the data fix its plane well (the base well off the
                // pole; along the pole the plane is loosely determined and both stop within
                // the tolerance's reach of the optimum, up to 0.01 rad apart).
                let (g1, g2) = (b.frame(Kind::Finger, l1, c1), b.frame(Kind::Finger, l2, c2));
                assert!(
                    g1.dir.angle_between(g2.dir) < 3e-3,
                    "{t:?}: {l1} {c1} vs {l2} {c2}"
                );
                let planes = g1.hinge.normalize().dot(g2.hinge.normalize()).abs();
                let tolerance = if c1.abs() > 0.3 { 3e-3_f32 } else { 2e-2 };
                assert!(planes > tolerance.cos(), "{t:?}: {l1} {c1} vs {l2} {c2}");
                // The closed form is the optimum already; the refinement only adds the prior.
                if let (Some((ls, cs)), true) = (start, c1.abs() > 0.3) {
                    let g = b.frame(Kind::Finger, ls, cs);
                    assert!(g.dir.angle_between(g1.dir) < 3e-3, "{t:?}: start {ls} {cs}");
                    assert!(g.hinge.normalize().dot(g1.hinge.normalize()).abs() > 0.9999);
                }
            }
        }
        assert_eq!(
            closed_form, 1000,
            "the closed form applies to every one of these"
        );
    }
}
