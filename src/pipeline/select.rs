//! The **select** stage: which tracked hand drives each avatar side; low scores ignored,
//! labels that contradict the pose wrists reassigned (`options.handedness`), labels that jump
//! to the other side between frames (no pose) relabelled, two hands on one side resolved.
//! What was resolved is reported per side ([`HandResolved`]).
//!
//! The witnesses, strongest first:
//!
//! 1. **The pose** (both pose wrists seen in the image): a hand whose image wrist is nearer the
//!    other side's pose wrist than [`CONTRADICTION_RATIO`] of its distance to its own side's
//!    has the wrong label ([`HandResolved::Swapped`]).
//! 2. **The last frame** (no pose witness; the side's hand of the frame before, in the image):
//!    a hand that lands where the *other* side's hand just was (nearer it than
//!    [`CONTRADICTION_RATIO`] of its distance to where its own side's hand was, and within
//!    one palm length of it) while that side has no nearer hand this frame is the other
//!    side's hand with its label flipped ([`HandResolved::Jumped`]); at most
//!    [`MAX_JUMP_FRAMES`] in a row are relabelled, then the label is believed again.
//! 3. **Two hands on one side** ([`HandResolved::Duplicate`]): the one nearer the side's
//!    pose wrist, else nearer where the side's hand was last frame, else the higher score
//!    keeps it. Without a pose witness, a second hand that is a distinct hand in the image
//!    (wrists farther apart than half a palm length) goes to the other side when that side
//!    has none (by the last frame's positions, else by the image's left-right order); one on
//!    top of the first (MediaPipe finding one hand twice) is dropped.

use glam::Vec2;

use crate::humanoid::bones::Side;
use crate::input::mediapipe::{hand_landmark, pose_landmark, CameraMapping, MAX_HANDS};
use crate::options::HandednessPolicy;

use super::frame::{Context, Frame, Pick};
use super::output::{HandResolved, HandUse, SolveOutput};

/// A hand's label contradicts the pose when its wrist is nearer the other side's pose wrist
/// than this fraction of its distance to its own side's (in the image).
pub const CONTRADICTION_RATIO: f32 = 0.5;

/// Frames in a row a hand is relabelled by the last frame's positions
/// ([`HandResolved::Jumped`]) before its label is believed again: MediaPipe's label flips on
/// a hand last a frame or a few; a label that stays is more likely right than the frame the
/// continuity started from.
pub const MAX_JUMP_FRAMES: u8 = 3;

/// Two hands of one label are distinct hands when their image wrists are farther apart than
/// this fraction of the larger image palm length (wrist to middle knuckle); nearer, they are
/// one hand found twice.
pub const DISTINCT_HANDS: f32 = 0.5;

/// The select stage: which tracked hand drives each side. Carries, per side, the hand of the frame
/// before.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub(super) struct Select {
    /// The image wrist of the hand that drove the side in the frame before (`None`: no hand,
    /// or no image landmarks).
    wrist: [Option<Vec2>; 2],
    /// Consecutive frames a hand was relabelled onto each side by continuity.
    jumped: [u8; 2],
}

/// One candidate hand of this frame.
#[derive(Clone, Copy, Debug)]
struct Candidate {
    side: Side,
    reassigned: bool,
    resolved: HandResolved,
    wrist: Option<Vec2>,
    /// Image palm length (wrist to middle knuckle), when the image landmarks are given.
    palm: Option<f32>,
    /// Whether the pose witnessed this hand's side.
    posed: bool,
}

fn distance(a: Option<Vec2>, b: Option<Vec2>) -> Option<f32> {
    a.zip(b).map(|(a, b)| (a - b).length())
}

impl Select {
    /// Which tracked hand drives each side (`f.picks`, `[left, right]`), recording what
    /// became of every hand in `out.hand_use` and what was resolved per side in the picks.
    pub(super) fn run(&mut self, cx: &Context, f: &mut Frame, out: &mut SolveOutput) {
        let (frame, camera, options) = (cx.input, cx.camera, cx.options);
        let policy = options.handedness;
        // Cleared by a new session (`Rig::new_session`): only the frame just before counts.
        let last = if policy == HandednessPolicy::Trust {
            [None, None]
        } else {
            self.wrist
        };
        // The pose wrists in the image, per avatar side, when both are visible.
        let pose_wrists = match (&frame.pose, &frame.pose_image) {
            (Some(pose), Some(image)) if policy != HandednessPolicy::Trust => {
                let at = |side: Side| {
                    let k = match camera.pose_side_for(side) {
                        Side::Left => pose_landmark::LEFT_WRIST,
                        Side::Right => pose_landmark::RIGHT_WRIST,
                    };
                    (pose.visibility[k] >= options.calibration.min_visibility)
                        .then(|| image[k].truncate())
                };
                at(Side::Left).zip(at(Side::Right)).map(|(l, r)| [l, r])
            }
            _ => None,
        };
        let pose_at = |side: Side| pose_wrists.map(|pw| pw[side.index()]);

        // Witness 1, the pose: each hand's side.
        let mut cands: [Option<Candidate>; MAX_HANDS] = [None; MAX_HANDS];
        for (index, h) in frame.hands().iter().enumerate() {
            if h.score < options.min_hand_score {
                out.hand_use[index] = HandUse::LowScore;
                continue;
            }
            let mut side = camera.avatar_side(h.handedness);
            let mut reassigned = false;
            let wrist = h.image.map(|img| img[hand_landmark::WRIST].truncate());
            let palm = h.image.map(|img| {
                (img[hand_landmark::MIDDLE_MCP].truncate() - img[hand_landmark::WRIST].truncate())
                    .length()
            });
            let own = distance(wrist, pose_at(side));
            let other = distance(wrist, pose_at(side.opposite()));
            if let (Some(own), Some(other)) = (own, other) {
                if other < CONTRADICTION_RATIO * own {
                    match policy {
                        HandednessPolicy::Reassign => {
                            side = side.opposite();
                            reassigned = true;
                        }
                        HandednessPolicy::Drop => {
                            out.hand_use[index] = HandUse::Contradicted;
                            continue;
                        }
                        HandednessPolicy::Trust => {}
                    }
                }
            }
            cands[index] = Some(Candidate {
                side,
                reassigned,
                resolved: if reassigned {
                    HandResolved::Swapped
                } else {
                    HandResolved::None
                },
                wrist,
                palm,
                posed: own.is_some() && other.is_some(),
            });
        }

        // Witness 2, the last frame: a label that jumped to the other side.
        let mut jumped_to = [false; 2];
        for i in 0..MAX_HANDS {
            let Some(c) = cands[i] else { continue };
            if c.posed {
                continue;
            }
            let to = c.side.opposite();
            let (Some(there), Some(palm)) = (distance(c.wrist, last[to.index()]), c.palm) else {
                continue;
            };
            let here = distance(c.wrist, last[c.side.index()]).unwrap_or(f32::INFINITY);
            // A hand already on that side this frame, nearer where its hand was, keeps it.
            let taken = cands.iter().enumerate().any(|(j, o)| {
                o.is_some_and(|o| {
                    j != i
                        && o.side == to
                        && distance(o.wrist, last[to.index()]).is_none_or(|d| d <= there)
                })
            });
            if there < CONTRADICTION_RATIO * here
                && there < palm
                && !taken
                && self.jumped[to.index()] < MAX_JUMP_FRAMES
            {
                cands[i] = Some(Candidate {
                    side: to,
                    reassigned: true,
                    resolved: HandResolved::Jumped,
                    ..c
                });
                jumped_to[to.index()] = true;
            }
        }

        // Two hands on one side.
        let mut picks: [Option<Pick>; 2] = [None, None];
        let mut moved: Option<usize> = None;
        for side in Side::BOTH {
            let s = side.index();
            // The keeper: nearer the pose wrist, else nearer last frame's hand, else the
            // higher score; the first of equals.
            let mut keep: Option<usize> = None;
            let mut claims = 0;
            for (i, c) in cands.iter().enumerate() {
                let Some(c) = c.filter(|c| c.side == side) else {
                    continue;
                };
                claims += 1;
                keep = match keep {
                    None => Some(i),
                    Some(k) => {
                        let kc = cands[k].expect("a candidate");
                        let (hs, ks) = (frame.hands()[i].score, frame.hands()[k].score);
                        let better = match (
                            distance(c.wrist, pose_at(side)),
                            distance(kc.wrist, pose_at(side)),
                        ) {
                            (Some(a), Some(b)) => a < b,
                            _ => match (distance(c.wrist, last[s]), distance(kc.wrist, last[s])) {
                                (Some(a), Some(b)) => a < b,
                                _ => hs > ks,
                            },
                        };
                        Some(if better { i } else { k })
                    }
                };
            }
            let Some(k) = keep else { continue };
            let kc = cands[k].expect("a candidate");
            let resolved = if claims > 1 && kc.resolved == HandResolved::None {
                HandResolved::Duplicate
            } else {
                kc.resolved
            };
            picks[s] = Some(Pick {
                index: k,
                reassigned: kc.reassigned,
                resolved,
                distance: distance(kc.wrist, pose_at(side)),
                score: frame.hands()[k].score,
            });
            for (i, c) in cands.iter().enumerate() {
                if i != k && c.is_some_and(|c| c.side == side) {
                    out.hand_use[i] = HandUse::Duplicate;
                    if moved.is_none()
                        && distinct_second_hand(&kc, c.as_ref(), last, camera, policy)
                    {
                        moved = Some(i);
                    }
                }
            }
        }
        // A distinct second hand of one label, without a pose witness, drives the other side
        // when that side has no hand.
        if let Some(i) = moved {
            let c = cands[i].expect("a candidate");
            let to = c.side.opposite();
            if picks[to.index()].is_none() {
                picks[to.index()] = Some(Pick {
                    index: i,
                    reassigned: true,
                    resolved: HandResolved::Duplicate,
                    distance: None,
                    score: frame.hands()[i].score,
                });
            }
        }
        for side in Side::BOTH {
            let s = side.index();
            if let Some(p) = picks[s] {
                out.hand_use[p.index] = HandUse::Drove(side);
            }
            self.wrist[s] = picks[s].and_then(|p| cands[p.index].and_then(|c| c.wrist));
            self.jumped[s] = if jumped_to[s] { self.jumped[s] + 1 } else { 0 };
        }
        f.picks = picks;
    }
}

/// Whether `second`, which lost its side to `keeper`, is a distinct hand that belongs on
/// the other side (no pose witness, image landmarks on both, wrists apart by more than
/// [`DISTINCT_HANDS`] palm lengths, and on the other side's part of the image: nearer
/// where that side's hand was last frame than the keeper, else further that way in the
/// image's left-right order).
fn distinct_second_hand(
    keeper: &Candidate,
    second: Option<&Candidate>,
    last: [Option<Vec2>; 2],
    camera: CameraMapping,
    policy: HandednessPolicy,
) -> bool {
    let Some(second) = second else { return false };
    if keeper.posed || second.posed || policy == HandednessPolicy::Trust {
        return false;
    }
    let (Some(a), Some(b)) = (keeper.wrist, second.wrist) else {
        return false;
    };
    let palm = keeper.palm.unwrap_or(0.0).max(second.palm.unwrap_or(0.0));
    if (a - b).length() <= DISTINCT_HANDS * palm {
        return false;
    }
    let to = second.side.opposite();
    if let Some(there) = last[to.index()] {
        return (b - there).length() < (a - there).length();
    }
    // The avatar's left is +x in its frame; image x turns into avatar x as world x does.
    let towards_left = if camera.flips_x() {
        b.x < a.x
    } else {
        b.x > a.x
    };
    towards_left == (to == Side::Left)
}
