//! The `render` command line. Each subcommand lives in its own file; the binary and the
//! umbrella command both call [`run`].

use anyhow::Result;
use clap::Subcommand;

/// Renderer subcommands.
#[derive(Debug, Subcommand)]
pub enum RenderCommand {}

/// Run one renderer subcommand.
pub fn run(cmd: RenderCommand) -> Result<()> {
    match cmd {}
}
