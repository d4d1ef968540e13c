//! SIGINT, SIGTERM and SIGHUP, one mechanism for every command: [`install`] (called by `main`
//! before any command runs) starts a thread that waits for them, and the process ends with
//! 128 + the first signal's number (130, 143, 129) and one line on stderr.
//!
//! * A run that keeps its work ([`keeping`]: a checkpoint, a sweep's or a reproduction's
//!   directory) is asked to stop through the process's [`StopFlag`]: every worker saves what
//!   it has in flight at the end of its current segment and the command returns
//!   [`lorentz_gas::Error::Interrupted`], which `main` reports ([`stopped`]). A run that has not
//!   returned [`GRACE`] after the signal is ended where it is: what it saved before is whole
//!   (journal lines and files are written so that a kill at any moment leaves them readable).
//! * Any other command is ended at once: it keeps nothing that a stop could save.
//! * A second signal ends the process at once, whatever it runs.
//!
//! Ending the process removes the temporary files it has in flight first
//! ([`lorentz_gas::files::in_flight`]), so every output holds its old content, a whole new one
//! or nothing. The signals are received by `signal_hook`'s iterator, whose handler only writes
//! to a pipe (async-signal-safe); everything else happens on the watching thread and the thread
//! that ends the process. The library installs no handler: the Python package turns Ctrl-C into
//! the same [`StopFlag`] with Python's own.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};
use std::sync::{Mutex, OnceLock};
use std::time::Duration;

use lorentz_gas::engine::options::StopFlag;
use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};

/// How long a run that keeps its work has, after the first signal, to save it and return.
/// Its workers look at the stop flag every segment (about 0.1 s of work); past this the
/// process ends anyway, within a second of the signal.
pub const GRACE: Duration = Duration::from_millis(800);

/// The stop flag every run of this process watches, the first signal received, and where the
/// run keeps its work.
struct Watch {
    stop: StopFlag,
    /// The number of the first signal received (0: none).
    signal: AtomicI32,
    /// Where the run keeps its work (a checkpoint file or an output directory): such a run is
    /// given [`GRACE`] to save it.
    kept: Mutex<Option<PathBuf>>,
    /// Whether the line saying why the process ends was written (it is written once).
    said: AtomicBool,
}

fn watch() -> &'static Watch {
    static WATCH: OnceLock<Watch> = OnceLock::new();
    WATCH.get_or_init(|| Watch {
        stop: StopFlag::default(),
        signal: AtomicI32::new(0),
        kept: Mutex::new(None),
        said: AtomicBool::new(false),
    })
}

/// Starts the thread that receives SIGINT, SIGTERM and SIGHUP for the rest of the process's
/// life, and returns once it listens. The handlers replace whatever disposition the process
/// inherited (a shell starts a background job with SIGINT ignored). They are registered by the
/// thread itself: if it cannot start or they cannot be installed, the signals keep the
/// disposition the process was given (by default, ending it).
pub fn install() {
    #[cfg(unix)]
    {
        let (ready, listening) = std::sync::mpsc::channel();
        let watching = move || {
            let registered = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]);
            let _ = ready.send(());
            if let Ok(mut signals) = registered {
                for sig in signals.forever() {
                    received(sig);
                }
            }
        };
        if std::thread::Builder::new()
            .name("signals".into())
            .spawn(watching)
            .is_ok()
        {
            let _ = listening.recv();
        }
    }
}

/// What the watching thread does with signal `sig`. The first one's ending runs on a thread of
/// its own, so that the watching thread stays free for a second signal (which ends the process
/// even if the first one's line could not be written, its standard error blocked).
fn received(sig: i32) {
    let w = watch();
    if w.signal
        .compare_exchange(0, sig, Ordering::SeqCst, Ordering::SeqCst)
        .is_err()
    {
        end_now(kept().is_some());
    }
    w.stop.request();
    // A run that keeps its work saves it and returns, or is ended at the end of its grace.
    let grace = kept().map(|_| GRACE);
    let ending = move || {
        if let Some(g) = grace {
            std::thread::sleep(g);
        }
        end_now(grace.is_some())
    };
    if std::thread::Builder::new()
        .name("ending".into())
        .spawn(ending)
        .is_err()
    {
        end_now(false);
    }
}

/// Ends the process now with the first signal's status, after its line on stderr (unless it
/// was written) and the removal of the temporary files in flight. `late`: a run that keeps its
/// work is ended before it saved (it did not return within [`GRACE`], or a second signal came).
fn end_now(late: bool) -> ! {
    let (status, message) = line(late).unwrap_or((130, "stopped by a signal".into()));
    say(&message);
    lorentz_gas::files::in_flight::abandon();
    #[cfg(unix)]
    // SAFETY: `_exit` takes a status and ends the process without running anything else; no
    // other thread's state is used afterwards.
    unsafe {
        libc::_exit(i32::from(status))
    }
    #[cfg(not(unix))]
    std::process::exit(i32::from(status))
}

/// Writes `message` on stderr, once in the life of the process.
pub fn say(message: &str) {
    if !watch().said.swap(true, Ordering::SeqCst) {
        eprintln!("{message}");
    }
}

/// The stop flag of this process's runs.
pub fn stop_flag() -> StopFlag {
    watch().stop.clone()
}

/// Records where the run keeps its work: on a signal it is asked to save it and given
/// [`GRACE`] to return, and the line on stderr names it.
pub fn keeping(path: &Path) {
    if let Ok(mut k) = watch().kept.lock() {
        *k = Some(path.to_path_buf());
    }
}

/// Where the run keeps its work, if it does.
fn kept() -> Option<PathBuf> {
    watch().kept.lock().ok().and_then(|k| k.clone())
}

/// The exit status and message of a run stopped by a signal: 128 + its number, and where the
/// work is kept (`None` if no signal was received).
pub fn stopped() -> Option<(u8, String)> {
    line(false)
}

/// [`stopped`]; `late`: said of a run that keeps its work and is ended before it saved.
fn line(late: bool) -> Option<(u8, String)> {
    let sig = watch().signal.load(Ordering::SeqCst);
    if sig == 0 {
        return None;
    }
    let name = match sig {
        SIGINT => "SIGINT",
        SIGTERM => "SIGTERM",
        SIGHUP => "SIGHUP",
        _ => "a signal",
    };
    let message = match kept() {
        Some(p) if late => format!(
            "stopped by {name}: the run was ended before it saved what it had in flight (it did \
             not within {:.1} s of the signal, or a second signal came), so {} keeps the work \
             saved before; the same command resumes it to the same bits",
            GRACE.as_secs_f64(),
            p.display()
        ),
        Some(p) => format!(
            "stopped by {name}: the work done so far is saved in {}; the same command resumes it \
             to the same bits",
            p.display()
        ),
        None => format!(
            "stopped by {name}: this run kept no checkpoint, so its work is lost (the commands \
             that take --checkpoint keep theirs)"
        ),
    };
    Some(((128 + sig).min(255) as u8, message))
}

/// The library's default run options, watching this process's stop flag: every command line
/// run starts from these.
pub fn options() -> lorentz_gas::engine::options::RunOptions<'static> {
    lorentz_gas::engine::options::RunOptions {
        stop: Some(stop_flag()),
        ..Default::default()
    }
}
