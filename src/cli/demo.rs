//! `blurlab demo`: the flags of `blurlab::demo::DemoOptions` (the pipeline is in the root
//! package's library, `src/demo.rs`) and what the demo prints when it is done.

use crate::cli::progress::{Look, Terminal};
use blurlab::demo::{DemoOptions, DemoProgress};
use clap::Args;
use std::path::PathBuf;

/// Render a small stimulus set, run simulated subjects through it, and write the report.
#[derive(Args, Clone, Debug)]
pub struct DemoArgs {
    /// Project root holding `scenes/` (stimuli go to `<root>/stimuli`, as the demo design
    /// expects) [default: the current folder if it holds the demo job, else the source checkout].
    #[arg(long)]
    pub root: Option<PathBuf>,
    /// Results folder [default: <root>/results/demo].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Number of simulated subjects (the thesis had 12).
    #[arg(long, default_value_t = 12, value_parser = renderer::limits::parse_subjects,
          allow_hyphen_values = true)]
    pub subjects: usize,
    /// Parametric bootstrap resamples per pooled fit.
    #[arg(long, default_value_t = 2000, value_parser = renderer::limits::resamples(1000),
          allow_hyphen_values = true)]
    pub bootstrap: usize,
    /// Hide progress bars.
    #[arg(long)]
    pub no_progress: bool,
    /// Simulated subjects answer from this observer file (e.g. scenes/thesis/observer.json)
    /// instead of the prediction from the stimuli.
    #[arg(long)]
    pub observer: Option<PathBuf>,
}

impl DemoArgs {
    /// The options these flags ask for.
    pub fn options(&self) -> DemoOptions {
        DemoOptions {
            root: self.root.clone(),
            out: self.out.clone(),
            subjects: self.subjects,
            bootstrap: self.bootstrap,
            observer: self.observer.clone(),
        }
    }
}

/// Run the demo with progress bars and print the JNDs and where everything is.
pub fn run(args: &DemoArgs) -> anyhow::Result<()> {
    let show = !args.no_progress;
    let (render, predict) = (
        Terminal::new(Look::Job, show),
        Terminal::new(Look::Steps, show),
    );
    let progress = DemoProgress {
        render: &render,
        predict: &predict,
    };
    let out = blurlab::demo::run(&args.options(), progress)?;
    println!("\n{}\n", out.jnd_summary);
    if let Some(text) = &out.beside_thesis {
        println!("{text}\n");
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_flags_defaults_are_the_options_defaults() {
        let cli = crate::cli::try_parse::<DemoArgs>(&["demo"]).unwrap();
        assert_eq!(cli.options(), DemoOptions::default());
    }
}
