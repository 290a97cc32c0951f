//! `grass`: the viewer (default) and the headless renderer.

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info")).init();
    match runner::app::run(runner::cli::Cli::parse()) {
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
