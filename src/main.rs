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
    /// Run a subject's session (full screen; continues an interrupted session).
    Run(experiment::cli::RunArgs),
    /// Run simulated subjects through a design, writing their session logs.
    Simulate(experiment::cli::SimulateArgs),
    /// Fit psychometric functions, JNDs with bootstrap intervals and t-tests from session logs.
    Analyze(analysis::cli::AnalyzeArgs),
    /// Predict how visible each stimulus's noise is from its display frames (contrast
    /// sensitivity, masking, pooling, the two-pair task): predicted.csv, JNDs, figures.
    Predict(analysis::predict::command::PredictCli),
    /// How many subjects a design needs: simulate it many times with a known observer and
    /// analyse each simulation (interval widths, power, false positives, session length).
    Plan(analysis::plan::command::PlanArgs),
    /// The whole study on built-in defaults: render the demo stimuli, predict their visibility,
    /// simulate 12 subjects answering from the prediction,
    /// analyze, and write results/demo/.
    Demo(blurlab::demo::DemoArgs),
    /// Run subjects' sessions in their browsers: one link per subject, logs like `run`'s.
    #[cfg(feature = "web")]
    Serve(blurlab::serve::ServeArgs),
}

fn demo(args: &blurlab::demo::DemoArgs) -> anyhow::Result<()> {
    let out = blurlab::demo::run(args)?;
    println!("\n{}\n", out.jnd_summary);
    println!(
        "{}",
        analysis::predict::compare::markdown(
            &out.side_by_side,
            &out.observer.display().to_string()
        )
    );
    println!("stimuli:   {}", out.stimuli.display());
    println!("sessions:  {}", out.sessions.display());
    println!("report:    {}", out.report.join("report.md").display());
    println!("speed/err: {}", out.convergence.display());
    println!("summary:   {}", out.summary.display());
    Ok(())
}

fn predict(cli: &analysis::predict::command::PredictCli) -> anyhow::Result<()> {
    use analysis::predict::command::{PredictCommand, ValidateData};
    let args = match (&cli.command, &cli.args) {
        (Some(PredictCommand::Validate { data }), _) => {
            let ValidateData::Modelfest(m) = data;
            println!("{}", analysis::predict::command::validate_modelfest(m)?);
            return Ok(());
        }
        (Some(PredictCommand::Frames(f)), _) => {
            println!("{}", analysis::predict::command::combine_frames(f)?);
            return Ok(());
        }
        (Some(PredictCommand::Explain(e)), _) => {
            println!("{}", analysis::predict::command::explain(e)?);
            return Ok(());
        }
        (None, Some(args)) => args,
        (None, None) => anyhow::bail!("blurlab predict: give a stimulus set or a subcommand"),
    };
    let out = analysis::predict::command::run(args)?;
    if let Some(c) = &out.calibration {
        println!("calibrated sensitivity constant k = {:.4}", c.k);
    }
    println!("{}", analysis::predict::output::jnd_table(&out.prediction));
    println!("prediction: {}", out.files.predicted_csv.display());
    println!("report:     {}", out.files.markdown.display());
    Ok(())
}

fn plan(args: &analysis::plan::command::PlanArgs) -> anyhow::Result<()> {
    let out = analysis::plan::command::run(args)?;
    let md = out.files.first().expect("plan.md is written first");
    println!("{}", std::fs::read_to_string(md)?);
    println!("plan: {}", md.display());
    Ok(())
}

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render { command } => renderer::cli::run(command),
        Command::Run(args) => experiment::cli::run(args),
        Command::Simulate(args) => experiment::cli::simulate(args),
        Command::Analyze(args) => analysis::cli::run(args),
        Command::Predict(args) => predict(&args),
        Command::Plan(args) => plan(&args),
        Command::Demo(args) => demo(&args),
        #[cfg(feature = "web")]
        Command::Serve(args) => blurlab::serve::run(&args),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
