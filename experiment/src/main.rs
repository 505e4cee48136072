//! `experiment`: the crate's own command line (`run`, `simulate`); `blurlab run` and
//! `blurlab simulate` are the same commands in the umbrella binary.

use clap::{Parser, Subcommand};

/// Two-pair constant-stimuli sessions: run a subject, or simulate subjects.
#[derive(Parser)]
#[command(name = "experiment", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    Run(experiment::cli::RunArgs),
    Simulate(experiment::cli::SimulateArgs),
}

fn main() {
    let result = match Cli::parse().command {
        Command::Run(a) => experiment::cli::run(a),
        Command::Simulate(a) => experiment::cli::simulate(a),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
