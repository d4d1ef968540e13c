//! The headline of a report: what was measured and what came out, read from the result file
//! before any check, so a reader sees the scene, the statistics and the estimates with their
//! errors at the top of the page, beside the verdict.

use serde::Serialize;
use serde_json::Value;

/// One line of the headline.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HeadlineRow {
    /// What it is ("w", "D", "collisions").
    pub name: String,
    /// Its value as text, an estimate with its standard error ("0.15229 ± 0.00011").
    pub value: String,
}

/// The parameters shown when the result has them, with their labels.
const PARAMETERS: [(&str, &str); 5] = [
    ("scene", "scene"),
    ("w", "w (gap)"),
    ("field", "field B"),
    ("collisions", "collisions"),
    ("particles", "particles"),
];

/// The estimates shown, each with its `_err`.
const ESTIMATES: [&str; 10] = [
    "D", "D_xx", "D_xy", "p_bs", "D_escape", "D_hops", "gamma", "lambda", "lyapunov", "entropy",
];

/// The headline of the result `value` of kind `kind`: the parameters, batches and seed, the
/// estimates with their errors, and, for a sweep, its points.
pub fn headline(kind: &str, value: &Value) -> Vec<HeadlineRow> {
    let mut rows = vec![row("result", kind.to_string())];
    for (key, label) in PARAMETERS {
        if let Some(v) = value.get(key).and_then(plain) {
            rows.push(row(label, v));
        }
    }
    let meta = value.get("meta");
    for (key, label) in [("batches", "batches"), ("seed", "seed")] {
        if let Some(v) = meta.and_then(|m| m.get(key)).and_then(plain) {
            rows.push(row(label, v));
        }
    }
    if let Some(points) = value.get("rows").and_then(Value::as_array) {
        rows.push(row("points", points.len().to_string()));
    }
    for key in ESTIMATES {
        let x = value.get(key).and_then(Value::as_f64);
        let e = value.get(format!("{key}_err")).and_then(Value::as_f64);
        if let (Some(x), Some(e)) = (x, e) {
            rows.push(row(key, with_error(x, e)));
        }
    }
    rows
}

fn row(name: &str, value: String) -> HeadlineRow {
    HeadlineRow {
        name: name.to_string(),
        value,
    }
}

/// A scalar as text (a string without quotes, a number as written), `None` for anything else.
fn plain(v: &Value) -> Option<String> {
    match v {
        Value::String(s) => Some(s.clone()),
        Value::Number(n) => Some(n.to_string()),
        Value::Bool(b) => Some(b.to_string()),
        _ => None,
    }
}

/// `x ± e` with the error to two significant digits and the value to the same decimal place
/// ("0.15229 ± 0.00011"); in scientific notation where that place is beyond 10⁻⁶ or above 10⁶.
pub fn with_error(x: f64, e: f64) -> String {
    if !(x.is_finite() && e.is_finite() && e > 0.0) {
        return format!("{x} ± {e}");
    }
    let place = e.log10().floor() as i32 - 1;
    if !(-6..=6).contains(&place) || x.abs() >= 1e6 {
        return format!("{x:.4e} ± {e:.1e}");
    }
    let decimals = (-place).max(0) as usize;
    format!("{x:.decimals$} ± {e:.decimals$}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_estimate_is_shown_to_the_place_of_its_error() {
        assert_eq!(with_error(0.152_287_3, 0.000_113_2), "0.15229 ± 0.00011");
        assert_eq!(with_error(12.3456, 0.27), "12.35 ± 0.27");
        assert_eq!(with_error(1234.4, 27.0), "1234 ± 27");
        assert_eq!(with_error(3e-9, 2e-10), "3.0000e-9 ± 2.0e-10");
    }

    #[test]
    fn the_headline_reads_the_parameters_and_estimates_the_result_has() {
        let v = serde_json::json!({
            "w": 0.1, "collisions": 2000000000u64, "D": 0.152_287_3, "D_err": 0.000_113_2,
            "meta": {"batches": 32, "seed": 1}
        });
        let h = headline("diffusion", &v);
        let text: Vec<String> = h
            .iter()
            .map(|r| format!("{}={}", r.name, r.value))
            .collect();
        assert_eq!(
            text,
            [
                "result=diffusion",
                "w (gap)=0.1",
                "collisions=2000000000",
                "batches=32",
                "seed=1",
                "D=0.15229 ± 0.00011"
            ]
        );
    }
}
