//! Progress on long work (benchmarks, the demo's phases): bars on a terminal, nothing
//! when stderr is a file or a pipe, so logs and CI output stay clean.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::time::Duration;

/// A bar of `len` steps named `prefix`, drawn on stderr when it is a terminal.
pub fn steps(len: u64, prefix: &str) -> ProgressBar {
    let target = if std::io::stderr().is_terminal() {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    };
    let bar = ProgressBar::with_draw_target(Some(len), target);
    if let Ok(style) = ProgressStyle::with_template(
        "{prefix:>8} [{bar:28.cyan/blue}] {pos}/{len} {msg} ({elapsed}, about {eta} left)",
    ) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_prefix(prefix.to_string());
    if !bar.is_hidden() {
        bar.enable_steady_tick(Duration::from_millis(250));
    }
    bar
}

/// A spinner for work of unknown length (a search, a library's benchmark loop).
pub fn spinner(message: &str) -> ProgressBar {
    let bar = steps(0, "");
    if let Ok(style) = ProgressStyle::with_template("{spinner} {msg} ({elapsed})") {
        bar.set_style(style);
    }
    bar.set_message(message.to_string());
    bar
}

/// Advances a bar by one when dropped: one step per finished item of a parallel loop,
/// however the item ends (`?` included).
pub struct Tick<'a>(pub &'a ProgressBar);

impl Drop for Tick<'_> {
    fn drop(&mut self) {
        self.0.inc(1);
    }
}

/// Logs behind `-v`: warnings by default, then info, debug, trace; on stderr.
pub fn init_logging(verbosity: u8) {
    use tracing_subscriber::layer::SubscriberExt;
    use tracing_subscriber::util::SubscriberInitExt;
    let level = match verbosity {
        0 => tracing::Level::WARN,
        1 => tracing::Level::INFO,
        2 => tracing::Level::DEBUG,
        _ => tracing::Level::TRACE,
    };
    // zenoh warns of every connection attempt it retries; tabula says once what failed,
    // so its own logs show only with -vv.
    let network = if verbosity >= 2 {
        level
    } else {
        tracing::Level::ERROR
    };
    let targets = tracing_subscriber::filter::Targets::new()
        .with_default(level)
        .with_target("zenoh", network)
        .with_target("zenoh_transport", network)
        .with_target("zenoh_link_tcp", network)
        // xacro-rs warns of style in published descriptions (`M_PI` redefined); the
        // expansion's errors reach the user as tabula's own.
        .with_target("xacro_rs", network);
    let _ = tracing_subscriber::registry()
        .with(
            tracing_subscriber::fmt::layer()
                .with_writer(std::io::stderr)
                .with_ansi(std::io::stderr().is_terminal())
                .with_target(true),
        )
        .with(targets)
        .try_init();
}
