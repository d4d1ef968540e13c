//! The command line: bad input gets a clear error naming the valid range and exit status 2,
//! never a panic; good input gives the documented JSON keys.

use std::process::Command;

fn lorentz(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_lorentz"))
        .args(args)
        .output()
        .expect("run lorentz");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

#[test]
fn bad_input_is_rejected_with_the_valid_range() {
    let cases: &[(&[&str], &str)] = &[
        (&["diffusion", "--w", "0"], "trapped"),
        (&["diffusion", "--w", "-0.1"], "trapped"),
        (&["diffusion", "--w", "0.31"], "0.309"),
        (&["diffusion", "--w", "0.3094010767585031"], "infinite"),
        (&["diffusion", "--w", "NaN"], "finite"),
        (&["diffusion", "--w", "inf"], "finite"),
        (&["diffusion", "--w", "0.1", "--precision", "52"], "53"),
        (&["diffusion", "--w", "0.1", "--precision", "double"], "f64"),
        (
            &["diffusion", "--w", "0.1", "--collisions", "0"],
            "collisions",
        ),
        (&["diffusion", "--w", "0.1", "--batches", "0"], "batches"),
        (&["diffusion", "--w", "0.1", "--batches", "1"], "batches"),
        (
            &["diffusion", "--w", "0.1", "--collisions", "1000"],
            "too small",
        ),
        (
            &[
                "diffusion",
                "--w",
                "0.1",
                "--threads",
                "0",
                "--collisions",
                "2000000",
                "--batches",
                "2",
            ],
            "threads",
        ),
        (&["diffusion", "--w", "0.1", "--window", "40:10"], "window"),
        (&["constants", "--w", "0"], "trapped"),
        (&["constants", "--w", "0.1", "--precision", "20"], "53"),
        (&["bench", "--w", "0.1", "--collisions", "0"], "collisions"),
        (&["bench", "--w", "-1"], "trapped"),
    ];
    for (args, needle) in cases {
        let (code, out, err) = lorentz(args);
        assert_eq!(code, 2, "{args:?}: status {code}, stderr {err}");
        assert!(out.is_empty(), "{args:?}: printed {out}");
        assert!(
            err.to_lowercase().contains(needle),
            "{args:?}: '{err}' lacks '{needle}'"
        );
        assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    }
    // A non-number is refused by the argument parser (also status 2).
    let (code, _, err) = lorentz(&["diffusion", "--w", "abc"]);
    assert_eq!(code, 2);
    assert!(err.contains("invalid value"), "{err}");
}

#[test]
fn json_outputs_have_the_documented_keys() {
    let (code, out, err) = lorentz(&[
        "diffusion",
        "--w",
        "0.2",
        "--collisions",
        "2000000",
        "--batches",
        "4",
        "--window",
        "2:8",
        "--check-window",
        "4:16",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    for k in [
        "w",
        "D",
        "D_err",
        "D_MZ",
        "mean_free_path",
        "mean_free_path_err",
        "mean_free_path_exact",
        "tau_hop",
        "tau_hop_err",
        "tau_hop_exact",
        "collisions",
        "batches",
        "seed",
        "precision",
        "seconds",
        "collisions_per_second",
        "version",
    ] {
        assert!(v.get(k).is_some(), "missing key {k}");
    }
    assert_eq!(v["precision"], "f64");
    let (code, out, _) = lorentz(&[
        "bench",
        "--w",
        "0.1",
        "--collisions",
        "100000",
        "--repetitions",
        "3",
        "--json",
    ]);
    assert_eq!(code, 0);
    let b: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(b["collisions_per_second"].as_f64().unwrap() > 0.0);
    let (code, out, _) = lorentz(&["constants", "--w", "0.1", "--precision", "200", "--json"]);
    assert_eq!(code, 0);
    let c: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(c["w_inf"].as_str().unwrap().starts_with("3.0940107675850"));
}
