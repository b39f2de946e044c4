//! Small numerical solvers shared by the kinematic methods: fixed-capacity, allocation-free,
//! sized for a handful of joint angles.
//!
//! * [`least_squares`]: Gauss-Newton for nonlinear least squares with box constraints (joint
//!   limits), each step an exact convex QP solved by an active set with Lagrange multipliers
//!   from a Cholesky factorization and a Schur complement (seed 003, section 3.1).

pub mod least_squares;
