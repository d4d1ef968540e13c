//! Printing a result: JSON (with its `meta` block) or the human-readable text.

use std::io::Write as _;

use serde::Serialize;

use lorentz_gas::Error;

/// Ends the program after a failed write to standard output: quietly with status 0 when the
/// reader has gone (a broken pipe: the output is no longer wanted), else with the cause on
/// stderr and the status of an I/O failure.
pub fn stdout_failed(e: std::io::Error) -> ! {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        std::process::exit(0);
    }
    let _ = writeln!(
        std::io::stderr(),
        "error: cannot write to standard output: {e}"
    );
    std::process::exit(i32::from(super::EXIT_IO))
}

/// Pretty JSON of a result.
pub fn to_json<T: Serialize>(v: &T) -> Result<String, Error> {
    serde_json::to_string_pretty(v).map_err(Error::encode)
}

/// Prints `r` as JSON when `json`, else through `text`.
pub fn emit<T: Serialize>(json: bool, r: &T, text: impl FnOnce(&T)) -> Result<(), Error> {
    if json {
        println!("{}", to_json(r)?);
    } else {
        text(r);
    }
    Ok(())
}
