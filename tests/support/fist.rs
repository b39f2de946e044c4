//! A fist from a recorded hand (issue 52: chest contact for every hand shape), the same
//! construction as `eval/fist.mjs`: the shared clips have a flat palm (`please`) and a curved
//! hand (`hungry`) on the chest and no fist. Each finger of the world landmarks is bent at its
//! three joints (MCP 90, PIP 100, DIP 70 degrees; the thumb 35 at its MCP and 60 at its IP)
//! toward the palm's front, about the axis across the finger and the palm normal; the wrist
//! and the palm's knuckles stay. The image landmarks follow through the affine map (world ->
//! image) fitted by least squares on the palm points of the same frame; the palm points keep
//! their recorded image positions. `palm_away`: the palm faces away from the camera (a palm on
//! the chest, seen from the front), so its front normal is the one whose z (MediaPipe: away
//! from the camera) is positive.

use glam::{Mat4, Quat, Vec3, Vec4};
use handrig::mediapipe::HandObservation;

const FINGERS: [([usize; 4], [f32; 3]); 5] = [
    ([1, 2, 3, 4], [0.0, 35.0, 60.0]),
    ([5, 6, 7, 8], [90.0, 100.0, 70.0]),
    ([9, 10, 11, 12], [90.0, 100.0, 70.0]),
    ([13, 14, 15, 16], [90.0, 100.0, 70.0]),
    ([17, 18, 19, 20], [90.0, 100.0, 70.0]),
];
const PALM: [usize; 6] = [0, 1, 5, 9, 13, 17];

/// `hand` made a fist (see the module docs).
pub fn fist(hand: &mut HandObservation, palm_away: bool) {
    let w = hand.world;
    let mut front = (w[5] - w[0]).cross(w[17] - w[0]).normalize();
    if (front.z < 0.0) == palm_away {
        front = -front;
    }
    let mut bent = w;
    for (joints, bends) in FINGERS {
        for j in 0..3 {
            let at = bent[joints[j]];
            let dir = (bent[joints[j + 1]] - at).normalize();
            // Turning about dir x front moves dir toward front.
            let turn = Quat::from_axis_angle(dir.cross(front).normalize(), bends[j].to_radians());
            for &m in &joints[j + 1..] {
                bent[m] = at + turn * (bent[m] - at);
            }
        }
    }
    if let Some(image) = hand.image.as_mut() {
        // Normal equations of the affine map [x y z 1] -> image, over the palm points.
        let (mut ata, mut atb) = (Mat4::ZERO, [Vec4::ZERO; 3]);
        for &i in &PALM {
            let a = w[i].extend(1.0);
            ata += Mat4::from_cols(a * a.x, a * a.y, a * a.z, a * a.w);
            for (o, b) in atb.iter_mut().enumerate() {
                *b += a * image[i][o];
            }
        }
        ata += Mat4::from_diagonal(Vec4::new(1e-9, 1e-9, 1e-9, 0.0));
        let inv = ata.inverse();
        let rows = atb.map(|b| inv * b);
        for (i, p) in bent.iter().enumerate() {
            if !PALM.contains(&i) {
                let a = p.extend(1.0);
                image[i] = Vec3::new(rows[0].dot(a), rows[1].dot(a), rows[2].dot(a));
            }
        }
    }
    hand.world = bent;
}
