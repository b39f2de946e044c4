//! handrig's integration tests, one binary with a module per topic (each file's header says
//! what it checks and on which data). Native only: they read the shared recordings and
//! fixtures from disk; `tests/wasm.rs` is the wasm32 suite (`wasm-pack test --node`).
//!
//! `cargo test --test it <filter>` runs one topic, e.g. `cargo test --test it golden`.

#![cfg(not(target_arch = "wasm32"))]

use handrig_support as support;

mod alignment;
mod arm_body;
mod arm_idle;
mod arm_ik;
mod arm_solvers;
mod bad_frames;
mod chain_ik;
mod contact;
mod dups;
mod face;
mod flips;
mod fuzz;
mod fuzz_gltf;
mod gltf;
mod golden;
mod hand_loss;
mod hand_props;
mod hand_real;
mod hand_rig;
mod hand_synthetic;
mod legs;
mod live;
mod missing_bones;
mod no_alloc;
mod retarget;
mod rig;
mod skin;
mod skin_file;
mod torso;
mod turn_limit;
mod vrm;
mod wrist_limits;
