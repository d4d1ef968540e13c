//! The rules of [`super`], each on a real file system.

use super::*;
use std::os::unix::fs::{PermissionsExt, symlink};

fn fifo(path: &Path) {
    let c = std::ffi::CString::new(path.as_os_str().as_encoded_bytes()).unwrap();
    // SAFETY: `c` is a NUL-terminated path that lives across the call.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
}

#[test]
fn write_refuses_a_link_and_leaves_its_target_alone() {
    let d = tempfile::tempdir().unwrap();
    let victim = d.path().join("victim");
    std::fs::write(&victim, "precious").unwrap();
    let link = d.path().join("sweep.json");
    symlink(&victim, &link).unwrap();
    let e = write(&link, "overwritten").unwrap_err();
    assert!(matches!(e, Error::UnsafePath { .. }), "{e}");
    assert!(e.to_string().contains("a symbolic link"), "{e}");
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    let e = Stream::create(&link).unwrap_err();
    assert!(e.to_string().contains("a symbolic link"), "{e}");
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
    // No temporary file is left behind.
    assert_eq!(std::fs::read_dir(d.path()).unwrap().count(), 2);
}

#[test]
fn write_replaces_a_regular_file_keeping_its_mode() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join("out.csv");
    std::fs::write(&p, "old").unwrap();
    std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o600)).unwrap();
    write(&p, "new").unwrap();
    assert_eq!(std::fs::read_to_string(&p).unwrap(), "new");
    let mode = std::fs::metadata(&p).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, 0o600);
    // A directory where a file goes is refused.
    std::fs::create_dir(d.path().join("dir")).unwrap();
    assert!(write(d.path().join("dir"), "x").is_err());
}

#[test]
fn a_fifo_is_refused_without_blocking() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join("fifo");
    fifo(&p);
    // Without O_NONBLOCK the open itself would wait forever for a writer.
    let e = read_to_string(&p, Cap::CONFIG).unwrap_err();
    assert!(e.to_string().contains("a FIFO"), "{e}");
    let e = write(&p, "x").unwrap_err();
    assert!(e.to_string().contains("a FIFO"), "{e}");
    let e = Stream::create(&p).unwrap_err();
    assert!(e.to_string().contains("a FIFO"), "{e}");
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::symlink_metadata(&p).unwrap().file_type().is_fifo());
}

#[test]
fn a_subdirectory_that_is_a_link_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let elsewhere = tempfile::tempdir().unwrap();
    let points = d.path().join("points");
    symlink(elsewhere.path(), &points).unwrap();
    let e = create_subdir(&points).unwrap_err();
    assert!(e.to_string().contains("a symbolic link"), "{e}");
    let fresh = d.path().join("fresh");
    create_subdir(&fresh).unwrap();
    create_subdir(&fresh).unwrap();
    assert!(fresh.is_dir());
}

#[test]
fn a_second_lock_is_refused_until_the_first_is_dropped() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join("run.ckpt");
    let first = lock(&p).unwrap();
    let e = lock(&p).unwrap_err();
    assert!(e.to_string().contains("in use by another run"), "{e}");
    drop(first);
    assert!(!d.path().join(".run.ckpt.lock").exists());
    let _again = lock(&p).unwrap();
}

#[test]
fn a_stream_dropped_before_its_commit_leaves_the_old_file_and_nothing_beside_it() {
    use std::io::Write as _;
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join("events.csv");
    let partner = d.path().join("partner.csv");
    std::fs::write(&p, "old").unwrap();
    std::fs::hard_link(&p, &partner).unwrap();
    let mut s = Stream::create(&p).unwrap();
    s.write_all(b"half").unwrap();
    drop(s);
    assert_eq!(std::fs::read_to_string(&p).unwrap(), "old");
    assert_eq!(std::fs::read_dir(d.path()).unwrap().count(), 2);
    // Committed, the name holds the new file and the other hard link the old one.
    let mut s = Stream::create(&p).unwrap();
    s.write_all(b"new").unwrap();
    s.commit().unwrap();
    assert_eq!(std::fs::read_to_string(&p).unwrap(), "new");
    assert_eq!(std::fs::read_to_string(&partner).unwrap(), "old");
    assert_eq!(std::fs::read_dir(d.path()).unwrap().count(), 2);
    // Appending in place to a file of two links is refused.
    std::fs::hard_link(&p, d.path().join("third")).unwrap();
    let e = open_append(&p).unwrap_err();
    assert!(e.to_string().contains("2 hard links"), "{e}");
}

#[test]
fn a_read_over_its_cap_is_refused_from_the_size() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join("big.ckpt");
    let f = std::fs::File::create(&p).unwrap();
    f.set_len(6 << 30).unwrap();
    let e = read(&p, Cap::CHECKPOINT).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!(
            "{}: 6.0 GiB (6442450944 bytes), beyond the 1 GiB a checkpoint can be",
            p.display()
        )
    );
    f.set_len(3).unwrap();
    assert_eq!(read(&p, Cap::CHECKPOINT).unwrap(), vec![0; 3]);
}

#[test]
fn an_output_that_is_an_input_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let input = d.path().join("report.json");
    std::fs::write(&input, "audited").unwrap();
    let other = d.path().join("other");
    std::fs::hard_link(&input, &other).unwrap();
    let outputs = Output::files_in(d.path(), &["report.md", "report.json"]);
    let e = check_outputs(&[&input], &outputs).unwrap_err();
    assert!(e.to_string().contains("the same file as the input"), "{e}");
    let e = check_outputs(&[&other], &outputs).unwrap_err();
    assert!(e.to_string().contains("other"), "{e}");
    check_outputs(&[&input], &Output::files_in(d.path(), &["report.md"])).unwrap();
    // A link among the outputs is refused before any work.
    symlink(&input, d.path().join("report.md")).unwrap();
    let e = check_outputs(&[], &Output::files_in(d.path(), &["report.md"])).unwrap_err();
    assert!(e.to_string().contains("a symbolic link"), "{e}");
}
