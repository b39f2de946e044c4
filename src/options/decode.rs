//! Options from a JSON value, checked and placed by the table ([`super::table::OPTIONS`]).
//!
//! serde reads the text or the JS object into a [`serde_json::Value`]; this walks it: each
//! key is an option's path (nested objects or dotted keys), each value is checked against its
//! row and written through the row's setter. Every error names the path as the user wrote it
//! (`options.filter.minCutoff`).

use serde_json::Value as Json;

use crate::error::{Error, Num, Result};

use super::table::{Kind, OptionSpec, Value, OPTIONS};
use super::RigOptions;

/// Writes every option given in `value` (an object, or `null` for none) into `options`.
pub(super) fn apply(value: &Json, options: &mut RigOptions) -> Result<()> {
    match value {
        Json::Null => Ok(()),
        Json::Object(_) => {
            let mut seen = Vec::new();
            walk(value, "", options, &mut seen)
        }
        other => Err(Error::invalid(
            "options",
            format!("must be an object, got {}", describe(other)),
        )),
    }
}

fn walk(
    value: &Json,
    prefix: &str,
    options: &mut RigOptions,
    seen: &mut Vec<&'static str>,
) -> Result<()> {
    let Json::Object(members) = value else {
        return Ok(());
    };
    for (key, value) in members {
        let path = if prefix.is_empty() {
            key.clone()
        } else {
            format!("{prefix}.{key}")
        };
        let field = format!("options.{path}");
        if let Some(spec) = OPTIONS.iter().find(|s| s.path == path) {
            if seen.contains(&spec.path) {
                return Err(Error::invalid(
                    field,
                    "given twice (as a nested object and as a dotted path)",
                ));
            }
            seen.push(spec.path);
            let v = read(spec, value, &field)?;
            (spec.set)(options, v);
            continue;
        }
        let group = format!("{path}.");
        if !OPTIONS.iter().any(|s| s.path.starts_with(&group)) {
            return Err(Error::invalid(
                field,
                format!("unknown option{}", hint(&path)),
            ));
        }
        match value {
            // `filter: false` is `filter: { enabled: false }`.
            Json::Bool(b) if OPTIONS.iter().any(|s| s.path == format!("{path}.enabled")) => {
                let mut m = serde_json::Map::new();
                m.insert("enabled".into(), Json::Bool(*b));
                walk(&Json::Object(m), &path, options, seen)?;
            }
            Json::Object(_) => walk(value, &path, options, seen)?,
            other => {
                return Err(Error::invalid(
                    field,
                    format!(
                        "must be an object of {path}.* options, got {}",
                        describe(other)
                    ),
                ))
            }
        }
    }
    Ok(())
}

/// The value of `spec` in `json`, checked.
fn read(spec: &OptionSpec, json: &Json, field: &str) -> Result<Value> {
    let v = match spec.kind {
        Kind::Bool => match json {
            Json::Bool(b) => Value::Bool(*b),
            other => return Err(expected(field, "true or false", other)),
        },
        Kind::Enum(names) => {
            let quoted = || {
                let q: Vec<String> = names.iter().map(|n| format!("\"{n}\"")).collect();
                q.join(", ")
            };
            match json.as_str().and_then(|s| names.iter().find(|n| **n == s)) {
                Some(n) => Value::Enum(n),
                None => {
                    return Err(Error::invalid(
                        field,
                        format!("must be one of {}, got {}", quoted(), describe(json)),
                    ))
                }
            }
        }
        Kind::Number { optional, .. } => match json {
            Json::Null if optional => Value::Number(None),
            Json::Number(n) => {
                let x = n.as_f64().unwrap_or(f64::NAN);
                if let Kind::Number { integer: true, .. } = spec.kind {
                    if x.fract() != 0.0 {
                        return Err(Error::invalid(
                            field,
                            format!("must be a whole number{}, got {}", range(spec), Num::f64(x)),
                        ));
                    }
                }
                Value::Number(Some(x as f32))
            }
            other => return Err(expected(field, &format!("a number{}", range(spec)), other)),
        },
        Kind::Points { names, .. } => {
            let mut points = [None; crate::contact::ANCHORS];
            match json {
                Json::Null => {}
                Json::Object(members) => {
                    for (name, p) in members {
                        let at = format!("{field}.{name}");
                        let k = names.iter().position(|n| n == name).ok_or_else(|| {
                            Error::invalid(
                                &at,
                                format!("unknown point (expected one of {})", names.join(", ")),
                            )
                        })?;
                        points[k] = point(p, &at)?;
                    }
                }
                other => {
                    return Err(expected(
                        field,
                        &format!("an object {{ {} }} of [x, y, z] (meters)", names.join(", ")),
                        other,
                    ))
                }
            }
            Value::Points(points)
        }
        Kind::Numbers { len, .. } => {
            let items = json
                .as_array()
                .filter(|a| a.len() == len)
                .ok_or_else(|| expected(field, &format!("an array of {len} numbers"), json))?;
            let mut out = [0.0; 5];
            for (k, (dst, item)) in out.iter_mut().zip(items).enumerate() {
                *dst = item
                    .as_f64()
                    .ok_or_else(|| expected(&format!("{field}[{k}]"), "a number", item))?
                    as f32;
            }
            Value::Numbers(out)
        }
    };
    // Ranges are checked by `RigOptions::validate` (`Rig::new`), for options from JSON and
    // from Rust alike.
    Ok(v)
}

/// `[x, y, z]`, `{ x, y, z }` or `null`.
fn point(json: &Json, field: &str) -> Result<Option<[f32; 3]>> {
    let bad = || expected(field, "[x, y, z]", json);
    let c = |v: Option<&Json>| v.and_then(Json::as_f64).map(|x| x as f32);
    match json {
        Json::Null => Ok(None),
        Json::Array(a) if a.len() == 3 => Ok(Some([
            c(a.first()).ok_or_else(bad)?,
            c(a.get(1)).ok_or_else(bad)?,
            c(a.get(2)).ok_or_else(bad)?,
        ])),
        Json::Object(o) => Ok(Some([
            c(o.get("x")).ok_or_else(bad)?,
            c(o.get("y")).ok_or_else(bad)?,
            c(o.get("z")).ok_or_else(bad)?,
        ])),
        _ => Err(bad()),
    }
}

/// Checks a value against its row: finite numbers within range (whole where asked), points
/// within their limit.
pub(super) fn check(spec: &OptionSpec, value: Value) -> Result<()> {
    let field = || format!("options.{}", spec.path);
    match (spec.kind, value) {
        (
            Kind::Number {
                min, max, integer, ..
            },
            Value::Number(Some(x)),
        ) if !(x.is_finite() && x >= min && x <= max) || (integer && x.fract() != 0.0) => {
            let what = if integer {
                "a whole number"
            } else {
                "a number"
            };
            return Err(Error::invalid(
                field(),
                format!("must be {what}{}, got {}", range(spec), Num::f32(x)),
            ));
        }
        (
            Kind::Number {
                optional: false, ..
            },
            Value::Number(None),
        ) => {
            return Err(Error::invalid(field(), "must be a number (not null)"));
        }
        (Kind::Points { names, limit }, Value::Points(points)) => {
            for (name, p) in names.iter().zip(points) {
                if let Some(p) = p {
                    if !p.iter().all(|c| c.is_finite() && c.abs() <= limit) {
                        return Err(Error::invalid(
                            format!("{}.{name}", field()),
                            format!(
                                "must be [x, y, z]: finite meters within {} of the head bone",
                                Num::f32(limit)
                            ),
                        ));
                    }
                }
            }
        }
        (Kind::Numbers { len, min, max }, Value::Numbers(v)) => {
            for (k, x) in v[..len].iter().enumerate() {
                if !(x.is_finite() && *x >= min && *x <= max) {
                    return Err(Error::invalid(
                        format!("{}[{k}]", field()),
                        format!(
                            "must be a number in {}..{}, got {}",
                            Num::f32(min),
                            Num::f32(max),
                            Num::f32(*x)
                        ),
                    ));
                }
            }
        }
        _ => {}
    }
    Ok(())
}

/// ` in min..max` of a number row.
fn range(spec: &OptionSpec) -> String {
    match spec.kind {
        Kind::Number { min, max, .. } => format!(" in {}..{}", Num::f32(min), Num::f32(max)),
        _ => String::new(),
    }
}

fn expected(field: &str, what: &str, got: &Json) -> Error {
    Error::invalid(field, format!("must be {what}, got {}", describe(got)))
}

/// A value as an error message shows it.
pub(crate) fn describe(v: &Json) -> String {
    match v {
        Json::Null => "null".into(),
        Json::Bool(b) => b.to_string(),
        Json::Number(n) => n.to_string(),
        Json::String(s) => format!("{s:?}"),
        Json::Array(_) => "an array".into(),
        Json::Object(_) => "an object".into(),
    }
}

/// Names users bring from MediaPipe and other rigs for handrig's options.
const ALIASES: [(&str, &str); 3] = [
    ("selfieMode", "inputMirrored"),
    ("mirrored", "mirror"),
    ("flipHorizontal", "inputMirrored"),
];

/// ` (did you mean X?)` for an unknown path: a known alias, or the option or group path
/// nearest in spelling (at most 2 edits, or the same name in another case).
fn hint(path: &str) -> String {
    if let Some((_, to)) = ALIASES.iter().find(|(from, _)| *from == path) {
        return format!(" (did you mean {to}?)");
    }
    let mut best: Option<(usize, &str)> = None;
    for spec in OPTIONS {
        let mut end = 0;
        loop {
            end = spec.path[end..]
                .find('.')
                .map_or(spec.path.len(), |i| end + i);
            let name = &spec.path[..end];
            let d = if name.eq_ignore_ascii_case(path) {
                0
            } else {
                edit_distance(name, path)
            };
            if d < 3 && best.is_none_or(|(b, _)| d < b) {
                best = Some((d, name));
            }
            if end == spec.path.len() {
                break;
            }
            end += 1;
        }
    }
    best.map_or(String::new(), |(_, n)| format!(" (did you mean {n}?)"))
}

/// Levenshtein distance (setup time: option names are short).
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut row = vec![i + 1];
        for (j, cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != *cb);
            row.push(sub.min(prev[j + 1] + 1).min(row[j] + 1));
        }
        prev = row;
    }
    prev[b.len()]
}

#[cfg(test)]
mod tests {
    use super::super::RigOptions;

    fn err(text: &str) -> String {
        RigOptions::from_json(text).unwrap_err().to_string()
    }

    #[test]
    fn errors_name_the_path_as_written() {
        let range = |text: &str| {
            let o = RigOptions::from_json(text).expect("types are right");
            o.validate().unwrap_err().to_string()
        };
        assert!(range(r#"{ "filter": { "minCutoff": 0 } }"#)
            .starts_with("options.filter.minCutoff: must be a number in 0.05..1000, got 0"));
        assert!(err(r#"{ "filter.minCutoff": "1" }"#).starts_with("options.filter.minCutoff:"));
        assert!(err(r#"{ "armSolver": "jacobian" }"#)
            .starts_with(r#"options.armSolver: must be one of "twoBone", "fabrik", "ccd""#));
        assert!(err(r#"{ "calibration": { "frames": 2.5 } }"#)
            .starts_with("options.calibration.frames: must be a whole number"));
        assert!(err(r#"{ "selfieMode": true }"#).contains("did you mean inputMirrored?"));
        assert!(err(r#"{ "filter": { "mincutoff": 1 } }"#)
            .contains("options.filter.mincutoff: unknown option (did you mean filter.minCutoff?)"));
        assert!(
            err(r#"{ "alignment": { "weight": 1 }, "alignment.weight": 1 }"#)
                .contains("given twice")
        );
        assert!(
            range(r#"{ "contact": { "faceAnchors": { "nose": [0, 0, 11] } } }"#)
                .starts_with("options.contact.faceAnchors.nose:")
        );
        assert!(
            err(r#"{ "contact": { "faceAnchors": { "beak": [0, 0, 1] } } }"#)
                .starts_with("options.contact.faceAnchors.beak: unknown point")
        );
        assert!(
            range(r#"{ "retarget": { "tipWeights": [1, 1, -1, 1, 1] } }"#)
                .starts_with("options.retarget.tipWeights[2]:")
        );
        assert!(err("[1]").starts_with("options: must be an object"));
        assert!(err("{ nope").starts_with("options: not valid JSON"));
        assert!(err(r#"{ "arm": 3 }"#).starts_with("options.arm: must be an object of arm.*"));
    }

    #[test]
    fn shorthand_null_and_dotted_paths_decode() {
        let o = RigOptions::from_json(
            r#"{ "filter": false, "dropout.holdMs": 100, "calibration": { "bodyScale": null },
                 "contact": { "torsoRadius": 0.1, "faceAnchors": { "nose": { "x": 0, "y": 0.05, "z": 0.1 } } } }"#,
        )
        .expect("options");
        assert!(!o.filter.enabled);
        assert_eq!(o.dropout.hold_ms, 100.0);
        assert_eq!(o.calibration.body_scale, None);
        assert_eq!(o.contact.torso_radius, Some(0.1));
        assert_eq!(
            o.contact.face_anchors.get(crate::contact::FaceAnchor::Nose),
            Some(glam::Vec3::new(0.0, 0.05, 0.1))
        );
        assert_eq!(
            RigOptions::from_json("null").expect("null"),
            RigOptions::default()
        );
    }
}
