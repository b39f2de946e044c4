//! The per-frame pipeline under its former path: everything here is re-exported from
//! [`crate::pipeline`] (the [`Rig`] and its stages) and [`crate::input`].

pub use crate::input::COORDINATE_LIMIT;
pub use crate::options::{HandednessPolicy, RigOptions};
pub use crate::pipeline::{
    HandCheck, HandResolved, HandUse, IkTarget, Rig, SolveOutput, TrackedHand, CONTRADICTION_RATIO,
    DISTINCT_HANDS, MAX_JUMP_FRAMES,
};
