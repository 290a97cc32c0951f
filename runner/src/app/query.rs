//! `grass query`: the questions a game asks of the grass (`shared::query`), asked of
//! the last of some headless frames and answered on the GPU; with `--check`, answered
//! again on the host from the blades read back.

use super::render::Headless;
use crate::answers::Answers;
use crate::cli::{Common, QueryArgs};
use anyhow::{Context as _, Result, bail};
use glam::{Vec2, Vec3};
use shared::query::{Around, MAX_QUESTIONS, Question, Sight, Tally};

/// What `grass query` found.
pub struct QueryReport {
    /// The GPU's answers of the last frame, and its contacts.
    pub answers: Answers,
    /// The host's answers from the blades read back (`--check`).
    pub host: Option<Vec<Tally>>,
    /// The colliders of the last frame (the ball, walkers and mowers).
    pub colliders: u32,
    /// GPU time of simulate + cull (ms) in the last frame that asked nothing, and in
    /// the last, which asked (with the query pass), where the device has timestamps.
    pub simulate_cull: Option<(f64, f64)>,
    /// Validation errors reported (0 without validation).
    pub validation_errors: u32,
}

/// Asks as `args` says, prints the answers and, with `--check`, fails where the
/// host's differ.
pub fn run(common: &Common, args: &QueryArgs) -> Result<QueryReport> {
    let report = query(common, args)?;
    println!(
        "{:<44} {:>7} {:>9} {:>7} {:>6} {:>11}",
        "question", "blades", "per m²", "height", "bend", "concealment"
    );
    for (q, t) in &report.answers.answers {
        println!("{}", describe(q, t));
    }
    let touching: Vec<String> = report
        .answers
        .contacts
        .iter()
        .map(|i| i.to_string())
        .collect();
    println!(
        "colliders touching grass: {} of {}{}",
        touching.len(),
        report.colliders,
        if touching.is_empty() {
            String::new()
        } else {
            format!(" ({})", touching.join(", "))
        }
    );
    if let Some((without, with)) = report.simulate_cull {
        println!(
            "simulate + cull: {without:.3} ms without the questions, {with:.3} ms with them \
             (GPU timestamps of the last frames)"
        );
    }
    if report.validation_errors > 0 {
        bail!(
            "{} validation errors (see the log above)",
            report.validation_errors
        );
    }
    if let Some(host) = &report.host {
        let gpu = report.answers.answers.iter().map(|(_, t)| t);
        let differ: Vec<String> = gpu
            .zip(host)
            .enumerate()
            .filter(|(_, (g, h))| !agree(g, h))
            .map(|(i, (g, h))| format!("question {}: GPU {g:?}, host {h:?}", i + 1))
            .collect();
        if !differ.is_empty() {
            bail!("the host answers differently: {}", differ.join("; "));
        }
        println!(
            "host check: the host's answers agree (the blades read back after the last frame)"
        );
    }
    Ok(report)
}

/// Runs `args.frames` frames, the last asking `args`' questions, and reads the
/// answers back.
pub fn query(common: &Common, args: &QueryArgs) -> Result<QueryReport> {
    let asked = args.at.len() + args.sight.len();
    if asked == 0 {
        bail!("nothing asked: add --at x,z or --sight x,z:x,z");
    }
    if asked > MAX_QUESTIONS {
        bail!("{asked} questions: at most {MAX_QUESTIONS} a frame");
    }
    let given = &common.given;
    if args.at.is_empty() {
        given.refuse(&["radius"], "it sizes each --at, and none is asked")?;
    }
    if args.sight.is_empty() {
        given.refuse(
            &["eye-height", "sight-radius"],
            "it shapes each --sight, and none is asked",
        )?;
    }
    if !super::tiled(common, &common.scene_kind()) {
        given.refuse(
            &["zoom", "yaw", "pitch", "orbit"],
            "a stored field's blades are all simulated wherever the camera is: it acts \
             on a tiled field (--field tiles), whose simulated blades are around the camera",
        )?;
    }
    // The target's size matters to no answer.
    let mut run = Headless::open(common, (64, 64), &args.camera, &args.events)?;
    let questions = questions(&run.scene, args)?;
    let progress_every = (args.frames / 10).max(1);
    let mut before = None;
    for frame in 0..args.frames {
        // The last two frames ask (the last answers): a pipeline's first dispatch may
        // cost a driver more than the pass (lavapipe compiles it then).
        if frame + 2 == args.frames.max(2) {
            // The frame before, done: its time without the query pass.
            run.driver.finish()?;
            before = run.driver.readback.times.map(|t| t.simulate_cull);
            run.questions = questions.clone();
        }
        run.frame(1.0 / 60.0, false)?;
        if args.frames >= 100 && (frame + 1) % progress_every == 0 {
            log::info!("frame {}/{}", frame + 1, args.frames);
        }
    }
    run.driver.finish()?;
    let after = run.driver.readback.times.map(|t| t.simulate_cull);
    let renderer = &run.driver.renderer;
    let host = if args.check {
        Some(renderer.host_answers(&questions)?)
    } else {
        None
    };
    Ok(QueryReport {
        answers: run.driver.readback.answers.clone(),
        host,
        colliders: renderer.block().forces.colliders,
        simulate_cull: before.zip(after),
        validation_errors: run.ctx.validation_errors(),
    })
}

/// The questions of `args` on `scene`'s ground: each point dropped onto it.
fn questions(scene: &crate::scene::Scene, args: &QueryArgs) -> Result<Vec<Question>> {
    let ground = |p: Vec2, what: &str| -> Result<Vec3> {
        crate::collider::point_below(&scene.solid, p)
            .map(|hit| hit.position)
            .with_context(|| format!("{what} {},{}: no ground there", p.x, p.y))
    };
    let mut asked = Vec::new();
    for &p in &args.at {
        asked.push(Question::around(Around {
            centre: ground(p, "--at")?,
            radius: args.radius,
        }));
    }
    let up = Vec3::Y * args.eye_height;
    for &(from, to) in &args.sight {
        asked.push(Question::sight(Sight {
            from: ground(from, "--sight")? + up,
            to: ground(to, "--sight")? + up,
            radius: args.sight_radius,
        }));
    }
    Ok(asked)
}

/// One line of the table: the question, then its answer.
fn describe(q: &Question, t: &Tally) -> String {
    let p = |v: glam::Vec4| format!("({:.2}, {:.2}, {:.2})", v.x, v.y, v.z);
    if q.is_sight() {
        let what = format!("sight {} to {} r {}", p(q.a), p(q.b), q.a.w);
        format!(
            "{what:<44} {:>7} {:>9} {:>7} {:>6} {:>11.3}",
            t.blades,
            "",
            "",
            "",
            t.concealment()
        )
    } else {
        let what = format!("around {} r {}", p(q.a), q.a.w);
        format!(
            "{what:<44} {:>7} {:>9.1} {:>7.3} {:>6.3} {:>11}",
            t.blades,
            t.density(q.a.w),
            t.mean_height(),
            t.mean_bend(),
            ""
        )
    }
}

/// Whether two answers agree within rounding: each sum within 1 + 0.2 % of the
/// larger (a blade on a question's edge, or a part rounded the other way, in the
/// GPU's arithmetic against the host's).
pub fn agree(a: &Tally, b: &Tally) -> bool {
    let close = |x: u32, y: u32| x.abs_diff(y) as f32 <= 1.0 + 0.002 * x.max(y) as f32;
    close(a.blades, b.blades)
        && close(a.height, b.height)
        && close(a.bend, b.bend)
        && close(a.cover, b.cover)
}
