//! The raw `ChainSolver` class: FABRIK or CCD on any chain (tails, spines, custom rigs), with
//! flat buffers in wasm memory like `HandRig`. The package's JS layer (`ChainSolver` in
//! `pkg-config/src/chain-solver.ts`) writes the goal and reads the pose through typed-array
//! views, so a solve moves no JS value and allocates nothing.

use glam::Vec3;
use wasm_bindgen::prelude::*;

use crate::ik::{ChainSolver, ChainSolverOptions};

/// Goal buffer: target `x y z`, a pole flag, pole `x y z`.
const GOAL_LEN: usize = 7;

/// A chain solver with its goal and pose buffers. `free()` when done.
#[wasm_bindgen(js_name = RawChainSolver)]
pub struct RawChainSolver {
    solver: ChainSolver,
    goal: Box<[f32]>,
    /// Joints `3 N`, then rotations `4 (N - 1)`, then reached, reachable, error, iterations.
    pose: Box<[f32]>,
    error: Option<String>,
}

#[wasm_bindgen(js_class = RawChainSolver)]
impl RawChainSolver {
    /// `options`: a plain object (the JS layer's checked copy of the user's), `{ method,
    /// joints, constraints, iterations, tolerance, maxStepAngle }`, read with
    /// serde-wasm-bindgen into a JSON value as the rig's options are (the same code), then
    /// walked by [`ChainSolverOptions::from_value`].
    #[wasm_bindgen(constructor)]
    pub fn new(options: JsValue) -> Result<RawChainSolver, JsError> {
        let options = serde_wasm_bindgen::from_value::<serde_json::Value>(options)
            .map_err(|e| JsError::new(&format!("options: {e}")))
            .and_then(|v| {
                ChainSolverOptions::from_value(&v).map_err(|e| JsError::new(&e.to_string()))
            })?;
        let solver = ChainSolver::new(&options).map_err(|e| JsError::new(&e.to_string()))?;
        let n = solver.joint_count();
        Ok(RawChainSolver {
            solver,
            goal: vec![0.0; GOAL_LEN].into_boxed_slice(),
            pose: vec![0.0; 3 * n + 4 * (n - 1) + 4].into_boxed_slice(),
            error: None,
        })
    }

    /// Number of joints.
    #[wasm_bindgen(getter, js_name = jointCount)]
    pub fn joint_count(&self) -> usize {
        self.solver.joint_count()
    }

    /// Byte offset of the goal buffer (7 floats) in wasm memory.
    #[wasm_bindgen(js_name = goalPtr)]
    pub fn goal_ptr(&self) -> u32 {
        self.goal.as_ptr() as u32
    }

    /// Byte offset of the pose buffer in wasm memory.
    #[wasm_bindgen(js_name = posePtr)]
    pub fn pose_ptr(&self) -> u32 {
        self.pose.as_ptr() as u32
    }

    /// Length of the pose buffer (floats).
    #[wasm_bindgen(getter, js_name = poseLength)]
    pub fn pose_length(&self) -> usize {
        self.pose.len()
    }

    /// Solves toward the goal buffer into the pose buffer; 0, or 1 with `takeError()` set.
    #[wasm_bindgen(js_name = solveFlat)]
    pub fn solve_flat(&mut self) -> u32 {
        let g = &self.goal;
        let target = Vec3::new(g[0], g[1], g[2]);
        let pole = (g[3] == 1.0).then(|| Vec3::new(g[4], g[5], g[6]));
        let n = self.solver.joint_count();
        let (joints, rest) = self.pose.split_at_mut(3 * n);
        let (rotations, status) = rest.split_at_mut(4 * (n - 1));
        match self.solver.solve_into(target, pole, joints, rotations) {
            Ok(report) => {
                status[0] = f32::from(u8::from(report.reached));
                status[1] = f32::from(u8::from(report.reachable));
                status[2] = report.error;
                status[3] = report.iterations as f32;
                0
            }
            Err(e) => {
                self.error = Some(e.to_string());
                1
            }
        }
    }

    /// The message of the last failed solve (once).
    #[wasm_bindgen(js_name = takeError)]
    pub fn take_error(&mut self) -> Option<String> {
        self.error.take()
    }

    /// Back to the rest pose (the next solve starts from rest).
    pub fn reset(&mut self) {
        self.solver.reset();
    }
}
