//! `analyze`: the analysis crate's own binary (the same as `blurlab analyze`).

use clap::Parser;

#[derive(Parser)]
#[command(name = "analyze", version, about)]
struct Cli {
    #[command(flatten)]
    args: analysis::cli::AnalyzeArgs,
}

fn main() {
    if let Err(e) = analysis::cli::run(Cli::parse().args) {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
