//! The README's performance table is the one the committed bench CSVs make
//! (`runner::app::bench::table`; `cargo run --release --example perf_table -- --write
//! README.md` makes it again).

use runner::app::bench::table;
use std::path::Path;

fn repository() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

#[test]
fn the_readme_s_performance_table_is_the_csvs() {
    let readme = std::fs::read_to_string(repository().join("README.md")).expect("README");
    let shown = table::table_in(&readme).expect("the README's table markers");
    let made = table::readme_table(&repository().join("docs/bench")).expect("the CSVs");
    assert_eq!(
        shown, made,
        "the README's table differs from the CSVs': run `cargo run --release --example \
         perf_table -- --write README.md`"
    );
}

/// A changed figure in a CSV changes the table.
#[test]
fn a_changed_figure_changes_the_table() {
    let dir = std::env::temp_dir().join(format!("grass-perf-table-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    for file in table::SOURCES {
        std::fs::copy(repository().join("docs/bench").join(file), dir.join(file)).expect("copy");
    }
    let before = table::readme_table(&dir).expect("table");
    // The first row's GPU time 10 % higher.
    let first = dir.join(table::SOURCES[0]);
    let mut reader = csv::Reader::from_path(&first).expect("csv");
    let headers = reader.headers().expect("headers").clone();
    let gpu = headers
        .iter()
        .position(|h| h == "gpu_ms_median")
        .expect("column");
    let mut rows: Vec<csv::StringRecord> = reader.records().map(|r| r.expect("row")).collect();
    let value: f64 = rows[0][gpu].parse().expect("number");
    let raised = format!("{:.4}", value * 1.1);
    rows[0] = rows[0]
        .iter()
        .enumerate()
        .map(|(i, v)| if i == gpu { raised.as_str() } else { v })
        .collect();
    let mut writer = csv::Writer::from_path(&first).expect("csv");
    writer.write_record(&headers).expect("write");
    for row in &rows {
        writer.write_record(row).expect("write");
    }
    writer.flush().expect("flush");
    let after = table::readme_table(&dir).expect("table");
    std::fs::remove_dir_all(&dir).ok();
    assert_ne!(
        before, after,
        "a figure 10 % higher left the table as it was"
    );
}
