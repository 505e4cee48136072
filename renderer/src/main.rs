use clap::Parser;

/// Render motion-blurred stimuli for perceptual noise studies.
#[derive(Parser)]
#[command(name = "render", version)]
struct Cli {
    #[command(subcommand)]
    command: renderer::cli::RenderCommand,
}

fn main() {
    let cli = Cli::parse();
    if let Err(e) = renderer::cli::run(cli.command) {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
