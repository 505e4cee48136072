//! The command line's binding of `renderer::progress::Progress`, the one terminal bar of the
//! workspace (the libraries report and never draw): an indicatif bar on stderr in the look its
//! command has always had, or nothing at all (`--no-progress`). Each [`Progress::start`] draws
//! a new bar; [`Progress::finish`] clears it.

use indicatif::{ProgressBar, ProgressState, ProgressStyle};
use renderer::progress::Progress;
use std::sync::RwLock;

/// How a command's bar looks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Look {
    /// `render scene`: samples, the current frame, samples per second, time left.
    Sequence,
    /// `render job`: samples of the shard, time left, the current frame.
    Job,
    /// `render converge`: samples.
    Converge,
    /// The experiment's preflight: frames checked (`run`, which needs the `gui` feature).
    #[cfg_attr(not(feature = "gui"), allow(dead_code))]
    Preflight,
    /// `predict`, `plan`: steps, named by the message.
    Steps,
}

impl Look {
    fn style(self) -> ProgressStyle {
        let template = match self {
            Look::Sequence => {
                "{elapsed_precise} [{bar:30}] {percent:>3}% {msg} | {rate} | eta {eta}"
            }
            Look::Job => "{elapsed_precise} [{bar:30}] {percent:>3}% of samples, eta {eta} | {msg}",
            Look::Converge => "{bar:40} {percent}% samples, {elapsed} (eta {eta})",
            Look::Preflight => "preflight {bar:40} {pos}/{len} frames checked ({eta} left)",
            Look::Steps => "{msg} [{bar:40}] {pos}/{len} ({eta} left)",
        };
        let style = ProgressStyle::with_template(template).expect("valid template");
        match self {
            Look::Sequence => style
                .with_key(
                    "rate",
                    |state: &ProgressState, w: &mut dyn std::fmt::Write| {
                        let _ = write!(w, "{:.2} M samples/s", state.per_sec() / 1e6);
                    },
                )
                .progress_chars("=> "),
            Look::Job | Look::Steps => style.progress_chars("=> "),
            Look::Converge | Look::Preflight => style,
        }
    }
}

/// A bar on stderr, or nothing when hidden.
#[derive(Debug)]
pub struct Terminal {
    look: Look,
    show: bool,
    /// The bar of the work under way (none before the first start and after finishing).
    bar: RwLock<Option<ProgressBar>>,
}

impl Terminal {
    /// Bars in `look`, drawn when `show` (false: `--no-progress`).
    pub fn new(look: Look, show: bool) -> Self {
        Self {
            look,
            show,
            bar: RwLock::new(None),
        }
    }

    fn with_bar(&self, f: impl FnOnce(&ProgressBar)) {
        if let Some(bar) = self.bar.read().expect("progress bar lock").as_ref() {
            f(bar);
        }
    }
}

impl Progress for Terminal {
    fn start(&self, total: u64) {
        if !self.show {
            return;
        }
        let bar = ProgressBar::new(total);
        bar.set_style(self.look.style());
        *self.bar.write().expect("progress bar lock") = Some(bar);
    }

    fn message(&self, text: &str) {
        self.with_bar(|bar| bar.set_message(text.to_string()));
    }

    fn advance(&self, n: u64) {
        self.with_bar(|bar| bar.inc(n));
    }

    fn finish(&self) {
        if let Some(bar) = self.bar.write().expect("progress bar lock").take() {
            bar.finish_and_clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_look_has_a_valid_style() {
        for look in [
            Look::Sequence,
            Look::Job,
            Look::Converge,
            Look::Preflight,
            Look::Steps,
        ] {
            let _ = look.style();
        }
    }

    #[test]
    fn a_hidden_terminal_never_holds_a_bar() {
        let t = Terminal::new(Look::Job, false);
        t.start(10);
        t.message("frame 1");
        t.advance(3);
        assert!(t.bar.read().unwrap().is_none());
        t.finish();
    }

    #[test]
    fn finishing_drops_the_bar() {
        let t = Terminal::new(Look::Steps, true);
        t.start(4);
        t.advance(4);
        assert_eq!(
            t.bar.read().unwrap().as_ref().map(|b| b.position()),
            Some(4)
        );
        t.finish();
        assert!(t.bar.read().unwrap().is_none());
    }
}
