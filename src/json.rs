//! JSON documents for the `.vrm` reader (being replaced by serde structs): a small document type ([`Json`]),
//! text parsing, and decoding into handrig's option types ([`Decode`]) with errors naming the
//! field path (`options.arm.shoulderAngle: expected a number, got "0.3"`).
//!
//! The WebAssembly build parses no JSON text itself: [`Json::parse`] calls the engine's
//! `JSON.parse` and walks the result, which keeps a JSON parser out of the shipped `.wasm`.
//! Native builds parse with `serde_json`. Both give the same documents: numbers are `f64`
//! (`1` and `1.0` are the same number), a key given twice keeps its last value, a number out
//! of `f64`'s range is invalid, and arrays and objects nested deeper than [`MAX_DEPTH`] levels
//! are an error (never a stack overflow).

use crate::error::Result;

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
// Native parsing (serde_json)

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
