//! `grass`: the viewer (default) and the headless renderer.

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    // A settings file's keys go before the command line's flags, which override them.
    let args = match runner::config::with_file(std::env::args_os().collect()) {
        Ok(args) => args,
        Err(e) => {
            eprintln!("error: {e:#}");
            return ExitCode::FAILURE;
        }
    };
    let cli = runner::cli::Cli::parse_from(args);
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
