//! The **face** stage (issue 50): a face tracker's face into expressions, the look-at and the
//! head ([`crate::face`]); the head and neck turned over the posed torso; eased out (after the
//! dropout hold) when the face is lost.

use glam::Quat;

use crate::face::Face;
use crate::humanoid::bones::HumanBone;

use super::frame::{Context, Frame};
use super::output::SolveOutput;

/// The face stage: the face solver's history and when the face was lost.
#[derive(Clone, Debug, Default)]
pub(super) struct FaceStage {
    pub(super) face: Face,
    lost_ms: Option<f64>,
}

impl FaceStage {
    /// Forgets the history (not the neutral face).
    pub(super) fn restart(&mut self) {
        self.face.restart();
        self.lost_ms = None;
    }

    // Out of line: inlined into solve_valid it cost a second copy of the body's forward
    // kinematics (when it posed the whole body again).
    #[inline(never)]
    /// Runs after the torso: `out.face`, and the neck and head in `out.local` (the world pose
    /// posed again) when the face turns them.
    pub(super) fn run(&mut self, cx: &Context, _f: &mut Frame, out: &mut SolveOutput) {
        out.face = super::output::FaceReport::default();
        let o = &cx.options.face;
        if !o.enabled {
            return;
        }
        let k = if let Some(obs) = &cx.input.face_tracking {
            let dt = cx.dt;
            self.face
                .solve(obs, cx.camera, cx.input.image_aspect, cx.now_ms, dt, o);
            self.lost_ms = None;
            out.face.state = 1;
            1.0
        } else {
            if !self.face.seen() && self.lost_ms.is_none() {
                return;
            }
            self.face.lose();
            let lost = *self.lost_ms.get_or_insert(cx.now_ms);
            let d = cx.options.dropout.effective();
            let t = (cx.now_ms - lost - f64::from(d.hold_ms)) as f32 / d.fade_out_ms.max(1e-3);
            let t = t.clamp(0.0, 1.0);
            let k = 1.0 - t * t * (3.0 - 2.0 * t);
            if k <= 0.0 {
                self.face.head_rotation = None;
                self.lost_ms = None;
                return;
            }
            out.face.state = 2;
            k
        };
        let face = &self.face;
        out.face.presets = face.presets.map(|w| w * k);
        out.face.arkit = face.arkit.map(|w| w * k);
        out.face.look_at = face.look_at.map(|a| a * k);
        if let Some(r) = face.head_rotation.filter(|_| o.head) {
            out.face.head = turn_head(cx, r, k, out);
        }
    }
}

/// Turns the neck (its share) and head so the head's world rotation is `r`, blended by `k` from
/// what the torso gave them; poses the body again. Whether the avatar has a head.
fn turn_head(cx: &Context, r: Quat, k: f32, out: &mut SolveOutput) -> bool {
    let sk = cx.skeleton;
    let (neck, head) = (HumanBone::Neck, HumanBone::Head);
    if !sk.has(head) {
        return false;
    }
    let first = if sk.has(neck) { neck } else { head };
    let parent = sk
        .parent(first)
        .map_or(Quat::IDENTITY, |p| out.world.rotation[p.index()]);
    let l = (parent.conjugate() * r).normalize();
    let mut head_local = l;
    if first == neck {
        let n = Quat::IDENTITY
            .slerp(l, cx.options.face.neck_share)
            .normalize();
        out.local[neck.index()] = out.local[neck.index()].slerp(n, k).normalize();
        out.solved[neck.index()] = k >= 1.0;
        head_local = (n.conjugate() * l).normalize();
    }
    out.local[head.index()] = out.local[head.index()].slerp(head_local, k).normalize();
    out.solved[head.index()] = k >= 1.0;
    // The torso stage posed the whole body: only the neck's (or head's) subtree moved.
    sk.forward_subtree(first, &out.local, &mut out.world);
    true
}
