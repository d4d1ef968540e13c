//! Build provenance for `lorentz report`: the git commit of the checkout (when built from one,
//! with `-dirty` when its sources had uncommitted changes) and the rustc version, as compile-time
//! environment variables.

use std::process::Command;

fn main() {
    let run = |cmd: &str, args: &[&str]| {
        Command::new(cmd)
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
            .filter(|s| !s.is_empty())
    };
    // The paths the binary is built from: a change to any of them not yet committed makes the
    // build `-dirty`, so a report never names a commit the binary was not built from.
    let sources = ["src", "Cargo.toml", "Cargo.lock", "build.rs"];
    let mut commit = run("git", &["rev-parse", "HEAD"]).unwrap_or_else(|| "unknown".into());
    let mut status = vec!["status", "--porcelain", "--untracked-files=normal", "--"];
    status.extend(sources);
    if commit != "unknown" && run("git", &status).is_some() {
        commit.push_str("-dirty");
    }
    for path in sources {
        println!("cargo:rerun-if-changed={path}");
    }
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let version = run(&rustc, &["--version"]).unwrap_or_else(|| "unknown".into());
    println!("cargo:rustc-env=LORENTZ_GIT_COMMIT={commit}");
    println!("cargo:rustc-env=LORENTZ_RUSTC_VERSION={version}");
    // A new commit changes HEAD (detached) or the branch's ref; nothing else reruns this.
    let mut watch = vec!["HEAD".to_string(), "packed-refs".to_string()];
    watch.extend(run("git", &["symbolic-ref", "-q", "HEAD"]));
    for name in watch {
        // --git-path resolves the files of linked worktrees too; a missing file is not watched
        // (cargo would rerun on every build).
        if let Some(path) = run("git", &["rev-parse", "--git-path", &name])
            && std::path::Path::new(&path).exists()
        {
            println!("cargo:rerun-if-changed={path}");
        }
    }
    println!("cargo:rerun-if-changed=build.rs");
}
