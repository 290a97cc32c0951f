//! Settings in a file (`--config FILE`, `grass config`): every option shared by the
//! commands, as TOML keys named like their flags (`wind-strength = 7.0`). A file's
//! keys become flags placed before the command line's, so the command line overrides
//! the file; each key is checked by the command line's own parser, so a wrong type or
//! a value out of range is refused with the same rule and range as the flag, named by
//! file and key.

use crate::cli::Cli;
use anyhow::{Result, bail};
use clap::{ArgAction, CommandFactory as _};
use std::ffi::OsString;
use std::path::Path;

/// The options a file may set: the ones every command shares (clap's global
/// arguments), less `--config` itself.
pub fn settable() -> Vec<clap::Arg> {
    Cli::command()
        .get_arguments()
        .filter(|a| a.is_global_set() && a.get_long().is_some_and(|l| l != "config"))
        .cloned()
        .collect()
}

/// `args` (the program's, its name first) with the settings of the file `--config`
/// names placed before the command line's own options (after the command's name,
/// where the options go), and the keys the file sets; `args` unchanged without
/// `--config`.
pub fn with_file(args: Vec<OsString>) -> Result<(Vec<OsString>, Vec<String>)> {
    let Some(path) = config_path(&args) else {
        return Ok((args, Vec::new()));
    };
    let from_file = read(Path::new(&path))?;
    let keys = from_file
        .iter()
        .map(|flag| {
            let flag = flag.trim_start_matches("--");
            flag.split_once('=').map_or(flag, |(key, _)| key).to_owned()
        })
        .collect();
    let commands: Vec<String> = Cli::command()
        .get_subcommands()
        .map(|c| c.get_name().to_owned())
        .collect();
    let at = args
        .iter()
        .skip(1)
        .position(|w| commands.iter().any(|c| w.to_str() == Some(c.as_str())))
        .map_or(1, |i| i + 2);
    let mut merged = args[..at.min(args.len())].to_vec();
    merged.extend(from_file.into_iter().map(OsString::from));
    merged.extend(args.into_iter().skip(at));
    Ok((merged, keys))
}

/// The value of `--config FILE` or `--config=FILE` in `args`, if any.
fn config_path(args: &[OsString]) -> Option<OsString> {
    let mut words = args.iter().skip(1);
    while let Some(word) = words.next() {
        let word = word.to_string_lossy();
        if word == "--" {
            return None;
        }
        if word == "--config" {
            return words.next().cloned();
        }
        if let Some(path) = word.strip_prefix("--config=") {
            return Some(path.into());
        }
    }
    None
}

/// Most bytes a settings file may have: every key with a long value is a few KiB.
pub const MAX_FILE_BYTES: u64 = 1 << 20;

/// The flags the file at `path` sets, each checked as the command line checks it.
pub fn read(path: &Path) -> Result<Vec<String>> {
    let shown = path.display();
    let text = crate::files::read_text(path, MAX_FILE_BYTES, "config")?;
    let table: toml::Table =
        toml::from_str(&text).map_err(|e| anyhow::anyhow!("config {shown}: not TOML: {e}"))?;
    let settable = settable();
    let mut flags = Vec::new();
    for (key, value) in &table {
        let Some(arg) = settable.iter().find(|a| a.get_long() == Some(key.as_str())) else {
            bail!("config {shown}: unknown key `{key}` (`grass config` lists them all)");
        };
        let switch = matches!(arg.get_action(), ArgAction::SetTrue);
        let flag = match (value, switch) {
            (toml::Value::Boolean(true), true) => Some(format!("--{key}")),
            (toml::Value::Boolean(false), true) => None,
            (_, true) => bail!("config {shown}: key `{key}`: expected true or false"),
            (toml::Value::String(s), false) => Some(format!("--{key}={s}")),
            (toml::Value::Integer(n), false) => Some(format!("--{key}={n}")),
            (toml::Value::Float(x), false) => Some(format!("--{key}={x}")),
            (toml::Value::Array(items), false) => {
                let words: Option<Vec<String>> = items.iter().map(scalar).collect();
                let Some(words) = words else {
                    bail!("config {shown}: key `{key}`: expected a list of numbers or words");
                };
                Some(format!("--{key}={}", words.join(",")))
            }
            _ => bail!("config {shown}: key `{key}`: expected a number, a word or a list"),
        };
        if let Some(flag) = flag {
            // The command line's own parser, on this flag alone.
            if let Err(e) = Cli::command().try_get_matches_from(["grass", flag.as_str()]) {
                bail!(
                    "config {shown}: key `{key}`: {}",
                    first_line(&e.to_string())
                );
            }
            flags.push(flag);
        }
    }
    Ok(flags)
}

/// A TOML scalar as a command-line word.
fn scalar(value: &toml::Value) -> Option<String> {
    match value {
        toml::Value::String(s) => Some(s.clone()),
        toml::Value::Integer(n) => Some(n.to_string()),
        toml::Value::Float(x) => Some(x.to_string()),
        _ => None,
    }
}

/// The first line of clap's message, without its "error: ".
fn first_line(message: &str) -> String {
    let line = message.lines().next().unwrap_or_default();
    line.strip_prefix("error: ").unwrap_or(line).to_owned()
}

/// Every settable option at its default, as a commented TOML file: its help as the
/// comment, its choices where it has some; an option without a default commented
/// out.
pub fn defaults() -> String {
    let mut out = String::from(
        "# grass settings: `grass --config FILE`; flags on the command line override them.\n\
         # Every option shared by the commands, at its default (`grass config`).\n",
    );
    for arg in settable() {
        let Some(key) = arg.get_long() else { continue };
        out.push('\n');
        if let Some(help) = arg.get_long_help().or(arg.get_help()) {
            for line in help.to_string().lines() {
                out.push_str(&format!("# {line}\n").replace("# \n", "#\n"));
            }
        }
        let choices: Vec<String> = arg
            .get_possible_values()
            .iter()
            .filter(|v| !v.is_hide_set())
            .map(|v| v.get_name().to_owned())
            .collect();
        if !choices.is_empty() && !matches!(arg.get_action(), ArgAction::SetTrue) {
            out.push_str(&format!("# one of: {}\n", choices.join(", ")));
        }
        let defaults: Vec<String> = arg
            .get_default_values()
            .iter()
            .map(|v| v.to_string_lossy().into_owned())
            .collect();
        match (arg.get_action(), defaults.is_empty()) {
            (ArgAction::SetTrue, _) => out.push_str(&format!("{key} = false\n")),
            (_, true) => out.push_str(&format!("# {key} = ...\n")),
            (_, false) => out.push_str(&format!("{key} = {}\n", literal(&defaults.join(",")))),
        }
    }
    out
}

/// `word` as a TOML value: a number where it reads as one, else a string.
fn literal(word: &str) -> String {
    if word.parse::<f64>().is_ok_and(f64::is_finite) && !word.starts_with('+') {
        word.to_owned()
    } else {
        format!("{word:?}")
    }
}

/// What the viewer holds beside [`shared::settings::Settings`] that a settings file
/// keeps: the overlay's and the keys' other controls. (The camera and flying are where
/// you look from, not settings.)
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ViewerState {
    /// A tiled field's distance every blade is kept within (`--full-distance`);
    /// `None` on a stored field.
    pub full_distance: Option<f32>,
    /// The ball is on (B; `--no-ball` when off).
    pub ball: bool,
    /// Walkers wandering the ground (`--walkers`).
    pub walkers: u32,
    /// Mowers cutting the grass (`--mowers`).
    pub mowers: u32,
    /// The ball cuts (C; `--ball-cuts`).
    pub ball_cuts: bool,
    /// The species the field grows (the overlay's control; `--species`).
    pub species: shared::species::Mix,
}

/// The running `settings` and `viewer` state (as the overlay and the keys leave them)
/// and the command line's other options (`common`: scene, field, maps, ball path) as a
/// settings file that `--config` reads back to the same settings: what the overlay's
/// "save settings" writes. The device's own choices (pipeline, samples, shadows and
/// their map, compute rasterizer) are written as they are now, so the file makes them explicit.
pub fn current(
    common: &crate::cli::Common,
    s: &shared::settings::Settings,
    viewer: &ViewerState,
) -> String {
    use crate::cli::PipelineChoice;
    use clap::ValueEnum;
    use shared::settings::{Antialiasing, GrassPipeline};
    let word = |v: Option<clap::builder::PossibleValue>| {
        format!(
            "{:?}",
            v.map(|v| v.get_name().to_owned()).unwrap_or_default()
        )
    };
    let path = |p: &Option<std::path::PathBuf>| {
        p.as_ref().map(|p| format!("{:?}", p.display().to_string()))
    };
    let number = |x: f32| Some(x.to_string());
    let switch = |on: bool| Some(on.to_string());
    let pipeline = match s.pipeline {
        GrassPipeline::Tess => PipelineChoice::Tess,
        GrassPipeline::Mesh => PipelineChoice::Mesh,
    };
    let g = &s.gravity;
    let centre =
        (g.centre_blend > 0.0).then(|| format!("\"{},{},{}\"", g.centre.x, g.centre.y, g.centre.z));
    let (cull, lod, look) = (&s.cull, &s.lod, &s.look);
    let tests = cull.tests;
    let lines: Vec<(&str, Option<String>)> = vec![
        ("scene", Some(format!("{:?}", common.scene))),
        ("blades", common.blades.map(|n| n.to_string())),
        ("density", common.density.map(|d| d.to_string())),
        ("seed", Some(common.seed.to_string())),
        ("field", common.field.map(|f| word(f.to_possible_value()))),
        ("density-map", path(&common.density_map)),
        ("height-map", path(&common.height_map)),
        ("colour-map", path(&common.colour_map)),
        ("type-map", path(&common.type_map)),
        ("species", Some(format!("{:?}", viewer.species.to_string()))),
        ("full-distance", viewer.full_distance.and_then(number)),
        ("wind", Some(word(s.wind.field.to_possible_value()))),
        ("wind-strength", number(s.wind.strength)),
        ("wind-direction", number(s.wind.direction)),
        ("gust-speed", number(s.wind.gust_speed)),
        ("gravity", number(g.acceleration)),
        ("gravity-centre", centre),
        ("shape", Some(word(s.shape.to_possible_value()))),
        ("tip-start", number(s.tip_start)),
        ("trample-decay", number(s.trample_decay)),
        ("regrow", number(s.regrow)),
        ("stiffness", number(s.stiffness)),
        ("collider-radius", number(common.collider_radius)),
        ("collider-speed", number(common.collider_speed)),
        (
            "collider-path",
            common
                .collider_path
                .as_ref()
                .map(|p| format!("{:?}", p.to_string())),
        ),
        ("no-ball", switch(!viewer.ball)),
        ("walkers", Some(viewer.walkers.to_string())),
        ("mowers", Some(viewer.mowers.to_string())),
        ("ball-cuts", switch(viewer.ball_cuts)),
        ("look", Some(word(look.style.to_possible_value()))),
        ("no-shadows", switch(!look.shadows)),
        ("shadows", switch(look.shadows)),
        ("aa", Some(word(look.aa.to_possible_value()))),
        // The samples act only with multisampling.
        (
            "msaa",
            (look.aa == Antialiasing::Msaa).then(|| look.msaa.to_string()),
        ),
        ("render-scale", number(look.render_scale)),
        ("shadow-size", Some(look.shadow_size.to_string())),
        ("exposure", number(look.exposure)),
        ("fog-density", number(look.fog_density)),
        ("clump-size", number(look.clump_size)),
        ("far-at-rest", switch(!s.far_sway)),
        ("pipeline", Some(word(pipeline.to_possible_value()))),
        ("view", Some(word(s.view.to_possible_value()))),
        ("no-lod", switch(!lod.on)),
        ("lod-most", number(lod.most)),
        ("lod-fewest", number(lod.fewest)),
        ("lod-pixels", number(lod.pixels_per_segment)),
        ("compute-raster-below", number(s.compute_raster_below)),
        ("no-cull-orientation", switch(!tests.orientation)),
        ("no-cull-frustum", switch(!tests.frustum)),
        ("no-cull-distance", switch(!tests.distance)),
        ("no-cull-occlusion", switch(!tests.occlusion)),
        ("orientation-threshold", number(cull.orientation_threshold)),
        ("edge-on-pixels", number(cull.edge_on_pixels)),
        ("frustum-tolerance", number(cull.frustum_tolerance)),
        ("max-distance", number(cull.max_distance)),
        ("buckets", Some(cull.buckets.to_string())),
    ];
    let mut out = String::from(
        "# grass settings saved from the viewer: `grass --config FILE` (after the command's\n\
         # name: `grass render --config FILE`); flags on the command line override them.\n",
    );
    for (key, value) in lines {
        if let Some(value) = value {
            out.push_str(&format!("{key} = {value}\n"));
        }
    }
    out
}

#[cfg(test)]
mod tests;
