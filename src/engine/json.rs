//! JSON as the crate reads untrusted files (result files, journals, sealed files): a
//! [`serde_json::Value`] whose objects may not repeat a key. `serde_json` keeps the last of two
//! equal keys, while another reader of the same file (a person, `jq`, a script) may see the
//! first: a file whose keys repeat says two things, and is refused, naming the key.

use serde::Deserializer;
use serde::de::{DeserializeSeed, Error as _, MapAccess, SeqAccess, Visitor};
use serde_json::{Map, Value};

/// Parses `text` as JSON, refusing an object that repeats a key.
///
/// # Examples
///
/// ```
/// use lorentz_gas::engine::json::parse_unique;
/// assert!(parse_unique(br#"{"D": 0.1, "n": [1, {"a": 2}]}"#).is_ok());
/// let e = parse_unique(br#"{"D": 0.1, "D": 0.2}"#).unwrap_err();
/// assert!(e.to_string().contains("duplicate key `D`"), "{e}");
/// assert!(parse_unique(br#"{"a": [{"x": 1, "x": 1}]}"#).is_err());
/// ```
///
/// # Errors
/// Text that is not JSON, or an object with a repeated key (serde_json's error, with its line
/// and column).
pub fn parse_unique(text: &[u8]) -> Result<Value, serde_json::Error> {
    let mut d = serde_json::Deserializer::from_slice(text);
    let v = Unique.deserialize(&mut d)?;
    d.end()?;
    Ok(v)
}

/// A seed that builds a [`Value`] and refuses a repeated key at any depth.
#[derive(Clone, Copy)]
struct Unique;

impl<'de> DeserializeSeed<'de> for Unique {
    type Value = Value;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Value, D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Unique {
    type Value = Value;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("JSON")
    }
    fn visit_bool<E>(self, b: bool) -> Result<Value, E> {
        Ok(Value::Bool(b))
    }
    fn visit_i64<E>(self, n: i64) -> Result<Value, E> {
        Ok(Value::from(n))
    }
    fn visit_u64<E>(self, n: u64) -> Result<Value, E> {
        Ok(Value::from(n))
    }
    fn visit_f64<E: serde::de::Error>(self, x: f64) -> Result<Value, E> {
        serde_json::Number::from_f64(x)
            .map(Value::Number)
            .ok_or_else(|| E::custom("a number that is not finite"))
    }
    fn visit_str<E>(self, s: &str) -> Result<Value, E> {
        Ok(Value::String(s.to_owned()))
    }
    fn visit_string<E>(self, s: String) -> Result<Value, E> {
        Ok(Value::String(s))
    }
    fn visit_unit<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }
    fn visit_none<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }
    fn visit_some<D: Deserializer<'de>>(self, d: D) -> Result<Value, D::Error> {
        d.deserialize_any(self)
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        let mut v = Vec::new();
        while let Some(x) = seq.next_element_seed(Unique)? {
            v.push(x);
        }
        Ok(Value::Array(v))
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
        let mut m = Map::new();
        while let Some(k) = map.next_key::<String>()? {
            if m.contains_key(&k) {
                return Err(A::Error::custom(format!(
                    "duplicate key `{k}`: a file whose keys repeat says two things"
                )));
            }
            let v = map.next_value_seed(Unique)?;
            m.insert(k, v);
        }
        Ok(Value::Object(m))
    }
}
