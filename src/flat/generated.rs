//! Files generated from the layout declaration ([`super::layout`]): `LAYOUT`'s values
//! (`pkg-config/src/layout.json`, which the package build inlines into the JS layer), the
//! TypeScript offsets type (`pkg-config/src/layout-types.ts`) and the layout table of
//! `docs/reference/flat-layout.md` (between its `layout-table` markers). A test compares both with the committed files;
//! `HANDRIG_GENERATE=write cargo test --lib flat` rewrites them.

use super::declare::RowKind;
use super::layout::{input, output, VERSION};
use super::Row;
use crate::humanoid::bones::HumanBone;
use crate::input::mediapipe::TrackerFace;
use crate::input::torso::{BodyJoint, TORSO_BONES};

/// Where the TypeScript type is committed, relative to the crate root.
pub const TYPESCRIPT_PATH: &str = "pkg-config/src/layout-types.ts";
/// Where `LAYOUT`'s values are committed (read by `pkg-config/build.mjs`, which inlines them
/// into the JS layer), relative to the crate root.
pub const JSON_PATH: &str = "pkg-config/src/layout.json";
/// The page whose layout table is generated, relative to the crate root.
pub const MARKDOWN_PATH: &str = "docs/reference/flat-layout.md";
/// The markers around the generated table in [`MARKDOWN_PATH`].
pub const TABLE_BEGIN: &str = "<!-- layout-table: generated from src/flat/layout.rs -->";
/// See [`TABLE_BEGIN`].
pub const TABLE_END: &str = "<!-- /layout-table -->";

/// JavaScript's `LAYOUT`: `{ version, input: {...}, output: {...}, bones, requiredBones,
/// torsoBones, bodyJoints, facePoints, handStatus, handCheck, handResolved, handUse }` (the
/// offsets of [`super::fields`] nested by their dotted paths; the 55 bone names in output
/// order; the torso section's bones, the body section's joints and the face section's points
/// in their order; the names of the output's codes by code), as pretty JSON.
#[must_use]
pub fn layout_json() -> String {
    use serde_json::{json, Map, Value};
    let mut root = Map::new();
    root.insert("version".into(), json!(VERSION));
    for (path, value) in super::fields() {
        let mut o = &mut root;
        let mut parts = path.split('.').peekable();
        while let Some(part) = parts.next() {
            if parts.peek().is_none() {
                o.insert(part.into(), json!(value));
            } else {
                let next = o.entry(part).or_insert_with(|| Value::Object(Map::new()));
                o = next.as_object_mut().expect("a path's parent is an object");
            }
        }
    }
    let bones: Vec<&str> = HumanBone::ALL.iter().map(|b| b.as_str()).collect();
    root.insert("bones".into(), json!(bones));
    let required: Vec<&str> = HumanBone::ALL
        .iter()
        .filter(|b| b.is_required())
        .map(|b| b.as_str())
        .collect();
    root.insert("requiredBones".into(), json!(required));
    let torso: Vec<&str> = TORSO_BONES.iter().map(|b| b.as_str()).collect();
    root.insert("torsoBones".into(), json!(torso));
    root.insert("bodyJoints".into(), json!(BodyJoint::NAMES.to_vec()));
    root.insert("facePoints".into(), json!(TrackerFace::NAMES.to_vec()));
    root.insert(
        "handStatus".into(),
        json!(super::HAND_STATUS_NAMES.to_vec()),
    );
    root.insert("handUse".into(), json!(super::HAND_USE_NAMES.to_vec()));
    root.insert("handCheck".into(), json!(super::HAND_CHECK_NAMES.to_vec()));
    root.insert(
        "handResolved".into(),
        json!(super::HAND_RESOLVED_NAMES.to_vec()),
    );
    // The face (issue 50): the ARKit names, the presets, the face-mesh landmarks read.
    root.insert("arkit".into(), json!(crate::face::ARKIT.to_vec()));
    root.insert("expressions".into(), json!(crate::face::PRESETS.to_vec()));
    root.insert("faceMesh".into(), json!(crate::face::MESH.to_vec()));
    let mut s = serde_json::to_string_pretty(&Value::Object(root)).expect("JSON");
    s.push('\n');
    s
}

/// A row's description on one line, as the TypeScript comment and the table show it.
fn one_line(doc: &str) -> String {
    doc.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The TypeScript interface of one side: its fields, each slot's fields as a nested object.
fn interface(name: &str, what: &str, rows: &[Row]) -> String {
    let mut s = format!("/** {what} */\nexport interface {name} {{\n");
    let mut in_slot: Option<&str> = None;
    for r in rows {
        let d = &r.detail;
        let leaf = r.path.rsplit('.').next().unwrap_or(r.path);
        if d.kind == RowKind::SlotField {
            let slot = r.path.split('.').nth(1).unwrap_or("");
            if in_slot != Some(slot) {
                s.push_str(&format!(
                    "  /** Offsets inside one slot of `{slot}`. */\n  readonly {slot}: {{\n"
                ));
                in_slot = Some(slot);
            }
            s.push_str(&format!(
                "    /** {} */\n    readonly {leaf}: number;\n",
                one_line(d.doc)
            ));
            continue;
        }
        if in_slot.take().is_some() {
            s.push_str("  };\n");
        }
        let doc = match d.kind {
            RowKind::Stride => "Floats from one slot to the next of the field above.".to_string(),
            RowKind::Length => "Length of the array.".to_string(),
            _ => one_line(d.doc),
        };
        s.push_str(&format!("  /** {doc} */\n  readonly {leaf}: number;\n"));
    }
    if in_slot.is_some() {
        s.push_str("  };\n");
    }
    s.push_str("}\n");
    s
}

/// `pkg-config/src/layout-types.ts`.
#[must_use]
pub fn typescript() -> String {
    format!(
        "// Generated from the layout declaration (src/flat/layout.rs) by `HANDRIG_GENERATE=write cargo\n\
         // test --lib flat`; a test fails when this file is stale. Do not edit.\n\n\
         /** The layout version these types describe (`LAYOUT.version`). */\n\
         export const LAYOUT_VERSION = {VERSION};\n\n{}\n{}",
        interface(
            "InputLayout",
            "Offsets of the input `Float32Array` (`LAYOUT.input`). See docs/reference/flat-layout.md.",
            input::ROWS
        ),
        interface(
            "OutputLayout",
            "Offsets of the output `Float32Array` (`LAYOUT.output`). See docs/reference/flat-layout.md.",
            output::ROWS
        ),
    )
}

/// The layout table of `docs/reference/flat-layout.md`, markers included.
#[must_use]
pub fn table() -> String {
    let mut s =
        format!("{TABLE_BEGIN}\n| field | offset | size | what |\n| --- | ---: | ---: | --- |\n");
    let all: Vec<&Row> = super::layout::rows().collect();
    for (k, r) in all.iter().enumerate() {
        let d = &r.detail;
        match d.kind {
            RowKind::Stride => continue,
            RowKind::Length => {
                s.push_str(&format!("| `{}` | {} | | |\n", r.path, r.offset));
                continue;
            }
            _ => {}
        }
        let offset = if d.kind == RowKind::SlotField {
            format!("+{}", r.offset)
        } else {
            r.offset.to_string()
        };
        let size = if d.count == 1 {
            d.width.to_string()
        } else {
            format!("{} × {}", d.count, d.width)
        };
        let mut what = one_line(d.doc);
        if let Some(stride) = all.get(k + 1).filter(|n| n.detail.kind == RowKind::Stride) {
            what.push_str(&format!(" (`{}` = {})", stride.path, stride.offset));
        }
        s.push_str(&format!("| `{}` | {offset} | {size} | {what} |\n", r.path));
    }
    s.push_str(TABLE_END);
    s.push('\n');
    s
}

/// `page` with its generated table replaced by [`table`] (`None` without both markers).
#[must_use]
pub fn with_table(page: &str) -> Option<String> {
    let begin = page.find(TABLE_BEGIN)?;
    let end = page[begin..].find(TABLE_END)? + begin + TABLE_END.len();
    let end = if page[end..].starts_with('\n') {
        end + 1
    } else {
        end
    };
    Some(format!("{}{}{}", &page[..begin], table(), &page[end..]))
}

#[cfg(all(test, not(target_arch = "wasm32")))]
mod tests {
    use super::*;
    use crate::options::generated::compare_with_committed;

    const COMMAND: &str = "cargo test --lib flat";

    #[test]
    fn generated_typescript_is_committed() {
        compare_with_committed(TYPESCRIPT_PATH, &typescript(), COMMAND);
    }

    #[test]
    fn generated_layout_json_is_committed() {
        compare_with_committed(JSON_PATH, &layout_json(), COMMAND);
    }

    #[test]
    fn generated_layout_table_is_committed() {
        let full = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(MARKDOWN_PATH);
        let page = std::fs::read_to_string(full).expect("docs/reference/flat-layout.md");
        let fresh =
            with_table(&page).expect("docs/reference/flat-layout.md has the layout-table markers");
        compare_with_committed(MARKDOWN_PATH, &fresh, COMMAND);
    }

    /// A change of any row's path, offset or size without a [`VERSION`] bump fails here: the
    /// signature is recorded with the version.
    #[test]
    fn the_layout_signature_moves_with_the_version() {
        // FNV-1a over every row's path, offset and size.
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let mut eat = |bytes: &[u8]| {
            for b in bytes {
                h ^= u64::from(*b);
                h = h.wrapping_mul(0x0100_0000_01b3);
            }
        };
        for r in super::super::layout::rows() {
            eat(r.path.as_bytes());
            for n in [r.offset, r.detail.count, r.detail.width] {
                eat(&(n as u64).to_le_bytes());
            }
        }
        assert_eq!(
            (VERSION, h),
            (VERSION, super::super::layout::LAYOUT_SIGNATURE),
            "the layout changed: bump VERSION in src/flat/layout.rs, say what changed, and record \
             the new signature {h:#x}"
        );
    }
}
