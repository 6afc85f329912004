//! The long loops inside a stage ask their observer whether to go on, so that a
//! Ctrl-C or a Python callback stops a run within moments, not at the end of a
//! smoothing or cancellation stage that lasts minutes on a large scan; they tell
//! their progress.

use crestline::lines::LineExtractor;
use crestline::mesh::generate::{self, Sampling};
use crestline::mesh::Mesh;
use crestline::morse::MorseSmale;
use crestline::progress::Observer;
use crestline::ridges::{ExtremalityTracer, Solver};
use crestline::Error;

/// Says no at its `stop_at`-th question asked while stage `stage` runs (and yes
/// to every question outside it).
struct StopInside {
    stage: &'static str,
    stop_at: usize,
    inside: bool,
    asked: usize,
}

impl StopInside {
    fn new(stage: &'static str, stop_at: usize) -> StopInside {
        StopInside {
            stage,
            stop_at,
            inside: false,
            asked: 0,
        }
    }
}

impl Observer for StopInside {
    fn stage_started(&mut self, name: &str) {
        self.inside |= name == self.stage;
    }

    fn stage_finished(&mut self, name: &str, _: f64) {
        if name == self.stage {
            self.inside = false;
        }
    }

    fn keep_going(&mut self) -> bool {
        if !self.inside {
            return true;
        }
        self.asked += 1;
        self.asked < self.stop_at
    }
}

fn ellipsoid() -> Mesh {
    generate::ellipsoid([1.0, 0.7, 0.45], 30_000, Sampling::jittered(1))
        .unwrap()
        .mesh
}

/// Runs `extract` with an observer that stops at its third question inside
/// `stage`, and checks the run stopped there: cancelled, asked exactly three
/// times. A stage that asks only before and after itself is asked nothing inside
/// and runs to its end.
fn stops_inside(
    stage: &'static str,
    extract: impl FnOnce(&mut StopInside) -> crestline::Result<()>,
) {
    let mut observer = StopInside::new(stage, 3);
    let result = extract(&mut observer);
    assert!(
        matches!(result, Err(Error::Cancelled)),
        "{stage}: {result:?} after {} questions inside",
        observer.asked
    );
    assert_eq!(observer.asked, 3, "{stage}: questions inside the stage");
}

/// [`stops_inside`] for ridges on the ellipsoid, with the systems solved by
/// `solver` after `presmooth_steps` steps of presmoothing.
fn tracer_stops_inside(stage: &'static str, solver: Solver, presmooth_steps: usize) {
    let mesh = ellipsoid();
    let tracer = ExtremalityTracer {
        solver,
        presmooth_steps,
        ..ExtremalityTracer::default()
    };
    stops_inside(stage, |observer| tracer.extract(&mesh, observer).map(drop));
}

#[test]
fn the_iterated_extremality_smoothing_stops_between_iterations() {
    tracer_stops_inside("smoothing", Solver::Iterative, 0);
}

#[test]
fn the_factored_extremality_smoothing_stops_between_steps() {
    // Three steps: asked before each, stopped before the third.
    tracer_stops_inside("smoothing", Solver::Direct, 0);
}

#[test]
fn the_surface_presmoothing_stops_between_solves() {
    tracer_stops_inside("presmooth", Solver::Auto, 2);
}

/// A jittered sphere, whose curvedness has critical points at every few vertices:
/// some twenty thousand cancellations.
fn jittered_sphere() -> Mesh {
    generate::sphere(1.0, 60_000, Sampling::jittered(3))
        .unwrap()
        .mesh
}

#[test]
fn the_morse_cancellation_loop_stops_between_cancellations() {
    let mesh = jittered_sphere();
    let (_, summary) = MorseSmale::default()
        .run(&mesh, &mut crestline::progress::Silent)
        .unwrap();
    assert!(
        summary.hierarchy.len() > 3 * 4096,
        "{} cancellations: too few for three questions",
        summary.hierarchy.len()
    );
    stops_inside("cancellation", |observer| {
        MorseSmale::default().run(&mesh, observer).map(drop)
    });
}

/// Records the progress told, with the stage running then.
#[derive(Default)]
struct ProgressLog {
    running: String,
    told: Vec<(String, usize, usize)>,
}

impl Observer for ProgressLog {
    fn stage_started(&mut self, name: &str) {
        self.running = name.to_string();
    }

    fn progress(&mut self, done: usize, total: usize) {
        self.told.push((self.running.clone(), done, total));
    }
}

#[test]
fn the_smoothing_stages_tell_their_steps() {
    let tracer = ExtremalityTracer {
        presmooth_steps: 2,
        solver: Solver::Iterative,
        ..ExtremalityTracer::default()
    };
    let mut log = ProgressLog::default();
    tracer.extract(&ellipsoid(), &mut log).unwrap();
    let told = |stage: &str, done: usize, total: usize| (stage.to_string(), done, total);
    assert_eq!(
        log.told,
        [
            told("presmooth", 0, 2),
            told("presmooth", 1, 2),
            told("presmooth", 2, 2),
            told("smoothing", 0, 3),
            told("smoothing", 1, 3),
            told("smoothing", 2, 3),
            told("smoothing", 3, 3),
        ]
    );
}

#[test]
fn the_morse_cancellation_tells_how_many_are_done_of_at_most_how_many() {
    let mut log = ProgressLog::default();
    let (_, summary) = MorseSmale::default()
        .run(&jittered_sphere(), &mut log)
        .unwrap();
    let told: Vec<(usize, usize)> = log
        .told
        .iter()
        .filter(|(stage, ..)| stage == "cancellation")
        .map(|&(_, done, total)| (done, total))
        .collect();
    let made = summary.hierarchy.len();
    // From none done, every 4096, to all of them: the totals never grow and
    // never fall below what is made in the end.
    assert_eq!(told.first().map(|t| t.0), Some(0));
    assert_eq!(told.last(), Some(&(made, made)));
    assert_eq!(told.len(), made / 4096 + 2, "{told:?}");
    for pair in told.windows(2) {
        assert!(pair[1].0 > pair[0].0 && pair[1].1 <= pair[0].1, "{pair:?}");
    }
    assert!(told.iter().all(|&(_, total)| total >= made), "{told:?}");
}
