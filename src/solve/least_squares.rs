//! Gauss-Newton for small nonlinear least-squares problems with box constraints.
//!
//! The problem, over `x` in R^N:
//!
//! ```text
//! minimize  E(x) = 1/2 r(x)' W r(x) + R(x)     subject to  lower <= x <= upper
//! ```
//!
//! The caller's [`Objective`] returns `E(x)` and, when asked, the Gauss-Newton model at `x`:
//! `H = J'WJ + d2R` and `g = J'Wr + dR` ([`Model`]). `H` must be positive definite: give `R` some
//! curvature in every direction (a temporal term toward the previous solution does).
//!
//! ## One iteration (seed 003, section 3.1)
//!
//! The step `s` solves the linearized problem with the bounds as inequality constraints:
//!
//! ```text
//! minimize  1/2 s'Hs + g's     subject to  lower - x <= s <= upper - x
//! ```
//!
//! exactly, by the primal active-set method for convex QPs (Nocedal & Wright, *Numerical
//! Optimization*, 2nd ed., 2006, algorithm 16.3). A working set `A` of bounds is held as
//! equalities `E s = b` (`E`: rows of the identity). For a given `A` the equality-constrained
//! QP is solved the way the seed describes: a Cholesky factorization `H = LL'`, the Lagrange
//! multipliers `lambda` of the active bounds from the Schur complement `S = E H^-1 E'`
//! (`S lambda = -E H^-1 grad`, `S` is the `A` x `A` block of `H^-1` and is positive definite),
//! and then the step `-H^-1 (grad + E' lambda)`. A bound in the way of the step joins `A`; a
//! multiplier of the wrong sign (the bound holds the solution back from the inside) leaves
//! it. Since `H` is positive definite the QP is strictly convex and the method ends at its
//! unique minimizer, the point satisfying its KKT conditions; the loop is capped at `4N + 4`
//! working-set changes, in which case the feasible, cost-reducing point reached so far is
//! used (a fallback for rounding-induced cycling; not observed).
//!
//! A backtracking (Armijo) line search on the true `E` then makes every iteration a descent
//! step; iterates never leave the box (it is convex and both ends of the step are inside).
//! At a fixed point the step is zero, which is exactly the KKT conditions of the constrained
//! problem (gradient zero in the free coordinates, pointing into the box at active bounds), so
//! the method converges to the same constrained optimum as the seed's.
//!
//! Everything is fixed-size: nothing is allocated. The linear algebra runs in `f64` (the
//! models are accumulated in `f64`), parameters and costs are `f32`.

// Dense matrix code reads best with explicit indices.
#![allow(clippy::needless_range_loop)]

use glam::Vec3;

/// The Gauss-Newton model of an objective at a point: `H = J'WJ + d2R` (only the lower
/// triangle and the diagonal are read; the `add_*` helpers fill both halves) and
/// `g = J'Wr + dR`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Model<const N: usize> {
    /// The Gauss-Newton Hessian approximation.
    pub hessian: [[f64; N]; N],
    /// The gradient.
    pub gradient: [f64; N],
}

impl<const N: usize> Default for Model<N> {
    fn default() -> Self {
        Model {
            hessian: [[0.0; N]; N],
            gradient: [0.0; N],
        }
    }
}

impl<const N: usize> Model<N> {
    /// Adds a weighted 3D residual `e` whose derivative with respect to `x[k]` is
    /// `columns[k]`; returns its cost `1/2 w |e|^2`.
    pub fn add_point(&mut self, weight: f32, e: Vec3, columns: &[Vec3; N]) -> f32 {
        let w = f64::from(weight);
        for k in 0..N {
            let ck = columns[k];
            if ck == Vec3::ZERO {
                continue;
            }
            self.gradient[k] += w * f64::from(ck.dot(e));
            for l in 0..=k {
                let v = w * f64::from(ck.dot(columns[l]));
                self.hessian[k][l] += v;
                if l != k {
                    self.hessian[l][k] += v;
                }
            }
        }
        0.5 * weight * e.length_squared()
    }

    /// Adds a weighted residual `e = x[index] - constant` (derivative 1 in coordinate
    /// `index`, 0 elsewhere: a prior or temporal term); returns its cost `1/2 w e^2`.
    pub fn add_coordinate(&mut self, weight: f32, index: usize, e: f32) -> f32 {
        let w = f64::from(weight);
        self.hessian[index][index] += w;
        self.gradient[index] += w * f64::from(e);
        0.5 * weight * e * e
    }

    /// Adds a weighted scalar residual `e` with derivative `row` (`de/dx`); returns its
    /// cost `1/2 w e^2`.
    pub fn add_scalar(&mut self, weight: f32, e: f32, row: &[f32; N]) -> f32 {
        let w = f64::from(weight);
        for k in 0..N {
            if row[k] == 0.0 {
                continue;
            }
            self.gradient[k] += w * f64::from(row[k] * e);
            for l in 0..=k {
                let v = w * f64::from(row[k] * row[l]);
                self.hessian[k][l] += v;
                if l != k {
                    self.hessian[l][k] += v;
                }
            }
        }
        0.5 * weight * e * e
    }
}

/// An objective `E(x)` for [`minimize`].
pub trait Objective<const N: usize> {
    /// `E(x)`; when `model` is given, also adds the Gauss-Newton model at `x` into it (it
    /// arrives zeroed). A non-finite return value rejects `x`.
    fn evaluate(&mut self, x: &[f32; N], model: Option<&mut Model<N>>) -> f32;
}

/// Stopping rules of [`minimize`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Most Gauss-Newton iterations (linearizations).
    pub max_iterations: u32,
    /// Converged when a step's largest component is at most this (units of `x`).
    pub step_tolerance: f32,
}

impl Default for Settings {
    /// 50 iterations, steps down to `1e-5`.
    fn default() -> Self {
        Settings {
            max_iterations: 50,
            step_tolerance: 1e-5,
        }
    }
}

/// What [`minimize`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Solution {
    /// Gauss-Newton iterations run (each one linearization and one QP solve).
    pub iterations: u32,
    /// `E` at the returned `x`.
    pub cost: f32,
    /// The last step was below the tolerance, or no step could reduce `E` any more (the
    /// limit of `f32` precision). `false` when the iterations ran out or the model was
    /// unusable (non-finite, or `H` not positive definite).
    pub converged: bool,
}

/// Most backtracking halvings of one step.
const MAX_BACKTRACKS: u32 = 12;
/// Armijo's sufficient-decrease constant.
const ARMIJO: f64 = 1e-4;

/// Minimizes `objective` over the box `lower..=upper` from `x` (moved into the box first),
/// leaving the result in `x`. Bounds must satisfy `lower <= upper` (a pair violating it is
/// treated as fixed at `lower`); infinite bounds are no bounds. Allocates nothing; never panics.
pub fn minimize<const N: usize, O: Objective<N>>(
    objective: &mut O,
    x: &mut [f32; N],
    lower: &[f32; N],
    upper: &[f32; N],
    settings: &Settings,
) -> Solution {
    let hi: [f32; N] = core::array::from_fn(|i| upper[i].max(lower[i]));
    for i in 0..N {
        x[i] = if x[i].is_nan() { lower[i] } else { x[i] };
        x[i] = x[i].max(lower[i]).min(hi[i]);
    }
    let mut model = Model::default();
    let mut cost = objective.evaluate(x, Some(&mut model));
    let mut solution = Solution {
        iterations: 0,
        cost,
        converged: false,
    };
    if !cost.is_finite() {
        return solution;
    }
    while solution.iterations < settings.max_iterations {
        solution.iterations += 1;
        let lo: [f64; N] = core::array::from_fn(|i| f64::from(lower[i] - x[i]).min(0.0));
        let up: [f64; N] = core::array::from_fn(|i| f64::from(hi[i] - x[i]).max(0.0));
        let Some(step) = box_qp(&model.hessian, &model.gradient, &lo, &up) else {
            break;
        };
        let slope: f64 = (0..N).map(|i| model.gradient[i] * step[i]).sum();
        let size = step.iter().fold(0.0_f64, |m, s| m.max(s.abs()));
        if slope >= 0.0 || slope.is_nan() || size <= f64::from(settings.step_tolerance) * 1e-3 {
            // No descent left in the model: a KKT point.
            solution.converged = true;
            break;
        }
        let mut alpha = 1.0_f64;
        let mut accepted = false;
        for _ in 0..MAX_BACKTRACKS {
            let trial: [f32; N] = core::array::from_fn(|i| {
                ((f64::from(x[i]) + alpha * step[i]) as f32)
                    .max(lower[i])
                    .min(hi[i])
            });
            let mut trial_model = Model::default();
            let c = objective.evaluate(&trial, Some(&mut trial_model));
            if c.is_finite() && f64::from(c) <= f64::from(cost) + ARMIJO * alpha * slope {
                *x = trial;
                cost = c;
                model = trial_model;
                accepted = true;
                break;
            }
            alpha *= 0.5;
        }
        solution.cost = cost;
        if !accepted || alpha * size <= f64::from(settings.step_tolerance) {
            solution.converged = true;
            break;
        }
    }
    solution
}

/// Where a coordinate stands in [`box_qp`]'s working set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Bound {
    Free,
    Lower,
    Upper,
    /// `lower == upper`: never released.
    Fixed,
}

/// Solves the strictly convex box-constrained QP
/// `minimize 1/2 s'Hs + g's subject to lower <= s <= upper` (`lower <= 0 <= upper`, so `s = 0`
/// is feasible; infinite bounds are no bounds) by the active-set method with Cholesky and Schur-complement multipliers
/// described in the module docs. `None` when `H` is not numerically positive definite or the
/// input is not finite.
#[must_use]
pub fn box_qp<const N: usize>(
    h: &[[f64; N]; N],
    g: &[f64; N],
    lower: &[f64; N],
    upper: &[f64; N],
) -> Option<[f64; N]> {
    let mut l = *h;
    if !cholesky(&mut l, N) {
        return None;
    }
    if !g.iter().all(|v| v.is_finite()) || lower.iter().chain(upper).any(|v| v.is_nan()) {
        return None;
    }
    // Start at s = 0 with the bounds that are active there and that the gradient pushes
    // against.
    let mut p = [0.0_f64; N];
    let mut state = [Bound::Free; N];
    for i in 0..N {
        state[i] = if upper[i] - lower[i] <= 0.0 {
            Bound::Fixed
        } else if lower[i] >= 0.0 && g[i] > 0.0 {
            Bound::Lower
        } else if upper[i] <= 0.0 && g[i] < 0.0 {
            Bound::Upper
        } else {
            Bound::Free
        };
    }
    let scale = 1.0 + g.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    for _ in 0..4 * N + 4 {
        // grad = H p + g; u = H^-1 grad.
        let mut grad = *g;
        for i in 0..N {
            for j in 0..N {
                grad[i] += h[i][j] * p[j];
            }
        }
        let mut u = grad;
        cholesky_solve(&l, N, &mut u);
        // The working set's columns of H^-1 and the Schur complement S = E H^-1 E'.
        let mut idx = [0usize; N];
        let mut m = 0;
        for i in 0..N {
            if state[i] != Bound::Free {
                idx[m] = i;
                m += 1;
            }
        }
        let mut cols = [[0.0_f64; N]; N];
        let mut s_mat = [[0.0_f64; N]; N];
        let mut lambda = [0.0_f64; N];
        for a in 0..m {
            cols[a][idx[a]] = 1.0;
            cholesky_solve(&l, N, &mut cols[a]);
        }
        for a in 0..m {
            for b in 0..m {
                s_mat[a][b] = cols[b][idx[a]];
            }
            lambda[a] = -u[idx[a]];
        }
        if m > 0 {
            if !cholesky(&mut s_mat, m) {
                return None;
            }
            cholesky_solve(&s_mat, m, &mut lambda);
        }
        // The step toward the working set's optimum: -H^-1 (grad + E' lambda).
        let mut step = [0.0_f64; N];
        for i in 0..N {
            step[i] = -u[i];
            for a in 0..m {
                step[i] -= lambda[a] * cols[a][i];
            }
        }
        for a in 0..m {
            step[idx[a]] = 0.0;
        }
        let size = step.iter().fold(0.0_f64, |mx, v| mx.max(v.abs()));
        if size <= 1e-13 * (1.0 + p.iter().fold(0.0_f64, |mx, v| mx.max(v.abs()))) {
            // Optimal for this working set: release the bound whose multiplier says it
            // holds the solution back most (lower bound: lambda > 0 means grad < 0 there).
            let mut worst = None;
            let mut worst_v = 1e-12 * scale;
            for a in 0..m {
                let v = match state[idx[a]] {
                    Bound::Lower => lambda[a],
                    Bound::Upper => -lambda[a],
                    _ => 0.0,
                };
                if v > worst_v {
                    worst_v = v;
                    worst = Some(idx[a]);
                }
            }
            match worst {
                Some(i) => state[i] = Bound::Free,
                None => return Some(p),
            }
            continue;
        }
        // Walk toward it until a free coordinate hits a bound.
        let mut alpha = 1.0_f64;
        let mut blocking = None;
        for i in 0..N {
            if state[i] != Bound::Free {
                continue;
            }
            let (t, b) = if step[i] < 0.0 {
                ((lower[i] - p[i]) / step[i], Bound::Lower)
            } else if step[i] > 0.0 {
                ((upper[i] - p[i]) / step[i], Bound::Upper)
            } else {
                continue;
            };
            if t < alpha {
                alpha = t.max(0.0);
                blocking = Some((i, b));
            }
        }
        for i in 0..N {
            p[i] += alpha * step[i];
        }
        if let Some((i, b)) = blocking {
            state[i] = b;
            p[i] = if b == Bound::Lower {
                lower[i]
            } else {
                upper[i]
            };
        }
    }
    Some(p)
}

/// In-place Cholesky factorization `A = LL'` of the leading `n` x `n` block (lower triangle
/// read and overwritten with `L`; the strict upper triangle is zeroed). `false` when not
/// positive definite.
fn cholesky<const N: usize>(a: &mut [[f64; N]; N], n: usize) -> bool {
    for j in 0..n {
        let mut d = a[j][j];
        for k in 0..j {
            d -= a[j][k] * a[j][k];
        }
        if d <= 0.0 || !d.is_finite() {
            return false;
        }
        let d = d.sqrt();
        a[j][j] = d;
        for i in j + 1..n {
            let mut v = a[i][j];
            for k in 0..j {
                v -= a[i][k] * a[j][k];
            }
            a[i][j] = v / d;
            a[j][i] = 0.0;
        }
    }
    true
}

/// Solves `LL' x = b` in place for the leading `n` entries, `L` from [`cholesky`].
fn cholesky_solve<const N: usize>(l: &[[f64; N]; N], n: usize, b: &mut [f64; N]) {
    for i in 0..n {
        let mut v = b[i];
        for k in 0..i {
            v -= l[i][k] * b[k];
        }
        b[i] = v / l[i][i];
    }
    for i in (0..n).rev() {
        let mut v = b[i];
        for k in i + 1..n {
            v -= l[k][i] * b[k];
        }
        b[i] = v / l[i][i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tiny deterministic generator (tests only; the crate has no RNG dependency).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((self.0 >> 11) as f64) / ((1u64 << 53) as f64) * 2.0 - 1.0
        }
    }

    fn random_qp(rng: &mut Lcg) -> ([[f64; 5]; 5], [f64; 5], [f64; 5], [f64; 5]) {
        // H = A'A + 0.05 I: positive definite, condition up to a few hundred.
        let a: [[f64; 5]; 5] = core::array::from_fn(|_| core::array::from_fn(|_| rng.next()));
        let mut h = [[0.0; 5]; 5];
        for i in 0..5 {
            for j in 0..5 {
                h[i][j] = (0..5).map(|k| a[k][i] * a[k][j]).sum::<f64>();
            }
            h[i][i] += 0.05;
        }
        let g = core::array::from_fn(|_| 3.0 * rng.next());
        let lo = core::array::from_fn(|i| if i == 4 { 0.0 } else { -rng.next().abs() });
        let up = core::array::from_fn(|_| 0.5 * rng.next().abs());
        (h, g, lo, up)
    }

    #[test]
    fn box_qp_satisfies_the_kkt_conditions() {
        let mut rng = Lcg(7);
        let mut active_seen = 0;
        for case in 0..500 {
            let (h, g, lo, up) = random_qp(&mut rng);
            let s = box_qp(&h, &g, &lo, &up).expect("positive definite");
            for i in 0..5 {
                let grad = g[i] + (0..5).map(|j| h[i][j] * s[j]).sum::<f64>();
                assert!(
                    s[i] >= lo[i] - 1e-12 && s[i] <= up[i] + 1e-12,
                    "case {case}"
                );
                let at_lo = (s[i] - lo[i]).abs() < 1e-10;
                let at_up = (s[i] - up[i]).abs() < 1e-10;
                if at_lo || at_up {
                    active_seen += 1;
                }
                // Free: stationary. At a bound: the gradient points into the box.
                let ok = (grad.abs() < 1e-8)
                    || (at_lo && grad > 0.0)
                    || (at_up && grad < 0.0)
                    || (at_lo && at_up);
                assert!(ok, "case {case} coordinate {i}: s {s:?} grad {grad}");
            }
        }
        // The cases exercise the constraints, not just the unconstrained solve.
        assert!(active_seen > 500, "{active_seen}");
    }

    #[test]
    fn box_qp_without_active_bounds_is_the_newton_step() {
        let h = [[2.0, 0.5], [0.5, 1.0]];
        let g = [1.0, -1.0];
        let s = box_qp(&h, &g, &[-10.0; 2], &[10.0; 2]).unwrap();
        // H s = -g.
        assert!((2.0 * s[0] + 0.5 * s[1] + 1.0).abs() < 1e-12);
        assert!((0.5 * s[0] + s[1] - 1.0).abs() < 1e-12);
        assert!(box_qp(&[[1.0, 2.0], [2.0, 1.0]], &g, &[-1.0; 2], &[1.0; 2]).is_none());
    }

    /// Rosenbrock as least squares, `r = (10 (y - x^2), 1 - x)`, with a temporal-style
    /// damping term so the model is positive definite.
    struct Rosenbrock {
        anchor: [f32; 2],
    }

    impl Objective<2> for Rosenbrock {
        fn evaluate(&mut self, x: &[f32; 2], model: Option<&mut Model<2>>) -> f32 {
            let (r0, r1) = (10.0 * (x[1] - x[0] * x[0]), 1.0 - x[0]);
            let d = [x[0] - self.anchor[0], x[1] - self.anchor[1]];
            let reg = 1e-6;
            match model {
                Some(m) => {
                    m.add_scalar(1.0, r0, &[-20.0 * x[0], 10.0])
                        + m.add_scalar(1.0, r1, &[-1.0, 0.0])
                        + m.add_scalar(reg, d[0], &[1.0, 0.0])
                        + m.add_scalar(reg, d[1], &[0.0, 1.0])
                }
                None => 0.5 * (r0 * r0 + r1 * r1) + 0.5 * reg * (d[0] * d[0] + d[1] * d[1]),
            }
        }
    }

    #[test]
    fn gauss_newton_finds_the_unconstrained_and_the_constrained_minimum() {
        let mut p = Rosenbrock {
            anchor: [-1.2, 1.0],
        };
        let mut x = [-1.2, 1.0];
        let s = minimize(&mut p, &mut x, &[-5.0; 2], &[5.0; 2], &Settings::default());
        assert!(s.converged, "{s:?}");
        assert!(
            (x[0] - 1.0).abs() < 1e-3 && (x[1] - 1.0).abs() < 1e-3,
            "{x:?}"
        );
        // With y <= 0.5 the minimum is on the bound (the free minimum has y = 1): there the
        // derivative along the bound of 50 (0.5 - x^2)^2 + (1 - x)^2 / 2 vanishes and the one
        // across it pushes outward.
        let mut x = [-1.2, 0.4];
        let s = minimize(
            &mut p,
            &mut x,
            &[-5.0, -5.0],
            &[5.0, 0.5],
            &Settings::default(),
        );
        assert!(s.converged, "{s:?}");
        assert_eq!(x[1], 0.5);
        let dfdx = |x: f32| -200.0 * x * (0.5 - x * x) - (1.0 - x);
        assert!(dfdx(x[0]).abs() < 1e-3, "x {x:?} slope {}", dfdx(x[0]));
        assert!(
            100.0 * (0.5 - x[0] * x[0]) < 0.0,
            "the bound holds y back: {x:?}"
        );
    }

    #[test]
    fn minimize_keeps_the_box_and_survives_bad_input() {
        let mut p = Rosenbrock { anchor: [0.0; 2] };
        let mut x = [f32::NAN, 9.0];
        let s = minimize(
            &mut p,
            &mut x,
            &[-0.5, -0.5],
            &[0.2, 0.3],
            &Settings::default(),
        );
        assert!(x.iter().all(|v| v.is_finite()));
        assert!(x[0] >= -0.5 && x[0] <= 0.2 && x[1] >= -0.5 && x[1] <= 0.3);
        assert!(s.cost.is_finite());
        // Inverted bounds: the coordinate is held at the lower bound.
        let mut x = [0.3, 0.3];
        minimize(
            &mut p,
            &mut x,
            &[0.1, -1.0],
            &[0.0, 1.0],
            &Settings::default(),
        );
        assert_eq!(x[0], 0.1);
    }
}
