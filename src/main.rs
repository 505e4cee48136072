//! `blurlab`: the one command line over the three crates (`src/cli/`).

mod cli;

use clap::Parser;

fn main() {
    // Timing the lane widths against each other (bench/lanes.sh): the same bytes either way.
    if std::env::var("BLURLAB_LANES").as_deref() == Ok("sse2") {
        renderer::simd::limit_to_sse2();
    }
    if let Err(e) = cli::run(cli::Cli::parse().command) {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
