//! A bounded fuzz run on stable Rust (issue 13): a seeded mutation loop over `.vrm` files and
//! flat frames, within a time budget, run by `cargo test`. cargo-fuzz needs a nightly toolchain;
//! this needs nothing but the crate.
//!
//! Corpus: the shared avatars, the generated fixtures and `tests/fuzz-corpus/` (inputs that
//! broke earlier builds or reach odd paths: kept in the repository so every run replays them).
//! Each `.vrm` mutant must load into a rig or fail with a clear `vrm:` error; each rig then
//! solves mutated flat frames, which must give finite unit rotations and finite positions or a
//! clear `frame...` error, and the rig must still solve a good frame afterwards. The seed is
//! fixed (`HANDRIG_FUZZ_SEED` to change it) and the budget is `HANDRIG_FUZZ_SECONDS` (default
//! 20 s); the run prints how many cases it tried.
// Native only: reads files from disk.

use crate::support::recordings;
use crate::support::vrm_fixture;

use std::time::{Duration, Instant};

use handrig::flat::{self, input};
use handrig::{FrameInput, Rig, RigOptions, SolveOutput};

/// xorshift64*: small, seeded, no dependency.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
    fn pick<T: Copy>(&mut self, xs: &[T]) -> T {
        xs[self.below(xs.len())]
    }
}

fn seed() -> u64 {
    std::env::var("HANDRIG_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20_261_202)
}

fn budget() -> Duration {
    let s = std::env::var("HANDRIG_FUZZ_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20.0);
    Duration::from_secs_f64(s)
}

fn corpus() -> Vec<(String, Vec<u8>)> {
    let mut files = vec![
        recordings::ROBOT.to_string(),
        "../shared/avatars/odd-armature-vrm0.vrm".to_string(),
        recordings::FIXTURE_VRM1.to_string(),
        recordings::FIXTURE_VRM0.to_string(),
    ];
    files.extend(recordings::fuzz_corpus(&[".vrm"]));
    files
        .into_iter()
        .map(|f| {
            let bytes = std::fs::read(recordings::path(&f)).unwrap_or_else(|e| panic!("{f}: {e}"));
            (f, bytes)
        })
        .collect()
}

/// One mutation of a `.vrm`: bytes flipped, spliced, truncated or the JSON edited.
fn mutate_vrm(rng: &mut Rng, bytes: &[u8]) -> Vec<u8> {
    let mut b = bytes.to_vec();
    match rng.below(6) {
        0 => {
            for _ in 0..1 + rng.below(8) {
                let i = rng.below(b.len());
                b[i] ^= 1 << rng.below(8);
            }
        }
        1 => b.truncate(rng.below(b.len())),
        2 => {
            let i = rng.below(b.len());
            let v = rng.pick(&[0u8, 0xFF, b'9', b'-', b'e', b'[', b'}']);
            b.insert(i, v);
        }
        _ => {
            // JSON-aware: a random number in the glTF JSON becomes extreme or a node index
            // goes out of range, keeping the container valid.
            if let Some((mut json, bin)) = vrm_fixture::unpack_glb(&b) {
                edit_json(rng, &mut json, 0);
                b = vrm_fixture::glb(&json, bin.as_deref());
            }
        }
    }
    b
}

fn edit_json(rng: &mut Rng, v: &mut serde_json::Value, depth: usize) -> bool {
    use serde_json::Value;
    match v {
        Value::Number(_) if rng.below(3) == 0 => {
            *v = match rng.below(8) {
                0 => serde_json::json!(0.0),
                1 => serde_json::json!(-1),
                2 => serde_json::json!(1e30),
                3 => serde_json::json!(1e-30),
                4 => serde_json::json!(999_999),
                5 => serde_json::json!(3.5),
                6 => serde_json::json!("1"),
                _ => Value::Null,
            };
            true
        }
        Value::Array(a) if !a.is_empty() && depth < 12 => {
            let i = rng.below(a.len());
            edit_json(rng, &mut a[i], depth + 1)
        }
        Value::Object(o) if !o.is_empty() && depth < 12 => {
            let keys: Vec<String> = o.keys().cloned().collect();
            let k = &keys[rng.below(keys.len())];
            if rng.below(10) == 0 {
                o.remove(k);
                true
            } else {
                edit_json(rng, o.get_mut(k).unwrap(), depth + 1)
            }
        }
        _ => false,
    }
}

/// One mutation of a flat input: slots set to hostile values.
fn mutate_frame(rng: &mut Rng, buf: &mut [f32]) {
    const VALUES: [f32; 12] = [
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        1e30,
        -1e30,
        0.0,
        -0.0,
        1.0,
        2.0,
        4.0,
        0.5,
        1e-30,
    ];
    for _ in 0..1 + rng.below(6) {
        let slot = match rng.below(4) {
            // Counts and flags are where the structure lives.
            0 => rng.pick(&[
                input::HAND_COUNT,
                input::POSE_PRESENT,
                input::POSE_HAS_IMAGE,
                input::IMAGE_ASPECT,
                input::HANDS + input::hand::HAS_WORLD,
                input::HANDS + input::hand::HAS_IMAGE,
                input::HANDS + input::hand::HANDEDNESS,
                input::WRISTS + input::wrist::PRESENT,
                input::WRISTS + input::wrist::HAS_ROTATION,
            ]),
            _ => rng.below(buf.len()),
        };
        buf[slot] = if rng.below(3) == 0 {
            buf[slot] * (rng.below(2000) as f32 / 1000.0)
        } else {
            rng.pick(&VALUES)
        };
    }
}

fn assert_sane(out: &SolveOutput, what: &str) {
    for (i, q) in out.local.iter().enumerate() {
        assert!(
            q.is_finite() && (q.length() - 1.0).abs() < 1e-3,
            "{what}: bone {i} rotation {q}"
        );
    }
    for (i, p) in out.world.position.iter().enumerate() {
        assert!(p.is_finite(), "{what}: bone {i} position {p}");
    }
    // The second fuzz round (2026-12-02) found infinite IK targets with finite bones.
    for t in out.ik_targets.iter().flatten() {
        assert!(
            t.position.is_finite() && t.rotation.is_finite(),
            "{what}: IK target {t:?}"
        );
    }
    for a in out.alignment.iter().flatten() {
        assert!(
            a.target_dip.is_finite() && a.ik_wrist.is_finite(),
            "{what}: alignment {a:?}"
        );
    }
}

#[test]
fn seeded_mutations_of_vrm_files_and_flat_frames() {
    let mut rng = Rng(seed().max(1));
    let deadline = Instant::now() + budget();
    let corpus = corpus();
    // Good frames: the hand video's hands, with a wrist or the plausible pose in turn.
    let hands = recordings::hand_video_first();
    let pose = recordings::plausible_pose();
    let good: Vec<Vec<f32>> = (0..30)
        .map(|i| {
            let mut f = FrameInput::default();
            let arm = recordings::ArmInput::ALL[i % 3];
            recordings::fill_frame(&mut f, hands[i * 20].world, 0.9, arm, &pose);
            let mut b = vec![0.0; input::LEN];
            flat::write_input(&f, &mut b);
            b
        })
        .collect();
    let (mut files, mut loaded, mut frames, mut rejected) = (0usize, 0usize, 0usize, 0usize);
    let mut decoded = FrameInput::default();
    let mut out = SolveOutput::default();
    while Instant::now() < deadline {
        let (name, bytes) = &corpus[rng.below(corpus.len())];
        let mutant = if files < corpus.len() {
            bytes.clone() // each corpus file once as it is
        } else {
            mutate_vrm(&mut rng, bytes)
        };
        files += 1;
        let skeleton = match handrig::humanoid::vrm::load_skeleton(&mutant) {
            Ok(s) => s,
            Err(e) => {
                let msg = e.to_string();
                assert!(msg.starts_with("vrm:"), "{name} mutant: {msg}");
                continue;
            }
        };
        loaded += 1;
        let options = if rng.below(2) == 0 {
            RigOptions::default()
        } else {
            RigOptions::per_frame()
        };
        let mut rig = Rig::new(skeleton, options).expect("default options");
        for k in 0..20 {
            let mut buf = good[rng.below(good.len())].clone();
            if k % 4 != 0 {
                mutate_frame(&mut rng, &mut buf);
            }
            frames += 1;
            let t = k as f64 * 33.3;
            match flat::read_input(&buf, t, &mut decoded) {
                Err(e) => {
                    rejected += 1;
                    assert!(e.to_string().starts_with("frame"), "{e}");
                }
                // Decoded, but a point beyond `COORDINATE_LIMIT`, or a hand more than 1 m
                // across, is for `Rig::solve`'s checks to refuse (naming the frame's field).
                Ok(()) => match rig.solve(&decoded, &mut out) {
                    Err(e) => {
                        rejected += 1;
                        let e = e.to_string();
                        assert!(
                            e.starts_with("frame")
                                && (e.contains("within -1000..1000") || e.contains("1 m across")),
                            "{e}"
                        );
                    }
                    Ok(()) => assert_sane(&out, name),
                },
            }
        }
        // The rig still solves a good frame afterwards.
        flat::read_input(&good[0], 10_000.0, &mut decoded).unwrap();
        rig.solve(&decoded, &mut out).unwrap();
        assert_sane(&out, name);
    }
    println!(
        "fuzz (seed {}): {files} .vrm inputs ({loaded} loaded), {frames} flat frames ({rejected} rejected with an error)",
        seed()
    );
    assert!(
        files > corpus.len() && frames > 0,
        "the budget allowed no case"
    );
}
