//! Ctrl-C (SIGINT, and SIGTERM) as a request to stop a run cleanly: the command installs a
//! handler that raises [`FLAG`]; a run loop given the flag (`RunOptions::interrupt`) checks it
//! once per control tick, stops, writes its log up to that tick and its metrics marked
//! interrupted, and returns [`Interrupted`], which the command turns into exit status 130.
//! A second Ctrl-C while the run is writing its files ends the process at once (status 130).

use std::sync::atomic::{AtomicBool, Ordering};

/// Raised by the handler; read by run loops.
pub static FLAG: AtomicBool = AtomicBool::new(false);

/// Exit status of an interrupted command (128 + SIGINT, as shells report it).
pub const EXIT_STATUS: i32 = 130;

/// Installs the handler. Without one (another handler already there), Ctrl-C keeps its
/// default effect of ending the process.
pub fn install() {
    let _ = ctrlc::set_handler(|| {
        if FLAG.swap(true, Ordering::SeqCst) {
            std::process::exit(EXIT_STATUS);
        }
    });
}

/// Whether `flag` (when there is one) has been raised.
pub fn raised(flag: Option<&AtomicBool>) -> bool {
    flag.is_some_and(|f| f.load(Ordering::Relaxed))
}

/// The error of a run stopped by Ctrl-C: it wrote what it had.
#[derive(Debug, thiserror::Error)]
#[error("interrupted at t = {t:.3} s; what the run had written is in {dir}")]
pub struct Interrupted {
    /// Simulated time of the last tick run (s).
    pub t: f64,
    /// The output directory.
    pub dir: String,
}
