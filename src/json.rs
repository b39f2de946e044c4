//! JSON documents, for the options and the `.vrm` reader: a small document type ([`Json`]),
//! text parsing, and decoding into handrig's option types ([`Decode`]) with errors naming the
//! field path (`options.arm.shoulderAngle: expected a number, got "0.3"`).
//!
//! The WebAssembly build parses no JSON text itself: [`Json::parse`] calls the engine's
//! `JSON.parse` and walks the result, which keeps a JSON parser out of the shipped `.wasm`.
//! Native builds parse with `serde_json`. Both give the same documents: numbers are `f64`
//! (`1` and `1.0` are the same number), a key given twice keeps its last value, a number out
//! of `f64`'s range is invalid, and arrays and objects nested deeper than [`MAX_DEPTH`] levels
//! are an error (never a stack overflow).

use glam::Vec3;

use crate::error::{Error, Result};

/// Deepest nesting of arrays and objects accepted (options nest 4 levels, glTF extensions
/// about 10).
pub const MAX_DEPTH: usize = 64;

/// A JSON value. Objects keep their members in document order, each key once.
#[derive(Clone, Debug, PartialEq)]
pub enum Json {
    /// `null`.
    Null,
    /// `true` or `false`.
    Bool(bool),
    /// A number (always finite).
    Number(f64),
    /// A string.
    String(String),
    /// An array.
    Array(Vec<Json>),
    /// An object: its members in document order, keys unique.
    Object(Vec<(String, Json)>),
}

/// Why JSON text was not read.
#[derive(Clone, Debug, PartialEq)]
pub enum JsonError {
    /// Not valid JSON, a number out of range or nesting deeper than [`MAX_DEPTH`]: the reason.
    Invalid(String),
    /// [`Json::parse_members`]: this member is an array longer than allowed.
    TooLong(String),
}

impl core::fmt::Display for JsonError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            JsonError::Invalid(why) => write!(f, "not valid JSON: {why}"),
            JsonError::TooLong(key) => write!(f, "{key}: too many items"),
        }
    }
}

impl std::error::Error for JsonError {}

/// The message of nesting deeper than [`MAX_DEPTH`].
pub(crate) fn too_deep() -> JsonError {
    JsonError::Invalid(format!(
        "arrays and objects nested deeper than {MAX_DEPTH} levels"
    ))
}

impl Json {
    /// Parses JSON text.
    ///
    /// # Errors
    /// [`JsonError::Invalid`] with the reason.
    pub fn parse(text: &str) -> Result<Json, JsonError> {
        #[cfg(target_arch = "wasm32")]
        {
            crate::wasm::json::parse(text)
        }
        #[cfg(not(target_arch = "wasm32"))]
        {
            native::parse(text)
        }
    }

    /// Parses JSON text whose top level should be an object, keeping only the members named
    /// in `keys` (in document order; the others are checked but not kept). `Ok(None)` when the
    /// top level is not an object. A kept member that is an array of more than `max_len`
    /// items is an error, found before the array is converted: this bounds the work a
    /// hostile file costs (the `.vrm` reader's `nodes`).
    ///
    /// # Errors
    /// [`JsonError::Invalid`] with the reason; [`JsonError::TooLong`] naming the member.
    pub fn parse_members(
        text: &str,
        keys: &[&str],
        max_len: usize,
    ) -> Result<Option<Vec<(String, Json)>>, JsonError> {
        #[cfg(target_arch = "wasm32")]
        {
            crate::wasm::json::parse_members(text, keys, max_len)
        }
        #[cfg(not(target_arch = "wasm32"))]
        {
            native::parse_members(text, keys, max_len)
        }
    }

    /// The member `key` of an object (`None` for a missing key or a value that is not an
    /// object).
    #[must_use]
    pub fn get(&self, key: &str) -> Option<&Json> {
        self.as_object()?
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v)
    }

    /// The number, if this is one.
    #[must_use]
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            Json::Number(x) => Some(*x),
            _ => None,
        }
    }

    /// The boolean, if this is one.
    #[must_use]
    pub fn as_bool(&self) -> Option<bool> {
        match self {
            Json::Bool(b) => Some(*b),
            _ => None,
        }
    }

    /// The string, if this is one.
    #[must_use]
    pub fn as_str(&self) -> Option<&str> {
        match self {
            Json::String(s) => Some(s),
            _ => None,
        }
    }

    /// The items, if this is an array.
    #[must_use]
    pub fn as_array(&self) -> Option<&[Json]> {
        match self {
            Json::Array(a) => Some(a),
            _ => None,
        }
    }

    /// The members, if this is an object.
    #[must_use]
    pub fn as_object(&self) -> Option<&[(String, Json)]> {
        match self {
            Json::Object(o) => Some(o),
            _ => None,
        }
    }

    /// Whether this is `null`.
    #[must_use]
    pub fn is_null(&self) -> bool {
        matches!(self, Json::Null)
    }

    /// The value for an error message, short whatever its size: integers and short strings
    /// as written, anything else by kind (`a number`, `a string`, `an array`, ...). Floats
    /// are not printed (their formatting code would grow the `.wasm`).
    #[must_use]
    pub fn describe(&self) -> String {
        match self {
            Json::Null => "null".into(),
            Json::Bool(b) => if *b { "true" } else { "false" }.into(),
            Json::Number(x) if x.fract() == 0.0 && x.abs() < 1e15 => format!("{}", *x as i64),
            Json::Number(_) => "a number".into(),
            Json::String(s) if s.len() <= 32 => format!("\"{s}\""),
            Json::String(_) => "a string".into(),
            Json::Array(_) => "an array".into(),
            Json::Object(_) => "an object".into(),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Decoding

/// A type read from a [`Json`] value, as the options are.
pub trait Decode: Sized {
    /// Reads `json`; `path` is its JS path (`options.arm`), named in errors.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the field: a wrong type, an unknown key, a missing
    /// required key, an unknown name.
    fn decode(json: &Json, path: &str) -> Result<Self>;
}

/// `path.key`.
#[must_use]
pub fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}

/// `expected <what>, got <value>` at `path`.
#[cold]
#[inline(never)]
#[must_use]
pub fn expected(path: &str, what: &str, got: &Json) -> Error {
    Error::invalid(path, format!("expected {what}, got {}", got.describe()))
}

/// The members of an object; an error naming `path` for anything else.
///
/// # Errors
/// `json` is not an object.
pub fn object<'a>(json: &'a Json, path: &str) -> Result<&'a [(String, Json)]> {
    json.as_object()
        .ok_or_else(|| expected(path, "an object", json))
}

/// An unknown key (`path` includes it), listing the known ones.
#[cold]
#[inline(never)]
#[must_use]
pub fn unknown_field(path: &str, known: &[&str]) -> Error {
    Error::invalid(
        path,
        format!("unknown field (expected one of {})", known.join(", ")),
    )
}

/// A required key missing from the object at `path`.
#[cold]
#[inline(never)]
#[must_use]
pub fn missing(path: &str, key: &str) -> Error {
    Error::invalid(join(path, key), "missing (required)")
}

/// The index in `names` of a string value (an enum by its JS name).
///
/// # Errors
/// Not a string, or not one of the names.
#[inline(never)]
pub fn one_of(json: &Json, path: &str, names: &[&str]) -> Result<usize> {
    let quoted = || {
        let quoted: Vec<String> = names.iter().map(|n| format!("\"{n}\"")).collect();
        quoted.join(", ")
    };
    let s = json
        .as_str()
        .ok_or_else(|| expected(path, &format!("one of {}", quoted()), json))?;
    names.iter().position(|n| *n == s).ok_or_else(|| {
        Error::invalid(
            path,
            format!("must be one of {}, got {}", quoted(), json.describe()),
        )
    })
}

/// Calls `set(i, value, path)` for every member of the object at `path`, `i` the index of
/// its key in `names`; a key not in `names` is an error.
///
/// # Errors
/// Not an object, an unknown key, or what `set` returns.
#[inline(never)]
pub fn decode_fields(
    json: &Json,
    path: &str,
    names: &[&str],
    set: &mut dyn FnMut(usize, &Json, &str) -> Result<()>,
) -> Result<()> {
    for (key, value) in object(json, path)? {
        let at = join(path, key);
        let i = names
            .iter()
            .position(|n| n == key)
            .ok_or_else(|| unknown_field(&at, names))?;
        set(i, value, &at)?;
    }
    Ok(())
}

impl Decode for bool {
    #[inline(never)]
    fn decode(json: &Json, path: &str) -> Result<Self> {
        json.as_bool()
            .ok_or_else(|| expected(path, "true or false", json))
    }
}

impl Decode for f32 {
    #[inline(never)]
    fn decode(json: &Json, path: &str) -> Result<Self> {
        json.as_f64()
            .map(|x| x as f32)
            .ok_or_else(|| expected(path, "a number", json))
    }
}

impl Decode for f64 {
    fn decode(json: &Json, path: &str) -> Result<Self> {
        json.as_f64()
            .ok_or_else(|| expected(path, "a number", json))
    }
}

/// A non-negative integer up to `max`.
fn integer(json: &Json, path: &str, max: u64) -> Result<u64> {
    json.as_f64()
        .filter(|x| x.fract() == 0.0 && *x >= 0.0 && *x <= max as f64)
        .map(|x| x as u64)
        .ok_or_else(|| expected(path, &format!("an integer in 0..={max}"), json))
}

impl Decode for u32 {
    fn decode(json: &Json, path: &str) -> Result<Self> {
        integer(json, path, u32::MAX.into()).map(|x| x as u32)
    }
}

impl Decode for usize {
    fn decode(json: &Json, path: &str) -> Result<Self> {
        // Any count handrig takes fits in 32 bits; the same bound on every target.
        integer(json, path, u32::MAX.into()).map(|x| x as usize)
    }
}

/// `null` is `None`.
impl<T: Decode> Decode for Option<T> {
    fn decode(json: &Json, path: &str) -> Result<Self> {
        if json.is_null() {
            Ok(None)
        } else {
            T::decode(json, path).map(Some)
        }
    }
}

/// An array; items are named `path[i]`.
impl<T: Decode> Decode for Vec<T> {
    #[inline(never)]
    fn decode(json: &Json, path: &str) -> Result<Self> {
        let items = json
            .as_array()
            .ok_or_else(|| expected(path, "an array", json))?;
        let mut out = Vec::with_capacity(items.len());
        for (i, v) in items.iter().enumerate() {
            out.push(T::decode(v, &format!("{path}[{i}]"))?);
        }
        Ok(out)
    }
}

/// `[x, y, z]`.
impl Decode for Vec3 {
    #[inline(never)]
    fn decode(json: &Json, path: &str) -> Result<Self> {
        let bad = || expected(path, "[x, y, z]", json);
        let a = json.as_array().filter(|a| a.len() == 3).ok_or_else(bad)?;
        let c = |k: usize| a[k].as_f64().map(|x| x as f32).ok_or_else(bad);
        Ok(Vec3::new(c(0)?, c(1)?, c(2)?))
    }
}

/// `impl Decode` for an options struct whose every field has a default (`Default`): an
/// object of the listed camelCase keys, each optional; any other key is an error.
macro_rules! decode_struct {
    ($ty:ty { $($name:literal => $field:ident),* $(,)? }) => {
        impl $crate::json::Decode for $ty {
            #[allow(unused_assignments)]
            #[inline(never)]
            fn decode(json: &$crate::json::Json, path: &str) -> $crate::error::Result<Self> {
                let mut out = <$ty as Default>::default();
                $crate::json::decode_fields(json, path, &[$($name),*], &mut |i, value, at| {
                    // The `k`-th listed field is the `k`-th name.
                    let mut k = 0;
                    $(
                        if i == k {
                            out.$field = $crate::json::Decode::decode(value, at)?;
                        }
                        k += 1;
                    )*
                    Ok(())
                })?;
                Ok(out)
            }
        }
    };
}
pub(crate) use decode_struct;

/// `impl Decode` for a fieldless enum written as one of the listed strings.
macro_rules! decode_enum {
    ($ty:ident { $($name:literal => $variant:ident),* $(,)? }) => {
        impl $crate::json::Decode for $ty {
            fn decode(json: &$crate::json::Json, path: &str) -> $crate::error::Result<Self> {
                let i = $crate::json::one_of(json, path, &[$($name),*])?;
                Ok([$($ty::$variant),*][i])
            }
        }
    };
}
pub(crate) use decode_enum;

// ---------------------------------------------------------------------------------------------
// Native parsing (serde_json)

#[cfg(not(target_arch = "wasm32"))]
mod native {
    use std::collections::HashMap;

    use serde::de::{
        self, DeserializeSeed, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor,
    };

    use super::{too_deep, Json, JsonError, MAX_DEPTH};

    /// Marks the error of a kept member longer than allowed (custom serde errors are strings).
    const TOO_LONG: &str = "\u{0}too long";

    pub(super) fn parse(text: &str) -> Result<Json, JsonError> {
        let mut de = serde_json::Deserializer::from_str(text);
        let value = Seed {
            depth: 0,
            max_len: usize::MAX,
        }
        .deserialize(&mut de)
        .and_then(|v| de.end().map(|()| v));
        value.map_err(|e| invalid(&e))
    }

    pub(super) fn parse_members(
        text: &str,
        keys: &[&str],
        max_len: usize,
    ) -> Result<Option<Vec<(String, Json)>>, JsonError> {
        let mut de = serde_json::Deserializer::from_str(text);
        let mut too_long = None;
        let top = (&mut de)
            .deserialize_any(Top {
                keys,
                max_len,
                too_long: &mut too_long,
            })
            .and_then(|v| de.end().map(|()| v));
        match (top, too_long) {
            (_, Some(key)) => Err(JsonError::TooLong(key)),
            (Ok(v), None) => Ok(v),
            (Err(e), None) => Err(invalid(&e)),
        }
    }

    fn invalid(e: &serde_json::Error) -> JsonError {
        let msg = e.to_string();
        if msg.starts_with(TOO_DEEP_MARK) {
            too_deep()
        } else {
            JsonError::Invalid(msg)
        }
    }

    /// Marks the error of nesting deeper than [`MAX_DEPTH`].
    const TOO_DEEP_MARK: &str = "\u{0}too deep";

    /// A whole value, `depth` levels down; an array of more than `max_len` items fails.
    struct Seed {
        depth: usize,
        max_len: usize,
    }

    impl Seed {
        fn child(&self) -> Result<Seed, String> {
            if self.depth >= MAX_DEPTH {
                Err(TOO_DEEP_MARK.into())
            } else {
                Ok(Seed {
                    depth: self.depth + 1,
                    max_len: usize::MAX,
                })
            }
        }
    }

    impl<'de> DeserializeSeed<'de> for Seed {
        type Value = Json;
        fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Json, D::Error> {
            d.deserialize_any(self)
        }
    }

    impl<'de> Visitor<'de> for Seed {
        type Value = Json;
        fn expecting(&self, f: &mut core::fmt::Formatter) -> core::fmt::Result {
            f.write_str("a JSON value")
        }
        fn visit_unit<E>(self) -> Result<Json, E> {
            Ok(Json::Null)
        }
        fn visit_bool<E>(self, b: bool) -> Result<Json, E> {
            Ok(Json::Bool(b))
        }
        fn visit_i64<E>(self, x: i64) -> Result<Json, E> {
            Ok(Json::Number(x as f64))
        }
        fn visit_u64<E>(self, x: u64) -> Result<Json, E> {
            Ok(Json::Number(x as f64))
        }
        fn visit_f64<E: de::Error>(self, x: f64) -> Result<Json, E> {
            if x.is_finite() {
                Ok(Json::Number(x))
            } else {
                Err(E::custom("number out of range"))
            }
        }
        fn visit_str<E>(self, s: &str) -> Result<Json, E> {
            Ok(Json::String(s.to_owned()))
        }
        fn visit_string<E>(self, s: String) -> Result<Json, E> {
            Ok(Json::String(s))
        }
        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Json, A::Error> {
            let mut items = Vec::new();
            while let Some(item) =
                seq.next_element_seed(self.child().map_err(de::Error::custom)?)?
            {
                if items.len() == self.max_len {
                    return Err(de::Error::custom(TOO_LONG));
                }
                items.push(item);
            }
            Ok(Json::Array(items))
        }
        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Json, A::Error> {
            let mut members: Vec<(String, Json)> = Vec::new();
            let mut at: HashMap<String, usize> = HashMap::new();
            while let Some(key) = map.next_key::<String>()? {
                let value = map.next_value_seed(self.child().map_err(de::Error::custom)?)?;
                insert(&mut members, &mut at, key, value);
            }
            Ok(Json::Object(members))
        }
    }

    /// A key given twice keeps its first place and its last value (as `JSON.parse`).
    fn insert(
        members: &mut Vec<(String, Json)>,
        at: &mut HashMap<String, usize>,
        key: String,
        value: Json,
    ) {
        if let Some(&i) = at.get(&key) {
            members[i].1 = value;
        } else {
            at.insert(key.clone(), members.len());
            members.push((key, value));
        }
    }

    /// The top level of [`parse_members`].
    struct Top<'a> {
        keys: &'a [&'a str],
        max_len: usize,
        too_long: &'a mut Option<String>,
    }

    impl<'de> Visitor<'de> for Top<'_> {
        type Value = Option<Vec<(String, Json)>>;
        fn expecting(&self, f: &mut core::fmt::Formatter) -> core::fmt::Result {
            f.write_str("a JSON value")
        }
        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
            let mut members = Vec::new();
            let mut at = HashMap::new();
            while let Some(key) = map.next_key::<String>()? {
                if !self.keys.contains(&key.as_str()) {
                    map.next_value::<IgnoredAny>()?;
                    continue;
                }
                let seed = Seed {
                    depth: 1,
                    max_len: self.max_len,
                };
                match map.next_value_seed(seed) {
                    Ok(value) => insert(&mut members, &mut at, key, value),
                    Err(e) => {
                        if e.to_string().starts_with(TOO_LONG) {
                            *self.too_long = Some(key);
                        }
                        return Err(e);
                    }
                }
            }
            Ok(Some(members))
        }
        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
            while seq.next_element::<IgnoredAny>()?.is_some() {}
            Ok(None)
        }
        fn visit_unit<E>(self) -> Result<Self::Value, E> {
            Ok(None)
        }
        fn visit_bool<E>(self, _: bool) -> Result<Self::Value, E> {
            Ok(None)
        }
        fn visit_i64<E>(self, _: i64) -> Result<Self::Value, E> {
            Ok(None)
        }
        fn visit_u64<E>(self, _: u64) -> Result<Self::Value, E> {
            Ok(None)
        }
        fn visit_f64<E>(self, _: f64) -> Result<Self::Value, E> {
            Ok(None)
        }
        fn visit_str<E>(self, _: &str) -> Result<Self::Value, E> {
            Ok(None)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Clone, Debug, PartialEq)]
    struct Inner {
        angle: f32,
        on: bool,
        count: usize,
        scale: Option<f32>,
    }

    impl Default for Inner {
        fn default() -> Self {
            Inner {
                angle: 0.25,
                on: true,
                count: 30,
                scale: None,
            }
        }
    }

    decode_struct!(Inner {
        "angleRad" => angle,
        "on" => on,
        "count" => count,
        "scale" => scale,
    });

    #[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
    enum Mode {
        #[default]
        Fast,
        Slow,
    }

    decode_enum!(Mode { "fast" => Fast, "slowMode" => Slow });

    #[derive(Clone, Debug, PartialEq, Default)]
    struct Outer {
        inner: Inner,
        mode: Mode,
        points: Vec<Option<Vec3>>,
    }

    decode_struct!(Outer {
        "inner" => inner,
        "mode" => mode,
        "points" => points,
    });

    fn outer(text: &str) -> Result<Outer> {
        let json = Json::parse(text).map_err(|e| Error::invalid("options", e.to_string()))?;
        Outer::decode(&json, "options")
    }

    fn message(text: &str) -> String {
        match outer(text) {
            Err(e) => e.to_string(),
            Ok(o) => panic!("{text}: expected an error, got {o:?}"),
        }
    }

    #[test]
    fn parses_every_kind_of_value() {
        let j =
            Json::parse(r#" {"a": [1, -2.5e3, true, false, null, "x\u00e9"], "b": {}} "#).unwrap();
        let a = j.get("a").unwrap().as_array().unwrap();
        assert_eq!(a[0], Json::Number(1.0));
        assert_eq!(a[1].as_f64(), Some(-2500.0));
        assert_eq!(a[2].as_bool(), Some(true));
        assert_eq!(a[3], Json::Bool(false));
        assert!(a[4].is_null());
        assert_eq!(a[5].as_str(), Some("x\u{e9}"));
        assert_eq!(j.get("b").unwrap().as_object().unwrap().len(), 0);
        assert_eq!(j.get("c"), None);
        assert_eq!(a[0].get("a"), None);
    }

    #[test]
    fn invalid_text_and_numbers_are_errors() {
        for text in ["", "{", "[1,]", "{\"a\" 1}", "nul", "1 2", "[1e999]", "'a'"] {
            assert!(
                matches!(Json::parse(text), Err(JsonError::Invalid(_))),
                "{text:?}"
            );
        }
        assert!(message("{\"mode\": ").starts_with("options: not valid JSON: "));
    }

    #[test]
    fn a_repeated_key_keeps_its_first_place_and_last_value() {
        let j = Json::parse(r#"{"a": 1, "b": 2, "a": 3}"#).unwrap();
        assert_eq!(
            j,
            Json::Object(vec![
                ("a".into(), Json::Number(3.0)),
                ("b".into(), Json::Number(2.0)),
            ])
        );
    }

    #[test]
    fn nesting_deeper_than_the_limit_is_an_error() {
        let nested = |n: usize| format!("{}{}", "[".repeat(n), "]".repeat(n));
        assert!(Json::parse(&nested(MAX_DEPTH)).is_ok());
        assert_eq!(Json::parse(&nested(MAX_DEPTH + 1)), Err(too_deep()));
        // Far deeper than any stack: an error, not an overflow.
        let deep = format!("{}1{}", "{\"a\":".repeat(100_000), "}".repeat(100_000));
        assert!(Json::parse(&deep).is_err());
        assert!(Json::parse(&nested(100_000)).is_err());
        let e = Json::parse(&format!("{{\"inner\": {}}}", nested(MAX_DEPTH))).unwrap_err();
        assert!(
            e.to_string().contains("nested deeper than 64 levels"),
            "{e}"
        );
    }

    #[test]
    fn missing_fields_keep_their_defaults() {
        assert_eq!(outer("{}").unwrap(), Outer::default());
        let o = outer(r#"{"inner": {"count": 12}, "mode": "slowMode"}"#).unwrap();
        assert_eq!(o.inner.count, 12);
        assert_eq!(o.inner.angle, 0.25);
        assert!(o.inner.on);
        assert_eq!(o.mode, Mode::Slow);
    }

    #[test]
    fn values_of_every_type_are_read() {
        let o = outer(
            r#"{"inner": {"angleRad": 0.5, "on": false, "count": 3.0, "scale": 2},
                "points": [[1, 2, 3], null]}"#,
        )
        .unwrap();
        assert_eq!(
            o.inner,
            Inner {
                angle: 0.5,
                on: false,
                count: 3,
                scale: Some(2.0)
            }
        );
        assert_eq!(o.points, vec![Some(Vec3::new(1.0, 2.0, 3.0)), None]);
        // null for an Option field is None.
        let o = outer(r#"{"inner": {"scale": null}}"#).unwrap();
        assert_eq!(o.inner.scale, None);
    }

    /// Each `(input, message)`: decoding the input fails with exactly that message.
    fn assert_messages(cases: &[(&str, &str)]) {
        for (input, expected) in cases {
            assert_eq!(message(input), *expected, "{input}");
        }
    }

    #[test]
    fn an_unknown_field_is_named_with_its_path() {
        assert_messages(&[
            (
                r#"{"inner": {"angle": 1}}"#,
                "options.inner.angle: unknown field (expected one of angleRad, on, count, scale)",
            ),
            (
                r#"{"extra": 1}"#,
                "options.extra: unknown field (expected one of inner, mode, points)",
            ),
        ]);
    }

    #[test]
    fn a_wrong_type_is_named_with_its_path() {
        assert_messages(&[
            (
                r#"{"inner": {"angleRad": "0.5"}}"#,
                "options.inner.angleRad: expected a number, got \"0.5\"",
            ),
            (
                r#"{"inner": {"on": 1}}"#,
                "options.inner.on: expected true or false, got 1",
            ),
            (
                r#"{"inner": {"count": 2.5}}"#,
                "options.inner.count: expected an integer in 0..=4294967295, got a number",
            ),
            (
                r#"{"inner": {"count": -1}}"#,
                "options.inner.count: expected an integer in 0..=4294967295, got -1",
            ),
            (
                r#"{"inner": [1]}"#,
                "options.inner: expected an object, got an array",
            ),
            (
                r#"{"points": [[1, 2, 3], [1, 2]]}"#,
                "options.points[1]: expected [x, y, z], got an array",
            ),
            ("null", "options: expected an object, got null"),
            (
                r#"{"inner": {"scale": {}}}"#,
                "options.inner.scale: expected a number, got an object",
            ),
        ]);
    }

    #[test]
    fn enums_are_read_by_name() {
        assert_messages(&[
            (
                r#"{"mode": "slow"}"#,
                "options.mode: must be one of \"fast\", \"slowMode\", got \"slow\"",
            ),
            (
                r#"{"mode": 1}"#,
                "options.mode: expected one of \"fast\", \"slowMode\", got 1",
            ),
        ]);
    }

    #[test]
    fn joint_limits_are_read_by_their_type_tag() {
        use crate::kinematics::JointLimit;
        let limit = |text: &str| JointLimit::decode(&Json::parse(text).unwrap(), "c[1]");
        assert_eq!(
            limit(r#"{"type": "hinge", "axis": [0, 0, 2], "min": -1, "max": 0.5}"#).unwrap(),
            JointLimit::Hinge {
                axis: Vec3::new(0.0, 0.0, 2.0),
                min: -1.0,
                max: 0.5
            }
        );
        assert_eq!(
            limit(r#"{"maxAngle": 0.25, "type": "cone"}"#).unwrap(),
            JointLimit::Cone { max_angle: 0.25 }
        );
        for (text, message) in [
            (r#"{"type": "cone"}"#, "c[1].maxAngle: missing (required)"),
            (
                r#"{"type": "hinge", "min": 0, "max": 1}"#,
                "c[1].axis: missing (required)",
            ),
            (
                r#"{"type": "cone", "maxAngle": 1, "min": 0}"#,
                "c[1].min: unknown field (expected one of type, maxAngle)",
            ),
            (
                r#"{"type": 3}"#,
                r#"c[1].type: expected one of "cone", "hinge", got 3"#,
            ),
            (r#"[]"#, "c[1]: expected an object, got an array"),
        ] {
            assert_eq!(limit(text).unwrap_err().to_string(), message, "{text}");
        }
    }

    #[test]
    fn members_are_selected_and_bounded() {
        let text = r#"{"skip": [1, 2, 3, {"deep": [[[]]]}], "keep": [1, 2], "obj": {"a": 1}}"#;
        let m = Json::parse_members(text, &["keep", "obj"], 2)
            .unwrap()
            .unwrap();
        assert_eq!(m.len(), 2);
        assert_eq!(m[0].0, "keep");
        assert_eq!(m[1].1.get("a"), Some(&Json::Number(1.0)));
        assert_eq!(
            Json::parse_members(text, &["keep"], 1),
            Err(JsonError::TooLong("keep".into()))
        );
        // Skipped members are checked all the same.
        assert!(matches!(
            Json::parse_members(r#"{"skip": [1,], "keep": 1}"#, &["keep"], 2),
            Err(JsonError::Invalid(_))
        ));
        assert_eq!(Json::parse_members("[1]", &["keep"], 2), Ok(None));
        assert_eq!(Json::parse_members("\"x\"", &["keep"], 2), Ok(None));
        assert!(Json::parse_members("{} x", &["keep"], 2).is_err());
    }

    #[test]
    fn long_values_are_described_by_kind() {
        assert_eq!(Json::String("a".repeat(33)).describe(), "a string");
        assert_eq!(Json::String("abc".into()).describe(), "\"abc\"");
        assert_eq!(Json::Number(1e20).describe(), "a number");
        assert_eq!(Json::Number(-7.0).describe(), "-7");
        assert_eq!(Json::Bool(true).describe(), "true");
    }
}
