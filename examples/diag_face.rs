//! Face-touch diagnostic (issue 26): per right-hand frame of the labeled ASL clips that is
//! labeled `face` (or labeled `none` with face contact on), on the generated avatars with their
//! skin: the face blend and anchor, the contact report's distance (avatar fingertip to anchor),
//! the alignment error, and an estimate of the hand's gap to the head skin (the smallest over
//! the hand's joints and fingertips of minus their depth in the head map, finger radius as the
//! margin: the skin measure of `eval/skin-contact.mjs` measures the real mesh).
//!
//! ```text
//! cargo run --release --example diag_face [woman-vrm1,man-vrm1,...]
//! ```
//!
//! Default options, one rig per avatar reset per clip (as `eval/skin-contact.mjs`);
//! `DIAG_NOFILTER=1` turns the filters off, `DIAG_NOLIMITS=1` the wrist limits. The summary
//! line per avatar also counts the right hand's `none` frames within 2 cm of the head and its
//! frames more than 1 cm inside it (the same estimate), over all six clips.

use handrig_support::recordings;

use handrig::contact::skin::{HEAD_MAP, MAP_BONES};
use handrig::humanoid::bones::{HumanBone, Side};
use handrig::{Rig, RigOptions, SolveOutput};

fn main() {
    let avatars = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "woman-vrm1,man-vrm1,child-vrm1".into());
    for avatar in avatars.split(',') {
        let skel = recordings::vrm(&format!("tests/fixtures/avatars/{avatar}.vrm"));
        let mut options = RigOptions::default();
        if std::env::var("DIAG_NOFILTER").is_ok() {
            options.filter.enabled = false;
        }
        if std::env::var("DIAG_NOLIMITS").is_ok() {
            options.arm.wrist_limits = false;
        }
        let mut rig = Rig::new(skel, options).expect("rig");
        let mut out = SolveOutput::default();
        println!("## {avatar}");
        println!("| clip | frame | label | blend | anchor | tip-anchor mm | align err mm | reachable | head gap mm (est.) |");
        let (mut n, mut near, mut none_near, mut deep) = (0, 0, 0, 0);
        for clip in ["again", "brother", "eat", "please", "sister", "thanks"] {
            let labels = recordings::contact_labels(clip);
            let frames = recordings::asl(&format!("../shared/data/asl/{clip}.json"));
            rig.reset();
            for (i, f) in frames.iter().enumerate() {
                rig.solve(f, &mut out).unwrap();
                let s = Side::Right.index();
                let label = labels["right"][i].as_str().unwrap_or("?");
                let c = out.contact[s];
                let w = c.map_or(0.0, |c| c.weight);
                let surface = rig.contact().surface().expect("a skin");
                let mut only = [false; MAP_BONES.len()];
                only[HEAD_MAP] = true;
                let r = surface.finger_radius[s];
                let mut gap = f32::INFINITY;
                let mut points: Vec<glam::Vec3> = Vec::new();
                points.push(out.world.position[HumanBone::RightHand.index()]);
                for finger in handrig::humanoid::bones::Finger::ALL {
                    for b in Side::Right.finger(finger) {
                        points.push(out.world.position[b.index()]);
                    }
                }
                points.extend(out.fingertips[s].iter().flatten());
                for p in points {
                    if let Some((d, _, _)) = surface.depth(p, r, &out.world, only) {
                        gap = gap.min(-d);
                    }
                }
                if label == "face" {
                    n += 1;
                    near += usize::from(gap <= 0.02);
                }
                none_near += usize::from(label == "none" && gap <= 0.02);
                deep += usize::from(gap < -0.01);
                if label != "face" && !(label == "none" && w > 0.0) {
                    continue;
                }
                println!(
                    "| {clip} | {i} | {label} | {w:.2} | {} | {:.0} | {:.0} | {} | {:.0} |",
                    c.and_then(|c| c.anchor).map_or("-", |a| a.as_str()),
                    c.map_or(f32::NAN, |c| c.distance) * 1000.0,
                    out.alignment[s].map_or(f32::NAN, |a| a.error) * 1000.0,
                    out.alignment[s].is_some_and(|a| a.reachable),
                    gap * 1000.0
                );
            }
        }
        println!("{avatar}: face hand-frames within 2 cm (estimate) {near} of {n}; none right-hand-frames within 2 cm of the head {none_near}; right-hand-frames > 1 cm inside the head {deep}\n");
    }
}
