//! `grass`: the viewer (default) and the headless renderer.

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    // A settings file's keys go before the command line's flags, which override them.
    let typed: Vec<_> = std::env::args_os().collect();
    let (args, file_keys) = match runner::config::with_file(typed.clone()) {
        Ok(merged) => merged,
        Err(e) => {
            eprintln!("error: {e:#}");
            return ExitCode::FAILURE;
        }
    };
    let mut cli = runner::cli::Cli::parse_from(args);
    cli.common.given = runner::cli::Given::new(&typed, file_keys);
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
