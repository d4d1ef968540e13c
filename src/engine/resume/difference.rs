//! The first field in which two configurations differ: what a refusal of a checkpoint, a sealed
//! file or a part of another configuration names.

use serde::Serialize;
use serde_json::Value;

/// The first field in which two configurations differ, as `field: a vs b` (`None` if equal).
pub fn difference<C: Serialize>(a: &C, b: &C) -> Option<String> {
    let (a, b) = (serde_json::to_value(a).ok()?, serde_json::to_value(b).ok()?);
    value_difference(&a, &b, "")
}

/// The first differing leaf of two JSON values, with its path.
pub(super) fn value_difference(a: &Value, b: &Value, at: &str) -> Option<String> {
    let name = |k: &str| {
        if at.is_empty() {
            k.to_string()
        } else {
            format!("{at}.{k}")
        }
    };
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let keys: std::collections::BTreeSet<&String> = x.keys().chain(y.keys()).collect();
            keys.into_iter().find_map(|k| match (x.get(k), y.get(k)) {
                (Some(u), Some(v)) => value_difference(u, v, &name(k)),
                (u, v) => Some(format!("{}: {} vs {}", name(k), show(u), show(v))),
            })
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => x
            .iter()
            .zip(y)
            .enumerate()
            .find_map(|(i, (u, v))| value_difference(u, v, &name(&i.to_string()))),
        _ if a == b => None,
        _ => Some(format!(
            "{}: {} vs {}",
            if at.is_empty() { "value" } else { at },
            show(Some(a)),
            show(Some(b))
        )),
    }
}

fn show(v: Option<&Value>) -> String {
    match v {
        None => "absent".into(),
        Some(Value::String(s)) => s.clone(),
        Some(v) => v.to_string(),
    }
}
