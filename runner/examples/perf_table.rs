//! The README's performance table, made from the committed bench CSVs
//! (`runner::app::bench::table`): printed, or written between the README's markers.
//!
//! ```text
//! cargo run --release --example perf_table                         # print it
//! cargo run --release --example perf_table -- --write README.md    # put it in
//! ```

use anyhow::Result;
use clap::Parser;
use runner::app::bench::table;
use std::path::PathBuf;

/// The README's performance table from docs/bench's CSVs.
#[derive(Parser, Debug)]
#[command(name = "perf_table")]
struct Args {
    /// The folder of the bench CSVs.
    #[arg(long, default_value = concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/bench"))]
    csv: PathBuf,
    /// A README to write the table into, between its markers (else it is printed).
    #[arg(long)]
    write: Option<PathBuf>,
}

fn main() -> Result<()> {
    let args = Args::parse();
    let made = table::readme_table(&args.csv)?;
    match &args.write {
        Some(readme) => {
            let text = runner::files::read_text(readme, 1 << 20, "README")?;
            std::fs::write(readme, table::with_table(&text, &made)?)?;
            println!("table written into {}", readme.display());
        }
        None => print!("{made}"),
    }
    Ok(())
}
