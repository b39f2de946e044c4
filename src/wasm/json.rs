//! [`Json::parse`] on wasm32: the engine's `JSON.parse`, then a walk of the result into a
//! [`Json`] tree, so that the `.wasm` carries no JSON parser. Runs no user code: `JSON.parse`
//! without a reviver builds plain arrays and objects, and only their own data properties are
//! read.

use js_sys::{Array, Object, Reflect};
use wasm_bindgen::{JsCast, JsValue};

use crate::json::{too_deep, Json, JsonError, MAX_DEPTH};

fn js_parse(text: &str) -> Result<JsValue, JsonError> {
    js_sys::JSON::parse(text).map_err(|e| {
        JsonError::Invalid(
            e.dyn_ref::<js_sys::Error>()
                .map_or_else(|| "JSON.parse failed".into(), |e| e.message().into()),
        )
    })
}

/// See [`Json::parse`].
pub(crate) fn parse(text: &str) -> Result<Json, JsonError> {
    convert(&js_parse(text)?, 0)
}

/// See [`Json::parse_members`].
pub(crate) fn parse_members(
    text: &str,
    keys: &[&str],
    max_len: usize,
) -> Result<Option<Vec<(String, Json)>>, JsonError> {
    let top = js_parse(text)?;
    if !top.is_object() || Array::is_array(&top) {
        return Ok(None);
    }
    let object: &Object = top.unchecked_ref();
    // In document order, as the native reader keeps them.
    let names = Object::keys(object);
    let mut out = Vec::new();
    for i in 0..names.length() {
        let name = names.get(i);
        let Some(key) = name.as_string().filter(|k| keys.contains(&k.as_str())) else {
            continue;
        };
        let value = get(&top, &name)?;
        if Array::is_array(&value) && value.unchecked_ref::<Array>().length() as usize > max_len {
            return Err(JsonError::TooLong(key));
        }
        out.push((key, convert(&value, 1)?));
    }
    Ok(Some(out))
}

fn get(object: &JsValue, key: &JsValue) -> Result<JsValue, JsonError> {
    Reflect::get(object, key).map_err(|_| JsonError::Invalid("unreadable member".into()))
}

/// `value`, `depth` arrays or objects down. Numbers first: most of a glTF's values are (each
/// test is a call into JavaScript).
fn convert(value: &JsValue, depth: usize) -> Result<Json, JsonError> {
    if let Some(x) = value.as_f64() {
        // JSON.parse reads 1e999 as Infinity; serde_json (native) rejects it.
        return if x.is_finite() {
            Ok(Json::Number(x))
        } else {
            Err(JsonError::Invalid("number out of range".into()))
        };
    }
    if let Some(s) = value.as_string() {
        return Ok(Json::String(s));
    }
    let array = Array::is_array(value);
    if array || value.is_object() {
        if depth >= MAX_DEPTH {
            return Err(too_deep());
        }
    } else if let Some(b) = value.as_bool() {
        return Ok(Json::Bool(b));
    } else if value.is_null() {
        return Ok(Json::Null);
    } else {
        return Err(JsonError::Invalid("not a JSON value".into()));
    }
    if array {
        let array: &Array = value.unchecked_ref();
        let mut items = Vec::with_capacity(array.length() as usize);
        for i in 0..array.length() {
            items.push(convert(&array.get(i), depth + 1)?);
        }
        return Ok(Json::Array(items));
    }
    let names = Object::keys(value.unchecked_ref::<Object>());
    let mut members = Vec::with_capacity(names.length() as usize);
    for i in 0..names.length() {
        let name = names.get(i);
        let member = convert(&get(value, &name)?, depth + 1)?;
        members.push((name.as_string().unwrap_or_default(), member));
    }
    Ok(Json::Object(members))
}
