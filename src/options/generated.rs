//! Files generated from the option table: the TypeScript `HandRigOptions` type
//! (`pkg-config/src/options-types.ts`), the options reference page (`docs/reference/options.md`) and
//! the options' descriptions for the package's `optionDescriptions()`
//! (`pkg-config/src/options.json`; the `.wasm` carries neither their text nor their list). A test compares
//! each with the committed file; `HANDRIG_GENERATE=write cargo test --lib options` rewrites
//! them.

use super::table::{Kind, OptionSpec, Value, OPTIONS};

/// Where the TypeScript type is committed, relative to the crate root.
pub const TYPESCRIPT_PATH: &str = "pkg-config/src/options-types.ts";
/// Where the reference page is committed, relative to the crate root.
pub const MARKDOWN_PATH: &str = "docs/reference/options.md";

/// Where the option descriptions are committed (read by the package build), relative to the
/// crate root.
pub const DESCRIPTIONS_PATH: &str = "pkg-config/src/options.json";

/// A JSON number for an `f32`: its shortest decimal (`0.05`, not `0.05000000074505806`).
fn json_f32(x: f32) -> String {
    serde_json::to_string(&x).unwrap_or_else(|_| "null".into())
}

/// A JSON string.
fn json_str(s: &str) -> String {
    serde_json::to_string(s).unwrap_or_default()
}

/// Every option as the package's `optionDescriptions()` gives it, as JSON: an array in table
/// order of `{ path, type, description, default, values?, names?, min?, max?, step?, integer?,
/// length? }` (the `.wasm` carries no description text and no such list).
#[must_use]
pub fn descriptions_json() -> String {
    let mut rows = Vec::new();
    for o in OPTIONS {
        let mut f = vec![
            format!("\"path\": {}", json_str(o.path)),
            String::new(),
            format!("\"description\": {}", json_str(o.doc)),
        ];
        let (kind, rest): (&str, Vec<String>) = match (o.kind, o.default) {
            (Kind::Bool, Value::Bool(d)) => ("boolean", vec![format!("\"default\": {d}")]),
            (Kind::Enum(values), Value::Enum(d)) => {
                let v: Vec<String> = values.iter().map(|v| json_str(v)).collect();
                (
                    "enum",
                    vec![
                        format!("\"values\": [{}]", v.join(", ")),
                        format!("\"default\": {}", json_str(d)),
                    ],
                )
            }
            (
                Kind::Number {
                    min,
                    max,
                    step,
                    integer,
                    ..
                },
                Value::Number(d),
            ) => {
                let mut r = Vec::new();
                if integer {
                    r.push("\"integer\": true".to_string());
                }
                r.push(format!("\"min\": {}", json_f32(min)));
                r.push(format!("\"max\": {}", json_f32(max)));
                r.push(format!("\"step\": {}", json_f32(step)));
                r.push(format!(
                    "\"default\": {}",
                    d.map_or_else(|| "null".to_string(), json_f32)
                ));
                ("number", r)
            }
            (Kind::Points { names, .. }, _) => {
                let v: Vec<String> = names.iter().map(|v| json_str(v)).collect();
                (
                    "points",
                    vec![
                        format!("\"names\": [{}]", v.join(", ")),
                        "\"default\": null".to_string(),
                    ],
                )
            }
            (Kind::Numbers { len, min, max }, Value::Numbers(d)) => {
                let v: Vec<String> = d.iter().map(|x| json_f32(*x)).collect();
                (
                    "numbers",
                    vec![
                        format!("\"length\": {len}"),
                        format!("\"min\": {}", json_f32(min)),
                        format!("\"max\": {}", json_f32(max)),
                        format!("\"default\": [{}]", v.join(", ")),
                    ],
                )
            }
            _ => ("unknown", Vec::new()),
        };
        f[1] = format!("\"type\": {}", json_str(kind));
        f.extend(rest);
        rows.push(format!("  {{ {} }}", f.join(", ")));
    }
    format!("[\n{}\n]\n", rows.join(",\n"))
}

/// The one-line summary of a row's type, range and default, as the docs show it.
fn summary(spec: &OptionSpec) -> String {
    let default = match spec.default {
        Value::Number(None) | Value::Points(_) => "unset".to_string(),
        d => format!("`{}`", d.to_json()),
    };
    match spec.kind {
        Kind::Bool => format!("boolean, default {default}"),
        Kind::Enum(names) => {
            let q: Vec<String> = names.iter().map(|n| format!("`\"{n}\"`")).collect();
            format!("one of {}, default {default}", q.join(", "))
        }
        Kind::Number {
            min, max, integer, ..
        } => {
            let what = if integer { "whole number" } else { "number" };
            format!("{what} in {min}..{max}, default {default}")
        }
        Kind::Points { names, limit } => format!(
            "object of [x, y, z] (meters, within {limit}) named {}, default {default}",
            names.join(", ")
        ),
        Kind::Numbers { len, min, max } => {
            format!("{len} numbers in {min}..{max}, default {default}")
        }
    }
}

/// The TypeScript type of a row's value.
fn ts_type(spec: &OptionSpec) -> String {
    match spec.kind {
        Kind::Bool => "boolean".into(),
        Kind::Enum(names) => {
            let q: Vec<String> = names.iter().map(|n| format!("\"{n}\"")).collect();
            q.join(" | ")
        }
        Kind::Number { optional, .. } => {
            if optional {
                "number | null".into()
            } else {
                "number".into()
            }
        }
        Kind::Points { names, .. } => {
            let q: Vec<String> = names.iter().map(|n| format!("\"{n}\"")).collect();
            format!(
                "{{ [name in {}]?: [number, number, number] | {{ x: number; y: number; z: number }} | null }} | null",
                q.join(" | ")
            )
        }
        Kind::Numbers { len, .. } => {
            format!("[{}]", vec!["number"; len].join(", "))
        }
    }
}

/// The groups (first path segments with nested rows), in table order.
fn groups() -> Vec<&'static str> {
    let mut out: Vec<&'static str> = Vec::new();
    for spec in OPTIONS {
        if let Some((g, _)) = spec.path.split_once('.') {
            if !out.contains(&g) {
                out.push(g);
            }
        }
    }
    out
}

/// What a group is, for its doc comment.
fn group_doc(group: &str) -> &'static str {
    match group {
        "arm" => "Options every arm solver shares.",
        "alignment" => "Fingertip alignment (seeds 000/001).",
        "calibration" => "Body-scale calibration from pose landmarks.",
        "filter" => "One Euro filtering of the landmarks.",
        "dropout" => "Holding and easing over tracking loss.",
        "contact" => "Self-contact retargeting: face, hand-to-hand, body colliders.",
        "retarget" => "The objective of handStrategy \"retarget\" (seed 003).",
        "handsOnly" => "Arms from hands alone (no pose): the camera and framing assumed.",
        _ => "Options.",
    }
}

/// `pkg-config/src/options-types.ts`.
#[must_use]
pub fn typescript() -> String {
    let mut s = String::from(
        "// Generated from the option table (src/options/table.rs) by `HANDRIG_GENERATE=write cargo test\n\
         // --lib options`; a test fails when this file is stale. Do not edit.\n\n\
         /** Options, set at construction. `HandRig.optionDescriptions()` lists them with ranges and defaults. */\n\
         export interface HandRigOptions {\n",
    );
    let mut done: Vec<&str> = Vec::new();
    for spec in OPTIONS {
        match spec.path.split_once('.') {
            None => {
                s.push_str(&format!(
                    "  /** {} ({}.) */\n  {}?: {} | undefined;\n",
                    spec.doc,
                    summary(spec),
                    spec.path,
                    ts_type(spec)
                ));
            }
            Some((group, _)) if !done.contains(&group) => {
                done.push(group);
                let switch = OPTIONS.iter().any(|o| o.path == format!("{group}.enabled"));
                s.push_str(&format!(
                    "  /** {}{} */\n  {group}?:{}\n",
                    group_doc(group),
                    if switch {
                        " `false` / `true` sets `enabled`."
                    } else {
                        ""
                    },
                    if switch {
                        "\n    | boolean\n    | {"
                    } else {
                        " {"
                    },
                ));
                let pad = if switch { "        " } else { "    " };
                for o in OPTIONS
                    .iter()
                    .filter(|o| o.path.starts_with(&format!("{group}.")))
                {
                    let name = &o.path[group.len() + 1..];
                    s.push_str(&format!(
                        "{pad}/** {} ({}.) */\n{pad}{name}?: {} | undefined;\n",
                        o.doc,
                        summary(o),
                        ts_type(o)
                    ));
                }
                // `| undefined` throughout: the options accept undefined as "not given", also
                // under TypeScript's exactOptionalPropertyTypes.
                s.push_str(if switch {
                    "      }\n    | undefined;\n"
                } else {
                    "  } | undefined;\n"
                });
            }
            Some(_) => {}
        }
    }
    s.push_str(
        "  /** Dotted paths as `optionDescriptions()` spells them are accepted too: `{ \"alignment.weight\": 0.5 }`. */\n\
         \x20 [dottedPath: `${string}.${string}`]: unknown;\n}\n",
    );
    s
}

/// `docs/reference/options.md`.
#[must_use]
pub fn markdown() -> String {
    let mut s = String::from(
        "# Options reference\n\n\
         Generated from the option table (`src/options/table.rs`) by `HANDRIG_GENERATE=write cargo\n\
         test --lib options`; a test fails when this page is stale. Pass options as the second\n\
         argument of `new HandRig(restPose, options)` / `HandRig.fromVrm(bytes, options)`, nested\n\
         (`{ filter: { minCutoff: 1 } }`) or dotted (`{ \"filter.minCutoff\": 1 }`); a group with an\n\
         `enabled` switch also takes `false` / `true` (`{ filter: false }`). In Rust:\n\
         `RigOptions::from_json` or the fields of `RigOptions`. Every option is checked when the rig\n\
         is made; an error names the path (`options.filter.minCutoff: must be a number in\n\
         0.05..1000, got 0`).\n\n",
    );
    let top: Vec<&OptionSpec> = OPTIONS.iter().filter(|o| !o.path.contains('.')).collect();
    s.push_str(
        "## Top level\n\n| option | type, range, default | what it does |\n| --- | --- | --- |\n",
    );
    for o in top {
        s.push_str(&format!("| `{}` | {} | {} |\n", o.path, summary(o), o.doc));
    }
    for g in groups() {
        s.push_str(&format!(
            "\n## `{g}`\n\n{}\n\n| option | type, range, default | what it does |\n| --- | --- | --- |\n",
            group_doc(g)
        ));
        for o in OPTIONS
            .iter()
            .filter(|o| o.path.starts_with(&format!("{g}.")))
        {
            s.push_str(&format!("| `{}` | {} | {} |\n", o.path, summary(o), o.doc));
        }
    }
    s
}

/// Compares `text` with the committed file at `path` (relative to the crate root), or writes
/// it there under `HANDRIG_GENERATE=write`; `command` is what regenerates it, for the message.
#[cfg(all(test, not(target_arch = "wasm32")))]
pub(crate) fn compare_with_committed(path: &str, text: &str, command: &str) {
    let full = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
    if std::env::var("HANDRIG_GENERATE").is_ok_and(|v| v == "write") {
        std::fs::create_dir_all(full.parent().expect("dir")).expect("mkdir");
        std::fs::write(&full, text).expect("write");
        return;
    }
    let committed = std::fs::read_to_string(&full).unwrap_or_default();
    assert!(
        committed == text,
        "{path} is stale: regenerate with HANDRIG_GENERATE=write {command}"
    );
}

#[cfg(all(test, not(target_arch = "wasm32")))]
mod tests {
    use super::*;

    fn compare(path: &str, text: &str) {
        compare_with_committed(path, text, "cargo test --lib options");
    }

    #[test]
    fn generated_typescript_is_committed() {
        compare(TYPESCRIPT_PATH, &typescript());
    }

    #[test]
    fn generated_reference_page_is_committed() {
        compare(MARKDOWN_PATH, &markdown());
    }

    #[test]
    fn generated_descriptions_are_committed() {
        let json = descriptions_json();
        let parsed: Vec<serde_json::Value> = serde_json::from_str(&json).expect("valid JSON");
        assert_eq!(parsed.len(), OPTIONS.len());
        for (row, o) in parsed.iter().zip(OPTIONS) {
            assert!(!o.doc.is_empty(), "{}: a description", o.path);
            assert_eq!(row["path"], o.path);
            assert_eq!(row["description"], o.doc, "{}", o.path);
            assert_ne!(row["type"], "unknown", "{}", o.path);
            // The default as the option decoder reads it back.
            let d = &row["default"];
            if !d.is_null() {
                let nested = o
                    .path
                    .rsplit('.')
                    .fold(d.clone(), |v, k| serde_json::json!({ k: v }));
                crate::options::RigOptions::from_json(&nested.to_string())
                    .unwrap_or_else(|e| panic!("{}: default {d}: {e}", o.path));
            }
        }
        compare(DESCRIPTIONS_PATH, &json);
    }

    #[test]
    fn every_option_appears_in_both_files() {
        let (ts, md) = (typescript(), markdown());
        for o in OPTIONS {
            let leaf = o.path.rsplit('.').next().unwrap_or(o.path);
            assert!(
                ts.contains(&format!("{leaf}?:")),
                "{} missing in the TS",
                o.path
            );
            assert!(
                md.contains(&format!("`{}`", o.path)),
                "{} missing in the docs",
                o.path
            );
        }
    }
}
