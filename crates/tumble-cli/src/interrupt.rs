//! Ctrl-C and SIGTERM for long verbs (`tumble run`, `tumble sweep`): the
//! first signal asks the work to stop between two steps and write what it
//! has; a second one ends the process at once (exit status 130).

use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Exit status of a run stopped by a signal (128 + SIGINT, as shells report it).
pub const EXIT_INTERRUPTED: u8 = 130;

/// Installs the handler (once per process; later calls do nothing). If it
/// cannot be installed the signals keep their default action.
pub fn install() {
    static INSTALLED: std::sync::Once = std::sync::Once::new();
    INSTALLED.call_once(|| {
        let _ = ctrlc::set_handler(|| {
            if REQUESTED.swap(true, Ordering::SeqCst) {
                std::process::exit(EXIT_INTERRUPTED as i32);
            }
        });
    });
}

/// Whether a stop was asked for.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}

/// The flag itself, for work that looks at it between steps (a sweep's runs).
pub fn flag() -> &'static AtomicBool {
    &REQUESTED
}
