//! SIGINT, SIGTERM and SIGHUP ask a run to stop the way Python's Ctrl-C does: the run's
//! [`StopFlag`] is raised, every worker saves its trajectories in flight into the checkpoint
//! (if the run keeps one) at the end of its current segment, and the command exits with
//! 128 + the signal's number (130, 143, 129) naming where the work is. A second signal of the
//! same kind ends the process at once, with the same status.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

use lorentz_gas::engine::options::StopFlag;
use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};

/// The stop flag every run of this process watches, and the number of the signal that raised
/// it (0: none).
struct Watch {
    stop: StopFlag,
    signal: Arc<AtomicUsize>,
    /// Where the run keeps its work (a checkpoint file or a sweep's directory).
    kept: Mutex<Option<PathBuf>>,
}

fn watch() -> &'static Watch {
    static WATCH: OnceLock<Watch> = OnceLock::new();
    WATCH.get_or_init(|| {
        let w = Watch {
            stop: StopFlag::default(),
            signal: Arc::new(AtomicUsize::new(0)),
            kept: Mutex::new(None),
        };
        for sig in [SIGINT, SIGTERM, SIGHUP] {
            // A second signal ends the process at once (registered first, so it looks at the
            // flag before this signal raises it); the first raises the flag and is recorded.
            // Registration fails only for signals that cannot be caught, which these are not;
            // without it the default action (ending the process) remains.
            let status = 128 + sig;
            let _ = signal_hook::flag::register_conditional_shutdown(sig, status, w.stop.shared());
            let _ = signal_hook::flag::register(sig, w.stop.shared());
            let _ = signal_hook::flag::register_usize(sig, w.signal.clone(), sig as usize);
        }
        w
    })
}

/// The stop flag of this process's runs, with the signal handlers installed.
pub fn stop_flag() -> StopFlag {
    watch().stop.clone()
}

/// Records where the run keeps its work, for the message when it is stopped.
pub fn keeping(path: &Path) {
    if let Ok(mut k) = watch().kept.lock() {
        *k = Some(path.to_path_buf());
    }
}

/// The exit status and message of a run stopped by a signal: 128 + its number, and where the
/// work is kept (`None` if no signal was received).
pub fn stopped() -> Option<(u8, String)> {
    let sig = watch().signal.load(Ordering::Relaxed);
    if sig == 0 {
        return None;
    }
    let name = match sig as i32 {
        SIGINT => "SIGINT",
        SIGTERM => "SIGTERM",
        SIGHUP => "SIGHUP",
        _ => "a signal",
    };
    let kept = watch().kept.lock().ok().and_then(|k| k.clone());
    let message = match kept {
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
