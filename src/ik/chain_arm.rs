//! The FABRIK and CCD arms ([`FabrikArm`], [`CcdArm`]): the arm chain with its pose, swivel
//! memory and twist state (`ChainArm`, crate-private), reached by the method's own step.
//! Both take the elbow's bend direction from the analytic solver ([`TwoBoneIk`]), so all
//! three arm methods agree where the arm has one solution.

use glam::{Quat, Vec3};

use crate::error::{Error, Result};
use crate::kinematics::{Chain, JointLimit, RootFrame};

use super::arm::{
    finish_hand, shoulder_need, shoulder_root, ArmChain, ArmGoal, ArmIk, ArmOptions, ArmPose,
    ArmReach, ForearmTwist, REACH_TOLERANCE,
};
use super::ccd::{Ccd, CcdOptions};
use super::fabrik::{Fabrik, FabrikOptions};
use super::goal::{ChainGoal, ChainReport, Effector};
use super::settle::settle;
use super::two_bone::{TwoBoneIk, TwoBoneOptions};

/// The method's reach step (FABRIK's or CCD's) as [`ChainArm`] calls it: the chain, its root,
/// the goal and the effectors, the joints to move in place; returns the method's report.
type ReachStep<'a> =
    dyn FnMut(&Chain, &RootFrame, &ChainGoal, &[Effector], &mut [Vec3]) -> ChainReport + 'a;

/// The arm chain with its pose, swivel memory and twist state, shared by [`super::FabrikArm`]
/// and [`super::CcdArm`]: they differ only in the reach step given to [`ChainArm::solve`].
#[derive(Clone, Debug)]
pub(crate) struct ChainArm {
    /// Joints upperArm, lowerArm, hand (the plain arm).
    plain: Chain,
    /// Joints shoulder, upperArm, lowerArm, hand (`None` without a shoulder bone).
    shouldered: Option<Chain>,
    joints: [Vec3; 4],
    /// Which chain `joints` holds (for the warm start), `None` before the first solve.
    last_shouldered: Option<bool>,
    /// The analytic solver, used for its bend direction (pole logic and memory) only.
    swivel: TwoBoneIk,
    twist: ForearmTwist,
    options: ArmOptions,
    report: ChainReport,
}

impl ChainArm {
    pub(crate) fn new(chain: &ArmChain, options: &ArmOptions) -> Result<Self> {
        options.validate()?;
        let [u, l] = [chain.upper, chain.lower];
        let field = |e: Error| match e {
            Error::InvalidInput { problem, .. } => Error::degenerate(
                format!("restPose.bones.{}", chain.bones[0]),
                format!("arm chain: {problem}"),
            ),
            e => e,
        };
        let plain = Chain::new(&[Vec3::ZERO, u, u + l], &[]).map_err(field)?;
        let shouldered = match chain.shoulder {
            Some(_) if chain.shoulder_offset.length() > 1e-6 => Some(
                Chain::new(
                    &[
                        Vec3::ZERO,
                        chain.shoulder_offset,
                        chain.shoulder_offset + u,
                        chain.shoulder_offset + u + l,
                    ],
                    &[Some(JointLimit::Cone { max_angle: 0.0 }), None, None],
                )
                .map_err(field)?,
            ),
            _ => None,
        };
        Ok(ChainArm {
            plain,
            shouldered,
            joints: [Vec3::ZERO; 4],
            last_shouldered: None,
            swivel: TwoBoneIk::new(TwoBoneOptions::default()).map_err(Error::from)?,
            twist: ForearmTwist::new(options.forearm_twist),
            options: *options,
            report: ChainReport::failed(),
        })
    }

    pub(crate) fn last_report(&self) -> ChainReport {
        self.report
    }

    pub(crate) fn reset(&mut self) {
        self.swivel.reset_memory();
        self.twist.reset();
        self.last_shouldered = None;
    }

    /// Solves `goal` with `reach` (the method: FABRIK or CCD) on the arm chain: sets up the
    /// shoulder cone, the warm start, the pole and the effectors, then converts the joints
    /// to local rotations; with the wrist limits on, re-solves for the limited hand
    /// ([`super::wrist`]).
    pub(crate) fn solve(
        &mut self,
        chain: &ArmChain,
        goal: &ArmGoal,
        out: &mut ArmPose,
        mut reach: impl FnMut(&Chain, &RootFrame, &ChainGoal, &[Effector], &mut [Vec3]) -> ChainReport,
    ) -> ArmReach {
        let parent = if goal.parent_rotation.is_finite() {
            goal.parent_rotation.normalize()
        } else {
            Quat::IDENTITY
        };
        if !(goal.target.is_finite() && goal.shoulder.is_finite()) {
            *out = ArmPose {
                elbow: goal.shoulder,
                wrist: goal.shoulder,
                ..ArmPose::default()
            };
            self.report = ChainReport::failed();
            return ArmReach {
                reachable: false,
                residual: f32::INFINITY,
                wrist: None,
            };
        }
        let pole = self.pole_point(chain, goal, parent);
        let (mut result, lower) = self.place(chain, goal, parent, pole, out, &mut reach);
        let mut goal = *goal;
        let mut lower_world = lower;
        if self.options.wrist_limits {
            if let Some(frame) = chain.wrist {
                result.wrist = settle(&frame, &mut goal, lower, &mut |g| {
                    let (r, l) = self.place(chain, g, parent, pole, out, &mut reach);
                    result = r;
                    lower_world = l;
                    l
                });
            }
        }
        finish_hand(chain, lower_world, goal.hand_rotation, &mut self.twist, out);
        result
    }

    /// The point the elbow is turned toward: the analytic solver's bend direction (pose elbow
    /// or default pole, continuity memory, updated here) from the upper arm joint as the
    /// shoulder option would place it for `goal`: the same pole for every method.
    fn pole_point(&mut self, chain: &ArmChain, goal: &ArmGoal, parent: Quat) -> Vec3 {
        let arm_length = chain.upper_length() + chain.lower_length();
        let shoulder =
            shoulder_root(chain, goal, &self.options).filter(|_| self.shouldered.is_some());
        let (upper_joint, rotation) = match shoulder {
            Some(root) => {
                let (need, axis) = shoulder_need(
                    &root,
                    chain.shoulder_offset,
                    goal.target,
                    arm_length,
                    &self.options,
                );
                let turned =
                    Quat::from_axis_angle(axis, need) * (root.rotation * chain.shoulder_offset);
                (root.position + turned, root.rotation)
            }
            None => (goal.shoulder, parent),
        };
        let swivel_goal = ArmGoal {
            shoulder: upper_joint,
            parent_rotation: rotation,
            ..*goal
        };
        let (dir, bend) = self.swivel.swivel(chain, &swivel_goal);
        let distance = (goal.target - upper_joint).length();
        upper_joint + dir * (0.5 * distance) + bend * arm_length
    }

    /// One reach of `goal` toward `pole_point`: the shoulder cone, the warm start, the
    /// effectors, `reach`, then the shoulder, upper and lower arm rotations and the elbow and
    /// wrist positions in `out` (the hand is left to [`finish_hand`]). Returns the reach and
    /// the forearm's world rotation.
    fn place(
        &mut self,
        chain: &ArmChain,
        goal: &ArmGoal,
        parent: Quat,
        pole_point: Vec3,
        out: &mut ArmPose,
        // `dyn`: one copy of this function for both methods (a generic one was two, 3.3 KiB
        // each in the .wasm); the reach step is called once or twice a frame.
        reach: &mut ReachStep<'_>,
    ) -> (ArmReach, Quat) {
        let arm_length = chain.upper_length() + chain.lower_length();
        let shoulder =
            shoulder_root(chain, goal, &self.options).filter(|_| self.shouldered.is_some());

        // The chain and its root.
        let (kc, root) = match shoulder {
            Some(root) => {
                let (need, _) = shoulder_need(
                    &root,
                    chain.shoulder_offset,
                    goal.target,
                    arm_length,
                    &self.options,
                );
                let kc = self.shouldered.as_mut().expect("checked above");
                // The cone limit was validated at setup; `need` is in 0..=pi/2.
                let _ = kc.set_limit(0, Some(JointLimit::Cone { max_angle: need }));
                (&*kc, root)
            }
            None => (
                &self.plain,
                RootFrame {
                    position: goal.shoulder,
                    rotation: parent,
                },
            ),
        };
        let n = kc.joint_count();
        let shouldered = shoulder.is_some();
        let joints = &mut self.joints[..n];
        if self.last_shouldered != Some(shouldered) {
            // First solve, or the chain changed: start from rest (or from the plain arm's
            // last pose carried over, which anchor() then moves to the root).
            let rest = kc.rest_joints();
            for (p, r) in joints.iter_mut().zip(rest) {
                *p = root.position + root.rotation * *r;
            }
        }
        self.last_shouldered = Some(shouldered);

        let upper_index = usize::from(shouldered);
        let chain_goal = ChainGoal {
            target: goal.target,
            pole: Some(pole_point),
            end_rotation: None,
            pole_first: upper_index + 1,
        };
        let wrist = n - 1;
        let finger = goal
            .finger
            .filter(|f| f.is_finite() && goal.hand_rotation.is_some());
        let mut effectors = [Effector {
            joint: wrist,
            offset: Vec3::ZERO,
            target: goal.target,
            first_joint: 0,
        }; 3];
        let mut count = 0;
        if let Some(f) = finger {
            effectors[count].offset = f;
            effectors[count].target = goal.target + f;
            count += 1;
        }
        count += 1; // the wrist itself
        effectors[count] = Effector {
            joint: wrist - 1,
            offset: Vec3::ZERO,
            target: pole_point,
            first_joint: upper_index,
        };
        count += 1;
        self.report = reach(kc, &root, &chain_goal, &effectors[..count], joints);

        // Joints to local rotations (swing chain).
        let mut world = [Quat::IDENTITY; 3];
        kc.rotations(root.rotation, joints, &mut world[..n - 1]);
        let (upper_parent, upper_world, lower_world) = if shouldered {
            out.shoulder = Some((root.rotation.conjugate() * world[0]).normalize());
            (world[0], world[1], world[2])
        } else {
            out.shoulder = None;
            (parent, world[0], world[1])
        };
        out.upper = (upper_parent.conjugate() * upper_world).normalize();
        out.lower = (upper_world.conjugate() * lower_world).normalize();
        // Positions by forward kinematics of the written rotations (the hand's twist, added
        // later, turns the forearm about its own axis and moves neither).
        let upper_at = joints[upper_index];
        out.elbow = upper_at + upper_parent * out.upper * chain.upper;
        out.wrist = out.elbow + upper_parent * out.upper * out.lower * chain.lower;
        let (a, b) = (chain.upper_length(), chain.lower_length());
        let reach_to = (goal.target - upper_at).length();
        (
            ArmReach {
                reachable: reach_to <= a + b + REACH_TOLERANCE
                    && reach_to + REACH_TOLERANCE >= (a - b).abs(),
                residual: (out.wrist - goal.target).length(),
                wrist: None,
            },
            upper_parent * out.upper * out.lower,
        )
    }
}

/// FABRIK for one arm ([`super::ArmSolver::Fabrik`]): the arm chain (upper arm, forearm;
/// with [`ArmOptions::shoulder_angle`] the shoulder bone too, under a cone limit) reaches the
/// wrist target, the elbow turned toward the same bend direction the analytic solver uses
/// (pose elbow or default pole, with its continuity memory). Warm-started from the previous
/// frame. See [`super::arm`] for rotations and twist.
#[derive(Clone, Debug)]
pub struct FabrikArm {
    fabrik: Fabrik,
    arm: ChainArm,
    frames: [Quat; 3],
}

impl FabrikArm {
    /// A FABRIK arm solver for `chain`.
    ///
    /// # Errors
    /// Options out of range.
    pub fn new(chain: &ArmChain, options: FabrikOptions, arm: &ArmOptions) -> Result<Self> {
        Ok(FabrikArm {
            fabrik: Fabrik::new(options)?,
            arm: ChainArm::new(chain, arm)?,
            frames: [Quat::IDENTITY; 3],
        })
    }

    /// The last solve's iteration count and convergence.
    #[must_use]
    pub fn last_report(&self) -> ChainReport {
        self.arm.last_report()
    }
}

impl ArmIk for FabrikArm {
    fn solve(&mut self, chain: &ArmChain, goal: &ArmGoal, out: &mut ArmPose) -> ArmReach {
        let fabrik = self.fabrik;
        let frames = &mut self.frames;
        self.arm
            .solve(chain, goal, out, |c, root, goal, _effectors, joints| {
                fabrik.solve(c, root, goal, joints, &mut frames[..c.bone_count()])
            })
    }

    fn reset(&mut self) {
        self.arm.reset();
    }
}

/// CCD for one arm ([`super::ArmSolver::Ccd`]) with the seed's priority effectors: the
/// aligned finger point (when the rig aligns one) first, the wrist second, the elbow toward
/// the bend direction the analytic solver uses (pose elbow or default pole, with its
/// continuity memory) last. With [`ArmOptions::shoulder_angle`] the shoulder bone joins the
/// chain under a cone limit. Warm-started from the previous frame; see [`super::arm`] for
/// rotations and twist.
#[derive(Clone, Debug)]
pub struct CcdArm {
    ccd: Ccd,
    arm: ChainArm,
    frames: [Quat; 3],
}

impl CcdArm {
    /// A CCD arm solver for `chain`.
    ///
    /// # Errors
    /// Options out of range.
    pub fn new(chain: &ArmChain, options: CcdOptions, arm: &ArmOptions) -> Result<Self> {
        Ok(CcdArm {
            ccd: Ccd::new(options)?,
            arm: ChainArm::new(chain, arm)?,
            frames: [Quat::IDENTITY; 3],
        })
    }

    /// The last solve's iteration count and convergence.
    #[must_use]
    pub fn last_report(&self) -> ChainReport {
        self.arm.last_report()
    }
}

impl ArmIk for CcdArm {
    fn solve(&mut self, chain: &ArmChain, goal: &ArmGoal, out: &mut ArmPose) -> ArmReach {
        let ccd = self.ccd;
        let frames = &mut self.frames;
        self.arm
            .solve(chain, goal, out, |c, root, _goal, effectors, joints| {
                ccd.solve(
                    c,
                    root,
                    effectors,
                    super::ccd::Guides::default(),
                    joints,
                    &mut frames[..c.bone_count()],
                )
            })
    }

    fn reset(&mut self) {
        self.arm.reset();
    }
}
