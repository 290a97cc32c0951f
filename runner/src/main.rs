//! `grass`: the viewer (default) and the headless renderer.

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = runner::cli::Cli::parse();
    // RUST_LOG, where set, decides; else info, or warnings with --quiet.
    let level = if cli.quiet { "warn" } else { "info" };
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or(level)).init();
    match runner::app::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            if let Some(advice) = runner::app::advice(&e) {
                eprintln!("{advice}");
            }
            ExitCode::FAILURE
        }
    }
}
