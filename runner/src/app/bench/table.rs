//! The README's performance table, made from the committed bench CSVs: one row per
//! device, camera, blade count and look, the frame and its passes in milliseconds and
//! the grass pass in nanoseconds per drawn blade.
//!
//! `cargo run --release --example perf_table -- --write README.md` puts it between the
//! README's markers; a test fails when the README's table and the CSVs disagree.

use anyhow::{Context as _, Result, bail};
use std::path::Path;

/// The CSVs the table is made from, in `docs/bench/`, in the table's order; the
/// README names the command that measured each.
pub const SOURCES: [&str; 3] = [
    "h100-bands-edge.csv",
    "h100-bands-overview.csv",
    "lavapipe-edge.csv",
];

/// The markers around the table in the README.
pub const MARKERS: (&str, &str) = ("<!-- perf-table:begin -->", "<!-- perf-table:end -->");

/// The table's columns.
const HEADER: &str = "| device | camera | blades | look | frame | grass pass | shadow map \
                      | resolve + shading | ns per blade drawn by the hardware |\n\
                      |---|---|---|---|---|---|---|---|---|\n";

/// The table, as markdown, from the CSVs in `dir`: each one's culls + LOD rows. A GPU's
/// frame is its GPU time; a software device's is its CPU frame (its timestamps time
/// its deferred rasteriser), and its passes are not timed.
pub fn readme_table(dir: &Path) -> Result<String> {
    let mut out = String::from(HEADER);
    for file in SOURCES {
        let path = dir.join(file);
        let mut reader =
            csv::Reader::from_path(&path).with_context(|| format!("read {}", path.display()))?;
        let headers = reader.headers()?.clone();
        let mut rows = 0;
        for record in reader.records() {
            let r = record?;
            let get = |name: &str| -> Result<&str> {
                let i = headers
                    .iter()
                    .position(|h| h == name)
                    .with_context(|| format!("{}: no column {name}", path.display()))?;
                Ok(r.get(i).unwrap_or(""))
            };
            if get("config")? != "CullsLod" {
                continue;
            }
            rows += 1;
            let software = get("device")?.starts_with("llvmpipe");
            let device = format!(
                "{}, {}x{}",
                short_device(get("device")?),
                get("width")?,
                get("height")?
            );
            let natural = get("look")? == "Natural";
            let samples = match get("msaa")? {
                "" => "1",
                n => n,
            };
            // The anti-aliasing (CSVs before the column: MSAA at their samples).
            let aa = match (get("aa").unwrap_or(""), samples) {
                ("taa", _) => "TAA".to_owned(),
                ("none", _) | ("", "1") => "1x".to_owned(),
                (_, n) => format!("{n}x MSAA"),
            };
            let shadow: f64 = get("shadow_ms_median")?.parse().unwrap_or(0.0);
            // A paper frame's shadow-map time is the timestamps' noise, not a map.
            let shadowed = natural && shadow > 0.01;
            let look = match (natural, shadowed) {
                (false, _) => format!("paper ({aa})"),
                (true, true) => format!("natural ({aa}, shadows)"),
                (true, false) => format!("natural ({aa})"),
            };
            let ms = |name: &str| -> Result<String> {
                Ok(match get(name)?.parse::<f64>() {
                    Ok(v) if !software => format!("{v:.2} ms"),
                    _ => "—".into(),
                })
            };
            // What follows the draw: the far blades' and the samples' resolve, and the
            // natural look's shading (which takes the far blades at one sample).
            let after_draw = || -> Result<String> {
                let resolve = get("resolve_ms_median")?.parse::<f64>();
                let shade = get("shade_ms_median").unwrap_or("").parse::<f64>();
                Ok(match resolve {
                    Ok(r) if !software => format!("{:.2} ms", r + shade.unwrap_or(0.0)),
                    _ => "—".into(),
                })
            };
            let frame: f64 = get(if software {
                "cpu_ms_median"
            } else {
                "gpu_ms_median"
            })?
            .parse()
            .with_context(|| format!("{}: frame time", path.display()))?;
            let ns = match get("grass_ns_per_drawn_blade").unwrap_or("").parse::<f64>() {
                Ok(v) if !software => format!("{v:.1}"),
                _ => "—".into(),
            };
            let blades: u64 = get("blades")?.parse()?;
            out += &format!(
                "| {device} | {} | {} | {look} | {frame:.2} ms | {} | {} | {} | {ns} |\n",
                get("camera")?.to_lowercase(),
                thousands(blades),
                ms("grass_ms_median")?,
                if shadowed {
                    ms("shadow_ms_median")?
                } else {
                    "—".into()
                },
                after_draw()?,
            );
        }
        if rows == 0 {
            bail!("{}: no culls + LOD rows", path.display());
        }
    }
    Ok(out)
}

/// The device's name without the driver's details.
fn short_device(name: &str) -> String {
    match name.split_once(" (") {
        Some((head, _)) if head.starts_with("llvmpipe") => "lavapipe".into(),
        _ => name.trim_end_matches(" 80GB HBM3").to_owned(),
    }
}

/// `n` with thousands separated by commas.
fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// `readme` with the table between its markers replaced by `table`.
pub fn with_table(readme: &str, table: &str) -> Result<String> {
    let (Some(begin), Some(end)) = (readme.find(MARKERS.0), readme.find(MARKERS.1)) else {
        bail!("the README has no {} … {} markers", MARKERS.0, MARKERS.1);
    };
    let head = &readme[..begin + MARKERS.0.len()];
    Ok(format!("{head}\n{table}{}", &readme[end..]))
}

/// The table between the markers of `readme`.
pub fn table_in(readme: &str) -> Option<&str> {
    let begin = readme.find(MARKERS.0)? + MARKERS.0.len();
    let end = readme.find(MARKERS.1)?;
    readme.get(begin..end).map(|t| t.trim_start_matches('\n'))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_grouped_and_devices_shortened() {
        assert_eq!(thousands(4_194_304), "4,194,304");
        assert_eq!(thousands(404), "404");
        assert_eq!(short_device("NVIDIA H100 80GB HBM3"), "NVIDIA H100");
        assert_eq!(short_device("llvmpipe (LLVM 15.0.6, 256 bits)"), "lavapipe");
    }

    #[test]
    fn the_table_goes_between_the_markers() {
        let readme = format!("a\n{}\nold\n{}\nb\n", MARKERS.0, MARKERS.1);
        let new = with_table(&readme, "| t |\n").unwrap();
        assert_eq!(table_in(&new), Some("| t |\n"));
        assert!(new.starts_with("a\n") && new.ends_with("b\n"));
    }
}
