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
    use shared::settings::GrassPipeline;
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
        ("full-distance", viewer.full_distance.and_then(number)),
        ("wind", Some(word(s.wind.field.to_possible_value()))),
        ("wind-strength", number(s.wind.strength)),
        ("wind-direction", number(s.wind.direction)),
        ("gravity", number(g.acceleration)),
        ("gravity-centre", centre),
        ("shape", Some(word(s.shape.to_possible_value()))),
        ("tip-start", number(s.tip_start)),
        ("trample-decay", number(s.trample_decay)),
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
        ("look", Some(word(look.style.to_possible_value()))),
        ("no-shadows", switch(!look.shadows)),
        ("shadows", switch(look.shadows)),
        ("msaa", Some(look.msaa.to_string())),
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
mod tests {
    use super::*;
    use clap::Parser as _;

    /// A file in the temporary folder holding `text`, and its path.
    fn file(name: &str, text: &str) -> std::path::PathBuf {
        let path = std::env::temp_dir().join(format!("grass-config-{}-{name}", std::process::id()));
        std::fs::write(&path, text).expect("write the file");
        path
    }

    /// `grass render` with `extra` after `--config path`, through the file.
    fn parse(path: &Path, extra: &[&str]) -> Result<Cli> {
        let mut args: Vec<OsString> = ["grass", "render", "--config"].map(OsString::from).into();
        args.push(path.into());
        args.extend(extra.iter().map(OsString::from));
        Ok(Cli::try_parse_from(with_file(args)?.0)?)
    }

    /// What `grass render` parses to with nothing asked, for comparison (`--config`
    /// itself left out).
    fn plain(cli: Cli) -> String {
        let mut common = cli.common;
        common.config = None;
        format!("{common:?}")
    }

    /// `grass config` read back gives every setting its default, and every key it
    /// writes is one a file may set.
    #[test]
    fn the_defaults_file_reads_back_as_the_defaults() {
        let text = defaults();
        let path = file("defaults.toml", &text);
        let read = parse(&path, &[]).expect("the defaults file reads");
        let expected = Cli::try_parse_from(["grass", "render"]).unwrap();
        assert_eq!(plain(read), plain(expected));
        // Every option, set or commented out.
        for arg in settable() {
            let key = arg.get_long().unwrap();
            assert!(
                text.contains(&format!("\n{key} = ")) || text.contains(&format!("\n# {key} = ")),
                "{key} missing"
            );
        }
    }

    /// A flag on the command line overrides the file's value; the file's values reach
    /// the settings (a number, a word, a list, a switch).
    #[test]
    fn the_command_line_overrides_the_file() {
        let path = file(
            "override.toml",
            "wind-strength = 3\nwind = \"gusts\"\nno-shadows = true\ncollider-path = \"0,0;1,1\"\n",
        );
        let cli = parse(&path, &[]).unwrap();
        assert_eq!(cli.common.wind_strength, 3.0);
        assert_eq!(cli.common.wind, shared::settings::WindField::Gusts);
        assert!(cli.common.no_shadows);
        assert!(cli.common.collider_path.is_some());
        let cli = parse(&path, &["--wind-strength", "5", "--wind", "calm"]).unwrap();
        assert_eq!(cli.common.wind_strength, 5.0);
        assert_eq!(cli.common.wind, shared::settings::WindField::Calm);
    }

    /// The leaves of a value's pretty `Debug` (`{:#?}`), as (path, text):
    /// ("wind.strength", "7.0"), ("gravity.centre.1", "0.0").
    fn leaves(debug: &str) -> Vec<(String, String)> {
        let lines: Vec<&str> = debug.lines().collect();
        let mut path: Vec<String> = Vec::new();
        let mut elements: Vec<usize> = vec![0];
        let mut out = Vec::new();
        // The first and last lines open and close the value itself.
        for line in &lines[1..lines.len() - 1] {
            let text = line.trim().trim_end_matches(',');
            if matches!(text, "}" | ")" | "]") {
                path.pop();
                elements.pop();
                continue;
            }
            let (name, value) = match text.split_once(": ") {
                Some((name, value)) => (name.to_owned(), value),
                None => {
                    let n = elements.last_mut().expect("inside a value");
                    *n += 1;
                    ((*n - 1).to_string(), text)
                }
            };
            if value.ends_with(['{', '(', '[']) {
                path.push(name);
                elements.push(0);
            } else {
                let mut full = path.clone();
                full.push(name);
                out.push((full.join("."), value.to_owned()));
            }
        }
        out
    }

    /// What the scene decides, not the user: the paper's light, the sun, where the
    /// ground and the scene are, how far shadows are cast.
    const FROM_THE_SCENE: [&str; 5] = [
        "light.",
        "look.caster_distance",
        "look.scene.",
        "look.ground_level.",
        "look.sun.",
    ];

    /// A GPU with every optional path, as the device defaults see it.
    fn gpu() -> crate::vulkan::probe::Capabilities {
        crate::vulkan::probe::Capabilities {
            name: "a GPU".into(),
            software: false,
            mesh_shader: Ok(()),
            int64_atomics: Ok(()),
        }
    }

    /// The settings and viewer state `cli` asks for on `scene` and a GPU, as the
    /// program makes them (`app::settings`, `app::device_defaults`).
    fn loaded(cli: &Cli, scene: &crate::scene::Scene) -> (shared::settings::Settings, ViewerState) {
        let mut settings = crate::app::settings(&cli.common, scene);
        crate::app::device_defaults(&mut settings, &cli.common, &gpu()).unwrap();
        let viewer = ViewerState {
            full_distance: cli.common.full_distance,
            ball: !cli.common.no_ball,
        };
        (settings, viewer)
    }

    /// One list of settings: every setting the overlay and the keys can change is set
    /// to a value other than its default, saved as the overlay's "save settings" does,
    /// read back through `--config`, and the whole `Settings` (and the viewer's state)
    /// compared. A setting added to `Settings` fails here until it is changed below
    /// (the leaves of its `Debug` are compared with the defaults'), and then until the
    /// settings file carries it (the read-back differs). Planted faults: the fog
    /// density left out of the file failed (0.0012 read back, not 0.004); `pipeline`
    /// left out failed too (the device's mesh path read back).
    #[test]
    fn every_setting_is_saved_and_read_back() {
        use glam::Vec3;
        use shared::settings::{BladeShape, CullTests, GrassPipeline, Look, View, WindField};
        let scene = crate::scene::Scene::plane(64, 1);
        let plain = Cli::try_parse_from(["grass", "render"]).unwrap();
        let (defaults, default_viewer) = loaded(&plain, &scene);
        // The scene's own options, given on the command line.
        let first = Cli::try_parse_from([
            "grass",
            "render",
            "--seed",
            "77",
            "--collider-path",
            "0,0;2,1",
            "--collider-speed",
            "2.5",
            "--collider-radius",
            "0.75",
            "--field",
            "tiles",
        ])
        .unwrap();
        let mut s = defaults;
        s.gravity.acceleration = 3.0;
        s.gravity.centre = Vec3::new(1.0, -30.0, 2.5);
        s.gravity.centre_blend = 1.0;
        s.wind.field = WindField::Vortex;
        s.wind.strength = 3.5;
        s.wind.direction = -40.25;
        s.trample_decay = 0.5;
        s.stiffness = 2.5;
        s.cull.tests = CullTests::NONE;
        s.cull.orientation_threshold = 0.7;
        s.cull.frustum_tolerance = 1.25;
        s.cull.max_distance = 123.5;
        s.cull.buckets = 5;
        s.lod.on = false;
        s.lod.pixels_per_segment = 17.5;
        s.lod.most = 5.0;
        s.lod.fewest = 2.0;
        s.view = View::Wireframe;
        s.shape = BladeShape::TriangleTip;
        s.tip_start = 0.3;
        s.look.style = Look::Paper;
        s.look.shadows = false;
        s.look.msaa = 2;
        s.look.shadow_size = 1024;
        s.look.exposure = 1.5;
        s.look.fog_density = 0.004;
        s.look.clump_size = 3.25;
        s.look.seed = 77;
        s.pipeline = GrassPipeline::Tess;
        s.compute_raster_below = 12.0;
        s.far_sway = false;
        let viewer = ViewerState {
            full_distance: Some(37.5),
            ball: false,
        };

        let unchanged: Vec<String> = leaves(&format!("{defaults:#?}"))
            .into_iter()
            .zip(leaves(&format!("{s:#?}")))
            .filter(|((path, a), (_, b))| {
                a == b && !FROM_THE_SCENE.iter().any(|p| path.starts_with(p))
            })
            .map(|((path, _), _)| path)
            .collect();
        assert!(
            unchanged.is_empty(),
            "settings this test leaves at their defaults: {unchanged:?}; give each a key in \
             the settings file (config::current, app::settings) and change it here"
        );
        assert_ne!(viewer.full_distance, default_viewer.full_distance);
        assert_ne!(viewer.ball, default_viewer.ball);

        let path = file("saved.toml", &current(&first.common, &s, &viewer));
        let again = parse(&path, &[]).unwrap();
        let (read, read_viewer) = loaded(&again, &scene);
        assert_eq!(read, s);
        assert_eq!(read_viewer, viewer);
        // The scene's own options come back too.
        assert_eq!(plain_scene(again), plain_scene(first));
    }

    /// The options that choose the scene and the ball's path, as text.
    fn plain_scene(cli: Cli) -> String {
        let c = cli.common;
        format!(
            "{} {:?} {:?} {} {:?} {} {} {:?}",
            c.scene,
            c.blades,
            c.density,
            c.seed,
            c.field,
            c.collider_radius,
            c.collider_speed,
            c.collider_path.map(|p| p.points)
        )
    }

    /// Each kind of bad file is refused, naming the file and the key, and the range
    /// where a value is out of it; none panics. Planted fault: the key's check left
    /// out (flags passed through unchecked) failed the range's message (clap's own,
    /// naming the flag, not the file).
    #[test]
    fn bad_files_are_refused_by_file_and_key() {
        for (name, text, expected) in [
            (
                "range.toml",
                "wind-strength = 500\n",
                vec!["`wind-strength`", "0..=100"],
            ),
            (
                "unknown.toml",
                "wind-strenth = 5\n",
                vec!["unknown key `wind-strenth`"],
            ),
            (
                "type.toml",
                "wind = 5\n",
                vec!["`wind`", "invalid value '5'"],
            ),
            (
                "switch.toml",
                "no-shadows = \"yes\"\n",
                vec!["`no-shadows`", "true or false"],
            ),
            (
                "integer.toml",
                "seed = 1.5\n",
                vec!["`seed`", "invalid value '1.5'"],
            ),
            (
                "table.toml",
                "[wind]\nx = 1\n",
                vec!["`wind`", "expected a number"],
            ),
            ("syntax.toml", "wind = [\n", vec!["not TOML", "line 1"]),
        ] {
            let path = file(name, text);
            let error = format!("{:#}", parse(&path, &[]).expect_err(name));
            assert!(error.contains(name), "{name}: {error}");
            for part in expected {
                assert!(error.contains(part), "{name}: {error}");
            }
        }
        let missing = std::env::temp_dir().join("grass-config-no-such-file.toml");
        let error = format!("{:#}", parse(&missing, &[]).expect_err("missing"));
        assert!(error.contains("no-such-file"), "{error}");
        // Through the file guard: a device or a named pipe is refused unread, at once
        // (`/dev/zero` was read without bound, a pipe waited for a writer).
        let pipe = std::env::temp_dir().join(format!("grass-config-{}-pipe", std::process::id()));
        let _ = std::fs::remove_file(&pipe);
        let made = std::process::Command::new("mkfifo").arg(&pipe).status();
        assert!(made.expect("run mkfifo").success());
        for (path, what) in [
            (Path::new("/dev/zero"), "character device"),
            (pipe.as_path(), "named pipe"),
        ] {
            let error = format!("{:#}", parse(path, &[]).expect_err(what));
            assert!(error.contains(what), "{error}");
        }
        let _ = std::fs::remove_file(pipe);
    }
}
