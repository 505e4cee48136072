//! `blurlab`: the one command line over the three crates (`src/cli/`).

mod cli;

use clap::Parser;

fn main() {
    if let Err(e) = cli::run(cli::Cli::parse().command) {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
