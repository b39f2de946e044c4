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

use serde_json::Value as Json;

use crate::error::{Error, Result};
use crate::kinematics::{Chain, JointLimit};
use crate::options::describe;

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

/// The fields of the options' JSON form, for the error naming an unknown one.
const CHAIN_FIELDS: &str = "method, joints, constraints, iterations, tolerance, maxStepAngle";

/// `options.{path}`, the name of a field in errors.
fn field(path: &str) -> String {
    format!("options.{path}")
}

/// A field's value as an `f32`.
fn number(v: &Json, path: &str) -> Result<f32> {
    match v.as_f64() {
        #[allow(clippy::cast_possible_truncation)]
        Some(x) => Ok(x as f32),
        None => Err(Error::invalid(
            field(path),
            format!("must be a number, got {}", describe(v)),
        )),
    }
}

/// A field's value as three numbers `[x, y, z]`.
fn point(v: &Json, path: &str) -> Result<Vec3> {
    match v.as_array() {
        Some(a) if a.len() == 3 => Ok(Vec3::new(
            number(&a[0], &format!("{path}[0]"))?,
            number(&a[1], &format!("{path}[1]"))?,
            number(&a[2], &format!("{path}[2]"))?,
        )),
        _ => Err(Error::invalid(
            field(path),
            format!("must be three numbers [x, y, z], got {}", describe_len(v)),
        )),
    }
}

/// [`describe`], with an array's length.
fn describe_len(v: &Json) -> String {
    match v.as_array() {
        Some(a) => format!("an array of {}", a.len()),
        None => describe(v),
    }
}

/// An optional number: absent or `null` is `None`.
fn optional(o: &serde_json::Map<String, Json>, key: &str) -> Result<Option<f32>> {
    match o.get(key) {
        None | Some(Json::Null) => Ok(None),
        Some(v) => number(v, key).map(Some),
    }
}

/// A limit's JSON form: `{ "type": "cone", "maxAngle" }` or `{ "type": "hinge", "axis",
/// "min", "max" }`, no other field.
fn limit(v: &Json, path: &str) -> Result<JointLimit> {
    let Json::Object(o) = v else {
        return Err(Error::invalid(
            field(path),
            format!(
                "must be {{ type: \"cone\", maxAngle }} or {{ type: \"hinge\", axis, min, max }} or null, got {}",
                describe(v)
            ),
        ));
    };
    let get = |key: &str| {
        o.get(key).ok_or_else(|| {
            Error::invalid(
                field(&format!("{path}.{key}")),
                "missing (a number is required)",
            )
        })
    };
    let (limit, keys): (JointLimit, &[&str]) = match o.get("type").and_then(Json::as_str) {
        Some("cone") => (
            JointLimit::Cone {
                max_angle: number(get("maxAngle")?, &format!("{path}.maxAngle"))?,
            },
            &["type", "maxAngle"],
        ),
        Some("hinge") => (
            JointLimit::Hinge {
                axis: point(get("axis")?, &format!("{path}.axis"))?,
                min: number(get("min")?, &format!("{path}.min"))?,
                max: number(get("max")?, &format!("{path}.max"))?,
            },
            &["type", "axis", "min", "max"],
        ),
        _ => {
            return Err(Error::invalid(
                field(&format!("{path}.type")),
                format!(
                    "must be \"cone\" or \"hinge\", got {}",
                    o.get("type").map_or("nothing".into(), describe)
                ),
            ))
        }
    };
    if let Some(key) = o.keys().find(|k| !keys.contains(&k.as_str())) {
        return Err(Error::invalid(
            field(&format!("{path}.{key}")),
            format!("unknown field (expected one of {})", keys.join(", ")),
        ));
    }
    Ok(limit)
}

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
        let value: Json =
            serde_json::from_str(text).map_err(|e| Error::invalid("options", e.to_string()))?;
        Self::from_value(&value)
    }

    /// Reads the options from any serde deserializer (the wasm binding's JS object, read into
    /// a JSON value); errors as [`ChainSolverOptions::from_json`].
    ///
    /// # Errors
    /// As [`ChainSolverOptions::from_json`].
    pub fn deserialize_from<'de, D: serde::Deserializer<'de>>(de: D) -> Result<ChainSolverOptions>
    where
        D::Error: core::fmt::Display,
    {
        let value = <Json as serde::Deserialize>::deserialize(de)
            .map_err(|e| Error::invalid("options", e.to_string()))?;
        Self::from_value(&value)
    }

    /// Reads the options from a JSON value; errors as [`ChainSolverOptions::from_json`].
    ///
    /// # Errors
    /// As [`ChainSolverOptions::from_json`].
    pub fn from_value(value: &Json) -> Result<ChainSolverOptions> {
        let Json::Object(o) = value else {
            return Err(Error::invalid(
                "options",
                format!(
                    "must be an object {{ method?, joints, constraints?, ... }}, got {}",
                    describe(value)
                ),
            ));
        };
        if let Some(key) = o
            .keys()
            .find(|k| !CHAIN_FIELDS.split(", ").any(|f| f == k.as_str()))
        {
            return Err(Error::invalid(
                field(key),
                format!("unknown option (expected one of {CHAIN_FIELDS})"),
            ));
        }
        let method = match o.get("method") {
            None | Some(Json::Null) => ChainMethod::Fabrik,
            Some(Json::String(m)) if m == "fabrik" => ChainMethod::Fabrik,
            Some(Json::String(m)) if m == "ccd" => ChainMethod::Ccd,
            Some(v) => {
                return Err(Error::invalid(
                    "options.method",
                    format!("must be \"fabrik\" or \"ccd\", got {}", describe(v)),
                ))
            }
        };
        let joints = match o.get("joints") {
            Some(Json::Array(a)) => a
                .iter()
                .enumerate()
                .map(|(k, p)| point(p, &format!("joints[{k}]")))
                .collect::<Result<Vec<_>>>()?,
            v => {
                return Err(Error::invalid(
                    "options.joints",
                    format!(
                        "must be an array of [x, y, z] rest joint positions, root first, got {}",
                        v.map_or("nothing".into(), describe)
                    ),
                ))
            }
        };
        let constraints = match o.get("constraints") {
            None | Some(Json::Null) => Vec::new(),
            Some(Json::Array(a)) => a
                .iter()
                .enumerate()
                .map(|(i, c)| match c {
                    Json::Null => Ok(None),
                    c => limit(c, &format!("constraints[{i}]")).map(Some),
                })
                .collect::<Result<Vec<_>>>()?,
            Some(v) => {
                return Err(Error::invalid(
                    "options.constraints",
                    format!(
                        "must be an array (one entry per bone, or null), got {}",
                        describe(v)
                    ),
                ))
            }
        };
        let iterations =
            match o.get("iterations") {
                None | Some(Json::Null) => None,
                Some(v) => Some(v.as_u64().and_then(|n| u32::try_from(n).ok()).ok_or_else(
                    || {
                        Error::invalid(
                            "options.iterations",
                            format!("must be a whole number, got {}", describe(v)),
                        )
                    },
                )?),
            };
        Ok(ChainSolverOptions {
            method,
            joints,
            constraints,
            iterations,
            tolerance: optional(o, "tolerance")?,
            max_step_angle: optional(o, "maxStepAngle")?,
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
