//! A periodic table as it is written: a TOML file (`--table FILE`) or a Python dict, every number
//! kept as the exact text typed.
//!
//! ```toml
//! name = "two-radius square"
//! [lattice]
//! e1 = ["1", "0"]        # along the x axis
//! e2 = ["0", "1"]        # e2.y > 0
//! [[disks]]
//! centre = ["0", "0"]
//! radius = "2/5"
//! [[disks]]
//! centre = ["1/2", "1/2"]
//! radius = "1/5"
//! ```
//!
//! A number is a string (`"2/5"`, `"0.4"`, `"1e-3"`) or an integer: a TOML or JSON float would be
//! rounded to binary before the table saw it, so it is refused with the advice to quote it.

use std::path::Path;

use rug::Rational;
use serde::{Deserialize, Serialize};

use crate::Error;
use crate::numbers::exact::parse_exact;
use crate::scenes::table::TableError;

/// The largest table file read (a table is a few lines; a bigger file is not one).
pub const MAX_FILE_BYTES: u64 = crate::files::Cap::TABLE.bytes;

/// An exact number as written: a decimal (`"0.4"`, `"1e-3"`) or a fraction (`"2/5"`), or an
/// integer.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "Written", into = "String")]
pub struct Number(String);

/// What a file may hold where a number goes.
#[derive(Deserialize)]
#[serde(untagged)]
enum Written {
    Text(String),
    Integer(i64),
    Float(f64),
}

impl TryFrom<Written> for Number {
    type Error = String;
    fn try_from(w: Written) -> Result<Self, String> {
        match w {
            Written::Text(t) => Number::new(&t),
            Written::Integer(i) => Ok(Number(i.to_string())),
            Written::Float(x) => Err(format!(
                "the number {x} is written as a float, which is rounded to binary before the \
                 table sees it: quote it (\"{x}\") or write a fraction such as \"2/5\""
            )),
        }
    }
}

impl From<Number> for String {
    fn from(n: Number) -> String {
        n.0
    }
}

impl Number {
    /// The number written `text` (trimmed), checked to be an exact decimal or fraction.
    ///
    /// # Errors
    /// Text that is not a number.
    pub fn new(text: &str) -> Result<Self, String> {
        let t = text.trim();
        parse_exact(t).map_err(|e| e.to_string())?;
        Ok(Number(t.to_string()))
    }

    /// The text as written.
    pub fn text(&self) -> &str {
        &self.0
    }

    /// The value, exactly.
    pub fn value(&self) -> Rational {
        parse_exact(&self.0).expect("checked when the number was read")
    }
}

impl std::fmt::Display for Number {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// The lattice of a table: e₁ along the x axis, e₂ above it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LatticeSpec {
    /// e₁ = (a, 0), a > 0.
    pub e1: [Number; 2],
    /// e₂ = (b, h), h > 0.
    pub e2: [Number; 2],
}

/// One disk of a cell: its centre (anywhere: it is reduced into the cell) and its radius.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DiskSpec {
    /// The centre (x, y).
    pub centre: [Number; 2],
    /// The radius, > 0.
    pub radius: Number,
}

/// A periodic table of disks as written: its lattice and the disks of one cell.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TableSpec {
    /// A name for labels and reports.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// The lattice.
    pub lattice: LatticeSpec,
    /// The disks of one cell, each once (none is refused by the validation, naming the count).
    #[serde(default)]
    pub disks: Vec<DiskSpec>,
}

impl TableSpec {
    /// The table written in TOML.
    ///
    /// # Errors
    /// Text that is not such a table ([`TableError::Syntax`], the parser's message with its
    /// line).
    pub fn from_toml(text: &str) -> Result<Self, Error> {
        toml::from_str(text).map_err(|e| TableError::Syntax(one_line(&e.to_string())).into())
    }

    /// The table written in JSON (how the Python package passes a dict).
    ///
    /// # Errors
    /// Text that is not such a table.
    pub fn from_json(text: &str) -> Result<Self, Error> {
        let refuse =
            |e: serde_json::Error| Error::from(TableError::Syntax(one_line(&e.to_string())));
        let value = crate::engine::json::parse_unique(text.as_bytes()).map_err(refuse)?;
        serde_json::from_value(value).map_err(refuse)
    }

    /// The table in the TOML file `path` (at most [`MAX_FILE_BYTES`]).
    ///
    /// # Errors
    /// A file that cannot be read (naming it) or is not a table (naming it).
    pub fn read(path: &Path) -> Result<Self, Error> {
        let text = crate::files::read_to_string(path, crate::files::Cap::TABLE)?;
        Self::from_toml(&text).map_err(|e| Error::malformed(path, e))
    }

    /// The name, or `"table"`.
    pub fn title(&self) -> &str {
        self.name.as_deref().unwrap_or("table")
    }
}

/// A parser's message on one line (refusals are one line).
fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    const TWO_RADII: &str = r#"
        name = "two radii"
        [lattice]
        e1 = ["1", 0]
        e2 = [0, "1"]
        [[disks]]
        centre = ["0", "0"]
        radius = "2/5"
        [[disks]]
        centre = ["1/2", "0.5"]
        radius = "1/5"
    "#;

    #[test]
    fn a_table_keeps_every_number_as_written() {
        let t = TableSpec::from_toml(TWO_RADII).unwrap();
        assert_eq!(t.title(), "two radii");
        assert_eq!(t.disks[1].centre[1].text(), "0.5");
        assert_eq!(t.disks[0].radius.value(), Rational::from((2, 5)));
        let json = serde_json::to_string(&t).unwrap();
        assert_eq!(TableSpec::from_json(&json).unwrap(), t);
    }

    #[test]
    fn floats_unknown_keys_and_words_are_refused() {
        let float = TWO_RADII.replace("\"2/5\"", "0.4");
        let e = TableSpec::from_toml(&float).unwrap_err().to_string();
        assert!(e.contains("quote it"), "{e}");
        let extra = TWO_RADII.replace("radius = \"1/5\"", "radius = \"1/5\"\ncolour = \"red\"");
        assert!(TableSpec::from_toml(&extra).is_err());
        let word = TWO_RADII.replace("\"2/5\"", "\"two fifths\"");
        assert!(TableSpec::from_toml(&word).is_err());
        assert!(
            !TableSpec::from_toml(&word)
                .unwrap_err()
                .to_string()
                .contains('\n')
        );
    }
}
