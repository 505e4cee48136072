//! The command line of `blurlab`, the one binary over the three library crates (ripgrep's
//! shape: the libraries know no command line). Every command's clap `Args` and its `run` live
//! here, one file per command or command group; each maps its flags onto a library's plain
//! options, calls the library, and prints. [`progress`] is the terminal bar the libraries
//! report to.

pub mod analyze;
pub mod demo;
pub mod named;
pub mod plan;
pub mod predict;
pub mod progress;
pub mod render;
pub mod run;
#[cfg(feature = "web")]
pub mod serve;
pub mod simulate;

use clap::{Parser, Subcommand};

/// Measure how much Monte Carlo noise people can see in ray-traced motion blur.
#[derive(Parser)]
#[command(name = "blurlab", version, about)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand)]
pub enum Command {
    /// Render scenes, stimulus jobs, point-set plots and convergence reports.
    Render {
        #[command(subcommand)]
        command: render::RenderCommand,
    },
    /// Run a subject's session (full screen; continues an interrupted session).
    Run(run::RunArgs),
    /// Run simulated subjects through a design, writing their session logs.
    Simulate(simulate::SimulateArgs),
    /// Fit psychometric functions, JNDs with bootstrap intervals and t-tests from session logs.
    Analyze(analyze::AnalyzeArgs),
    /// Predict how visible each stimulus's noise is from its display frames (contrast
    /// sensitivity, masking, pooling, the two-pair task): predicted.csv, JNDs, figures.
    Predict(predict::PredictCli),
    /// How many subjects a design needs: simulate it many times with a known observer and
    /// analyse each simulation (interval widths, power, false positives, session length).
    Plan(plan::PlanArgs),
    /// The whole study on built-in defaults: render the demo stimuli, predict their visibility,
    /// simulate 12 subjects answering from the prediction,
    /// analyze, and write results/demo/.
    Demo(demo::DemoArgs),
    /// Run subjects' sessions in their browsers: one link per subject, logs like `run`'s.
    #[cfg(feature = "web")]
    Serve(serve::ServeArgs),
}

/// Run one command.
pub fn run(command: Command) -> anyhow::Result<()> {
    match command {
        Command::Render { command } => render::run(command),
        Command::Run(args) => run::run(args),
        Command::Simulate(args) => simulate::simulate(args),
        Command::Analyze(args) => analyze::run(args),
        Command::Predict(args) => predict::run(&args),
        Command::Plan(args) => plan::run(&args),
        Command::Demo(args) => demo::run(&args),
        #[cfg(feature = "web")]
        Command::Serve(args) => serve::run(&args),
    }
}

/// One command's flags parsed from `argv` (its first element the command's name): the harness
/// of the command-line tests, in place of a test `Parser` per command.
#[cfg(test)]
pub(crate) fn try_parse<A: clap::Args + clap::FromArgMatches>(
    argv: &[&str],
) -> Result<A, clap::Error> {
    let mut matches = A::augment_args(clap::Command::new("blurlab")).try_get_matches_from(argv)?;
    A::from_arg_matches_mut(&mut matches)
}
