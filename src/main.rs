//! `blurlab`: the umbrella command line over the three crates.

use clap::{Parser, Subcommand};

/// Measure how much Monte Carlo noise people can see in ray-traced motion blur.
#[derive(Parser)]
#[command(name = "blurlab", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render scenes, stimulus jobs, point-set plots and convergence reports.
    Render {
        #[command(subcommand)]
        command: renderer::cli::RenderCommand,
    },
    /// Fit psychometric functions, JNDs with bootstrap intervals and t-tests from session logs.
    Analyze(analysis::cli::AnalyzeArgs),
}

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render { command } => renderer::cli::run(command),
        Command::Analyze(args) => analysis::cli::run(args),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
