//! Prints the humanoid rest pose handrig reads from `.vrm` files, as JSON shaped like
//! `{ "<file name>": { "vrmVersion": "0" | "1", "bones": { "<bone>": [x, y, z] } } }`
//! (meters, the model's own frame: what three-vrm's normalized bones report at rest).
//!
//! `cargo run --example vrm_rest -- ../shared/avatars/debug-robot.vrm [more.vrm ...]`
//!
//! Used to compare handrig's VRM reader with three-vrm (see tests/fixtures/PROVENANCE.md).

use std::process::ExitCode;

fn main() -> ExitCode {
    let paths: Vec<String> = std::env::args().skip(1).collect();
    if paths.is_empty() {
        eprintln!("usage: vrm_rest FILE.vrm [FILE.vrm ...]");
        return ExitCode::FAILURE;
    }
    let mut out = serde_json::Map::new();
    for path in paths {
        let bytes = match std::fs::read(&path) {
            Ok(b) => b,
            Err(e) => {
                eprintln!("{path}: {e}");
                return ExitCode::FAILURE;
            }
        };
        let h = match handrig::humanoid::vrm::parse(&bytes) {
            Ok(h) => h,
            Err(e) => {
                eprintln!("{path}: {e}");
                return ExitCode::FAILURE;
            }
        };
        let bones: serde_json::Map<String, serde_json::Value> = h
            .bones
            .iter()
            .map(|(b, p)| (b.as_str().to_string(), serde_json::json!([p.x, p.y, p.z])))
            .collect();
        let name = std::path::Path::new(&path)
            .file_name()
            .map_or(path.clone(), |n| n.to_string_lossy().into_owned());
        out.insert(
            name,
            serde_json::json!({ "vrmVersion": h.version.as_str(), "bones": bones }),
        );
    }
    match serde_json::to_string_pretty(&serde_json::Value::Object(out)) {
        Ok(s) => {
            println!("{s}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("{e}");
            ExitCode::FAILURE
        }
    }
}
