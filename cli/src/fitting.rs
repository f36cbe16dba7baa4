//! What the commands that fit (`fit`, `identify-paper`) share: the
//! progress line and its flag, and how a fit that did not converge is
//! reported.

use crate::identify::{FitReport, Progress};
use indicatif::{ProgressBar, ProgressStyle};
use std::fmt;
use std::io::IsTerminal;
use std::time::Duration;

/// `--no-progress` of the commands that fit.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::Args)]
pub struct ProgressArgs {
    /// Do not draw the progress line (it is only drawn when stderr is
    /// a terminal anyway).
    #[arg(long)]
    pub no_progress: bool,
}

impl ProgressArgs {
    /// The progress display these flags ask for.
    pub fn display(self) -> Display {
        Display::new(!self.no_progress)
    }
}

/// The progress display: a spinner line on stderr, drawn only when asked
/// for and stderr is a terminal; cleared when dropped.
pub struct Display(ProgressBar);

impl Display {
    pub fn new(wanted: bool) -> Self {
        if !(wanted && std::io::stderr().is_terminal()) {
            return Display(ProgressBar::hidden());
        }
        let bar = ProgressBar::new_spinner();
        if let Ok(style) = ProgressStyle::with_template("{spinner} fitting [{elapsed}] {msg}") {
            bar.set_style(style);
        }
        bar.set_message("starting");
        bar.enable_steady_tick(Duration::from_millis(120));
        Display(bar)
    }

    pub fn update(&self, p: Progress) {
        self.message(format!(
            "iteration {}, {} evaluations, cost {:.6e}",
            p.iteration, p.evaluations, p.cost
        ));
    }

    pub fn message(&self, message: String) {
        self.0.set_message(message);
    }
}

impl Drop for Display {
    fn drop(&mut self) {
        self.0.finish_and_clear();
    }
}

/// Exit code of a fit that ran but did not converge (its last iterate is
/// written like a converged result).
pub const EXIT_NOT_CONVERGED: u8 = 3;

/// After a report that did not converge: what the CLI wrote and how it
/// exits.
pub fn not_converged_note(f: &mut fmt::Formatter<'_>, r: &FitReport) -> fmt::Result {
    if r.status.converged() {
        return Ok(());
    }
    writeln!(
        f,
        "the fit did not converge: the parameters written are its last iterate \
         (exit code {EXIT_NOT_CONVERGED})"
    )
}
