//! A standalone chain IK solver for any chain (tails, spines, custom rigs): the Rust side of
//! the JS `ChainSolver`.
//!
//! ```text
//! let mut solver = ChainSolver::new(&ChainSolverOptions {
//!     method: ChainMethod::Fabrik,
//!     joints: vec![root, j1, j2, end],          // rest positions, root first, >= 3
//!     constraints: vec![None, Some(JointLimit::Cone { max_angle: 0.5 }), None],
//!     ..ChainSolverOptions::default()
//! })?;
//! let solution = solver.solve(target, Some(pole))?;
//! // solution.joints, solution.rotations (x y z w from each bone's rest direction),
//! // solution.status.reached / error / iterations
//! ```
//!
//! The solver owns every buffer: setup allocates, [`ChainSolver::solve`] and
//! [`ChainSolver::solve_into`] allocate nothing. Each solve starts from the previous solution
//! (a warm start, so a moving target gives a continuous motion); [`ChainSolver::reset`] goes
//! back to rest. The root stays at its rest position.
//!
//! Rotations are each bone's world rotation from its rest direction: its parent's rotation
//! followed by the minimal swing onto its solved direction (see [`crate::kinematics::chain`]),
//! so a chain of normalized bones takes `parent⁻¹ * rotation` as local rotations.
//!
//! Degenerate goals have a defined answer: a target at the root folds the chain as far as it
//! goes (FABRIK's passes from the last pose), a pole on the root-to-target line or at the
//! root is ignored, a target beyond reach gives the straight chain toward it. A non-finite
//! target or pole is an error naming the field.

use glam::{Quat, Vec3};

use crate::error::{Error, Result};
use crate::kinematics::{Chain, JointLimit};

use super::ccd::{Ccd, CcdOptions};
use super::fabrik::{Fabrik, FabrikOptions};
use super::goal::{ChainGoal, ChainReport, Effector};

/// Which method a [`ChainSolver`] uses (JS: `method`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "camelCase")]
#[non_exhaustive]
pub enum ChainMethod {
    /// `"fabrik"`: FABRIK ([`Fabrik`], seed 002).
    #[default]
    Fabrik,
    /// `"ccd"`: CCD ([`Ccd`], seed 004).
    Ccd,
}

/// Setup of a [`ChainSolver`] (JS: the constructor's argument, same camelCase names; from
/// JSON: [`ChainSolverOptions::from_json`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ChainSolverOptions {
    /// The method. Default `"fabrik"`.
    pub method: ChainMethod,
    /// Rest joint positions (m), root first; at least 3, no two consecutive ones equal.
    pub joints: Vec<Vec3>,
    /// One limit per bone (`None`/`null` for a free bone), or empty for none. Default none.
    pub constraints: Vec<Option<JointLimit>>,
    /// Most iterations per solve; `None` for the method's default (FABRIK 100, CCD 200).
    pub iterations: Option<u32>,
    /// End-to-target distance (m) that counts as reached; `None` for 1e-5 of the chain's
    /// length.
    pub tolerance: Option<f32>,
    /// CCD's damping: the largest angle (radians) one joint turns per step; `None` for the
    /// default 0.5. Ignored by FABRIK.
    pub max_step_angle: Option<f32>,
}

impl Default for ChainSolverOptions {
    /// FABRIK, no joints yet (set [`ChainSolverOptions::joints`]), no limits, the method's
    /// default iterations and tolerance.
    fn default() -> Self {
        ChainSolverOptions {
            method: ChainMethod::Fabrik,
            joints: Vec::new(),
            constraints: Vec::new(),
            iterations: None,
            tolerance: None,
            max_step_angle: None,
        }
    }
}

/// The JSON form of [`ChainSolverOptions`] (serde): `joints` required, every other field
/// optional (`null` for an unset optional number), no other field. Other fields are collected
/// rather than denied by serde: serde-wasm-bindgen reads a struct by looking up its declared
/// fields only, so `deny_unknown_fields` would never see them; a flattened map makes every
/// reader go through all of the object's keys.
#[derive(serde::Deserialize)]
#[serde(rename_all = "camelCase")]
struct ChainSolverJson {
    #[serde(default)]
    method: ChainMethod,
    joints: Vec<[f32; 3]>,
    /// `null` (or, from JS, `undefined`) is none, as when left out.
    #[serde(default)]
    constraints: Option<Vec<Option<JointLimit>>>,
    #[serde(default)]
    iterations: Option<u32>,
    #[serde(default)]
    tolerance: Option<f32>,
    #[serde(default)]
    max_step_angle: Option<f32>,
    #[serde(flatten)]
    unknown: std::collections::BTreeMap<String, serde::de::IgnoredAny>,
}

/// The fields of [`ChainSolverJson`], for the error naming an unknown one.
const CHAIN_FIELDS: &str = "method, joints, constraints, iterations, tolerance, maxStepAngle";

impl ChainSolverOptions {
    /// Reads the options from JSON text: `{ method, joints, constraints, iterations,
    /// tolerance, maxStepAngle }` (see the fields; `joints` is required, as `[x, y, z]`
    /// arrays; constraints as [`JointLimit`]'s JSON form). The values are checked later, by
    /// [`ChainSolver::new`].
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the field (`options.constraints[1].maxAngle`): text
    /// that is not JSON, a wrong type, an unknown or missing name.
    pub fn from_json(text: &str) -> Result<ChainSolverOptions> {
        let mut de = serde_json::Deserializer::from_str(text);
        Self::deserialize_from(&mut de)
    }

    /// Reads the options from any serde deserializer (the wasm binding's JS object); errors
    /// as [`ChainSolverOptions::from_json`].
    ///
    /// # Errors
    /// As [`ChainSolverOptions::from_json`].
    pub fn deserialize_from<'de, D: serde::Deserializer<'de>>(de: D) -> Result<ChainSolverOptions>
    where
        D::Error: core::fmt::Display,
    {
        let o: ChainSolverJson = serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            let field = if path == "." {
                "options".to_string()
            } else {
                format!("options.{path}")
            };
            Error::invalid(field, e.inner().to_string())
        })?;
        if let Some(key) = o.unknown.keys().next() {
            return Err(Error::invalid(
                format!("options.{key}"),
                format!("unknown option (expected one of {CHAIN_FIELDS})"),
            ));
        }
        Ok(ChainSolverOptions {
            method: o.method,
            joints: o.joints.into_iter().map(Vec3::from_array).collect(),
            constraints: o.constraints.unwrap_or_default(),
            iterations: o.iterations,
            tolerance: o.tolerance,
            max_step_angle: o.max_step_angle,
        })
    }
}

/// A solved chain, borrowed from the solver.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainSolution<'a> {
    /// Joint positions, root first.
    pub joints: &'a [Vec3],
    /// Each bone's world rotation from its rest direction.
    pub rotations: &'a [Quat],
    /// Reached, error, iterations.
    pub status: ChainReport,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Method {
    Fabrik(Fabrik),
    Ccd(Ccd),
}

/// FABRIK or CCD over one chain, owning its pose and buffers (see the module docs).
#[derive(Clone, Debug)]
pub struct ChainSolver {
    chain: Chain,
    method: Method,
    joints: Vec<Vec3>,
    rotations: Vec<Quat>,
    status: ChainReport,
}

/// Largest magnitude of a coordinate of the joints, the target and the pole, in the chain's
/// unit of length: far larger (finite) numbers overflow squared distances into infinities, and a
/// chain solved toward such a target would not move.
pub const COORDINATE_LIMIT: f32 = 1e9;

const RANGE: &str = "must be three numbers within -1e9..1e9";

/// A finite point with a coordinate beyond [`COORDINATE_LIMIT`].
fn out_of_range(p: Vec3) -> bool {
    p.abs().max_element() > COORDINATE_LIMIT
}

impl ChainSolver {
    /// Reads the chain and checks every option.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the field: fewer than 3 joints (`joints`), a non-finite
    /// joint, one beyond [`COORDINATE_LIMIT`] or a zero-length bone (`joints[k]`), a
    /// constraint count other than 0 or N - 1 (`constraints`), a bad limit
    /// (`constraints[i].maxAngle`, `constraints[i].axis`, ...),
    /// `iterations` of 0, a non-positive `tolerance`, `maxStepAngle` outside `(0, pi]`.
    pub fn new(options: &ChainSolverOptions) -> Result<Self> {
        if let Some(k) = options.joints.iter().position(|p| out_of_range(*p)) {
            return Err(Error::invalid(format!("joints[{k}]"), RANGE));
        }
        if options.joints.len() < 3 {
            return Err(Error::invalid(
                "joints",
                format!(
                    "needs at least 3 joints (2 bones), got {}",
                    options.joints.len()
                ),
            ));
        }
        let chain = Chain::new(&options.joints, &options.constraints)?;
        let tolerance = match options.tolerance {
            Some(t) => t,
            None => 1e-5 * chain.total_length(),
        };
        let method = match options.method {
            ChainMethod::Fabrik => Method::Fabrik(Fabrik::new(FabrikOptions {
                iterations: options
                    .iterations
                    .unwrap_or(FabrikOptions::default().iterations),
                tolerance,
            })?),
            ChainMethod::Ccd => {
                let d = CcdOptions::default();
                Method::Ccd(Ccd::new(CcdOptions {
                    iterations: options.iterations.unwrap_or(d.iterations),
                    tolerance,
                    max_step_angle: options.max_step_angle.unwrap_or(d.max_step_angle),
                })?)
            }
        };
        let n = chain.joint_count();
        let mut solver = ChainSolver {
            joints: chain.rest_joints().to_vec(),
            rotations: vec![Quat::IDENTITY; n - 1],
            status: ChainReport::failed(),
            chain,
            method,
        };
        solver.reset();
        Ok(solver)
    }

    /// The chain (lengths, rest directions, limits).
    #[must_use]
    pub fn chain(&self) -> &Chain {
        &self.chain
    }

    /// The method in use.
    #[must_use]
    pub fn method(&self) -> ChainMethod {
        match self.method {
            Method::Fabrik(_) => ChainMethod::Fabrik,
            Method::Ccd(_) => ChainMethod::Ccd,
        }
    }

    /// Number of joints `N` (the solve-into `joints` buffer holds `3 N` numbers, `rotations`
    /// `4 (N - 1)`).
    #[must_use]
    pub fn joint_count(&self) -> usize {
        self.chain.joint_count()
    }

    /// Back to the rest pose (the next solve starts from there).
    pub fn reset(&mut self) {
        self.joints.copy_from_slice(self.chain.rest_joints());
        self.rotations.fill(Quat::IDENTITY);
        self.status = ChainReport::failed();
    }

    /// The current pose (the last solution, or rest).
    #[must_use]
    pub fn solution(&self) -> ChainSolution<'_> {
        ChainSolution {
            joints: &self.joints,
            rotations: &self.rotations,
            status: self.status,
        }
    }

    /// Solves for `target` with an optional `pole` (see [`ChainGoal`]). Allocates nothing.
    ///
    /// # Errors
    /// A non-finite `target` or `pole`, or one beyond [`COORDINATE_LIMIT`] (fields `target`,
    /// `pole`); the pose is unchanged.
    pub fn solve(&mut self, target: Vec3, pole: Option<Vec3>) -> Result<ChainSolution<'_>> {
        self.solve_goal(&ChainGoal::new(target, pole))
    }

    /// Solves a full [`ChainGoal`] (end rotation, pole's first joint). Allocates nothing.
    ///
    /// # Errors
    /// A non-finite `target`, `pole` or `endRotation`; a `target` or `pole` beyond
    /// [`COORDINATE_LIMIT`].
    pub fn solve_goal(&mut self, goal: &ChainGoal) -> Result<ChainSolution<'_>> {
        if !goal.target.is_finite() {
            return Err(Error::invalid("target", "must be three finite numbers"));
        }
        if out_of_range(goal.target) {
            return Err(Error::invalid("target", RANGE));
        }
        if goal.pole.is_some_and(|p| !p.is_finite()) {
            return Err(Error::invalid("pole", "must be three finite numbers"));
        }
        if goal.pole.is_some_and(out_of_range) {
            return Err(Error::invalid("pole", RANGE));
        }
        if goal
            .end_rotation
            .is_some_and(|q| !(q.is_finite() && q.length_squared() > 0.5))
        {
            return Err(Error::invalid(
                "endRotation",
                "must be a unit quaternion [x, y, z, w]",
            ));
        }
        let root = self.chain.rest_root();
        let end_direction = goal.end_direction(&self.chain);
        self.status = match &self.method {
            Method::Fabrik(f) => f.solve(
                &self.chain,
                &root,
                goal,
                &mut self.joints,
                &mut self.rotations,
            ),
            Method::Ccd(c) => {
                let n = self.chain.joint_count();
                // A pinned last bone: the effector is its root, the target moved back along it.
                let effector = match end_direction {
                    Some(d) => Effector {
                        joint: n - 2,
                        offset: Vec3::ZERO,
                        target: goal.target - d * self.chain.lengths()[n - 2],
                        first_joint: 0,
                    },
                    None => Effector::end(&self.chain, goal.target),
                };
                let mut status = c.solve(
                    &self.chain,
                    &root,
                    &[effector],
                    super::ccd::Guides {
                        pole: goal.pole.map(|p| (p, goal.pole_first)),
                        end_direction,
                    },
                    &mut self.joints,
                    &mut self.rotations,
                );
                status.error = (self.joints[n - 1] - goal.target).length();
                status.reached = status.error <= c.options().tolerance;
                status
            }
        };
        if let (Some(q), Some(last)) = (goal.end_rotation, self.rotations.last_mut()) {
            // The pinned bone takes the goal's rotation (with its twist), turned minimally
            // onto the direction it got.
            let q = q.normalize();
            let n = self.joints.len();
            let want = q * self.chain.rest_directions()[n - 2];
            let got = (self.joints[n - 1] - self.joints[n - 2]).normalize();
            *last = (crate::kinematics::swing(want, got, want.any_orthonormal_vector()) * q)
                .normalize();
        }
        Ok(self.solution())
    }

    /// [`ChainSolver::solve`] into caller storage: `joints` gets `3 N` numbers (x y z per
    /// joint, root first), `rotations` `4 (N - 1)` (x y z w per bone). Allocates nothing.
    ///
    /// # Errors
    /// A buffer of the wrong length (fields `joints`, `rotations` of the output), a
    /// non-finite `target` or `pole`.
    pub fn solve_into(
        &mut self,
        target: Vec3,
        pole: Option<Vec3>,
        joints: &mut [f32],
        rotations: &mut [f32],
    ) -> Result<ChainReport> {
        let n = self.chain.joint_count();
        if joints.len() != 3 * n {
            return Err(Error::invalid(
                "out.joints",
                format!("must hold 3 * {n} numbers, has {}", joints.len()),
            ));
        }
        if rotations.len() != 4 * (n - 1) {
            return Err(Error::invalid(
                "out.rotations",
                format!("must hold 4 * {} numbers, has {}", n - 1, rotations.len()),
            ));
        }
        let status = self.solve(target, pole)?.status;
        for (dst, p) in joints.chunks_exact_mut(3).zip(&self.joints) {
            dst.copy_from_slice(&p.to_array());
        }
        for (dst, q) in rotations.chunks_exact_mut(4).zip(&self.rotations) {
            dst.copy_from_slice(&q.to_array());
        }
        Ok(status)
    }
}
