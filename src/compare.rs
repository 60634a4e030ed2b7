//! Speed against accuracy: a scene run with every applicable method, each scored against the
//! exact event log (the brute-force reference's).
//!
//! A contact is a `begin` and the `end` that follows it (or the horizon). An exact contact is
//! *found* when the method reports a contact of the same pair that overlaps it in time, give
//! or take the method's step; otherwise it is *missed*. A reported contact that overlaps no
//! exact one is a *false contact*. The time error of a found contact is how far its begin is
//! from the exact one.

use crate::rapier_run::{Broad, run_rapier};
use crate::time_stepped::run_stepped;
use kinetic_collide::Structure;
use kinetic_collide::run::{RunError, run_scene};
use kinetic_collide::scene::Scene;
use kinetic_core::{ContactEvent, ContactKind, Real, Response};
use kinetic_scenes::families::{Case, Family};
use std::collections::BTreeMap;

/// The steps the time-stepped methods run at.
pub const STEPS: [(u32, Real); 5] = [
    (30, 1.0 / 30.0),
    (60, 1.0 / 60.0),
    (120, 1.0 / 120.0),
    (240, 1.0 / 240.0),
    (1000, 1.0 / 1000.0),
];

/// A way of detecting contacts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// A kinetic structure, exact.
    Kinetic(Structure),
    /// Overlap tests at every step, pairs from a per-step sweep-and-prune.
    Stepped(Real),
    /// rapier 0.27's pipeline with the given broad phase and CCD on or off.
    Rapier {
        /// The step.
        dt: Real,
        /// The broad phase.
        broad: Broad,
        /// Continuous collision detection on every body.
        ccd: bool,
    },
    /// avian 0.8 stepped at `dt` on its own broad phase or the kinetic plugin, with
    /// `SweptCcd` on every body or not (feature `avian`).
    Avian {
        /// The step.
        dt: Real,
        /// The kinetic plugin instead of avian's broad phase.
        kinetic: bool,
        /// `SweptCcd` on every body.
        ccd: bool,
    },
}

impl Method {
    /// The method's name in tables ("sweep", "stepped", "rapier", "rapier+ccd",
    /// "rapier+kinetic", "avian", "avian+ccd", "avian+kinetic").
    pub fn name(&self) -> &'static str {
        match self {
            Method::Kinetic(s) => s.name(),
            Method::Stepped(_) => "stepped",
            Method::Rapier {
                broad: Broad::Default,
                ccd: false,
                ..
            } => "rapier",
            Method::Rapier {
                broad: Broad::Default,
                ccd: true,
                ..
            } => "rapier+ccd",
            Method::Rapier {
                broad: Broad::Kinetic,
                ccd: false,
                ..
            } => "rapier+kinetic",
            Method::Rapier {
                broad: Broad::Kinetic,
                ccd: true,
                ..
            } => "rapier+kinetic+ccd",
            Method::Avian {
                kinetic: false,
                ccd: false,
                ..
            } => "avian",
            Method::Avian {
                kinetic: false,
                ccd: true,
                ..
            } => "avian+ccd",
            Method::Avian {
                kinetic: true,
                ccd: false,
                ..
            } => "avian+kinetic",
            Method::Avian {
                kinetic: true,
                ccd: true,
                ..
            } => "avian+kinetic+ccd",
        }
    }

    /// The step, for the time-stepped methods.
    pub fn dt(&self) -> Option<Real> {
        match *self {
            Method::Kinetic(_) => None,
            Method::Stepped(dt) | Method::Rapier { dt, .. } | Method::Avian { dt, .. } => Some(dt),
        }
    }

    /// The step as written in tables: `1/60`, or `exact` for a kinetic structure.
    pub fn step_label(&self) -> String {
        match self.dt() {
            None => "exact".into(),
            Some(dt) => STEPS
                .iter()
                .find(|(_, s)| *s == dt)
                .map_or(format!("{dt}"), |(k, _)| format!("1/{k}")),
        }
    }

    /// Every method that applies to `scene`: its kinetic structures and the brute force;
    /// and, when objects pass through each other (response `"none"`, so every method follows
    /// the same motion), time-stepped detection, rapier and (feature `avian`) avian at each
    /// of [`STEPS`].
    pub fn applicable(scene: &Scene) -> Vec<Method> {
        let mut methods: Vec<Method> = Structure::ALL
            .into_iter()
            .filter(|s| s.applies_to(scene))
            .map(Method::Kinetic)
            .collect();
        if scene.response == Response::None {
            for (_, dt) in STEPS {
                methods.push(Method::Stepped(dt));
                for (broad, ccd) in [
                    (Broad::Default, false),
                    (Broad::Default, true),
                    (Broad::Kinetic, false),
                ] {
                    methods.push(Method::Rapier { dt, broad, ccd });
                }
                if cfg!(feature = "avian") {
                    for (kinetic, ccd) in [(false, false), (false, true), (true, false)] {
                        methods.push(Method::Avian { dt, kinetic, ccd });
                    }
                }
            }
        }
        methods
    }
}

/// How a method's contacts compare with the exact ones.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Accuracy {
    /// Exact contacts (begins in the exact log).
    pub contacts: usize,
    /// Exact contacts the method found.
    pub found: usize,
    /// Begins the method reported that match no exact contact.
    pub false_contacts: usize,
    /// Median of |method's begin - exact begin| over found contacts (NaN if none).
    pub error_median: Real,
    /// Largest such error (NaN if none).
    pub error_max: Real,
}

impl Accuracy {
    /// Exact contacts missed.
    pub fn missed(&self) -> usize {
        self.contacts - self.found
    }

    /// The fraction of exact contacts missed (0 when there are none).
    pub fn missed_fraction(&self) -> Real {
        if self.contacts == 0 {
            0.0
        } else {
            self.missed() as Real / self.contacts as Real
        }
    }
}

/// Contact intervals `(begin, end)` per pair; a contact that never ends lasts to `horizon`.
fn contacts(events: &[ContactEvent], horizon: Real) -> BTreeMap<(u32, u32), Vec<(Real, Real)>> {
    let mut open: BTreeMap<(u32, u32), Real> = BTreeMap::new();
    let mut out: BTreeMap<(u32, u32), Vec<(Real, Real)>> = BTreeMap::new();
    for e in events {
        let pair = (e.a.0, e.b.0);
        match e.kind {
            ContactKind::Begin => {
                // Elastic logs have begins only: each is a contact of no length.
                if let Some(b) = open.insert(pair, e.time) {
                    out.entry(pair).or_default().push((b, b));
                }
            }
            ContactKind::End => {
                if let Some(b) = open.remove(&pair) {
                    out.entry(pair).or_default().push((b, e.time));
                }
            }
        }
    }
    for (pair, b) in open {
        out.entry(pair).or_default().push((b, horizon));
    }
    for v in out.values_mut() {
        v.sort_by(|x, y| x.0.total_cmp(&y.0));
    }
    out
}

/// Scores `found` against `exact`: a found contact matches an exact contact of the same pair
/// when their time intervals overlap, with `slack` to spare on either side; each contact
/// matches at most one other, in time order.
pub fn score(
    exact: &[ContactEvent],
    found: &[ContactEvent],
    horizon: Real,
    slack: Real,
) -> Accuracy {
    let exact = contacts(exact, horizon);
    let found = contacts(found, horizon);
    let mut acc = Accuracy {
        contacts: exact.values().map(Vec::len).sum(),
        found: 0,
        false_contacts: 0,
        error_median: Real::NAN,
        error_max: Real::NAN,
    };
    let mut errors = Vec::new();
    for (pair, got) in &found {
        let want = exact.get(pair).map_or(&[][..], Vec::as_slice);
        let (mut i, mut j) = (0, 0);
        while j < got.len() {
            let (d, d_end) = got[j];
            match want.get(i) {
                // An exact contact over before this one starts: missed.
                Some(&(_, e)) if e + slack < d => i += 1,
                // They overlap: found.
                Some(&(b, _)) if d_end + slack >= b => {
                    acc.found += 1;
                    errors.push((d - b).abs());
                    (i, j) = (i + 1, j + 1);
                }
                // No exact contact here: false.
                _ => {
                    acc.false_contacts += 1;
                    j += 1;
                }
            }
        }
    }
    if !errors.is_empty() {
        errors.sort_by(Real::total_cmp);
        acc.error_median = errors[(errors.len() - 1) / 2];
        acc.error_max = errors[errors.len() - 1];
    }
    acc
}

/// One method's result on one scene: a row of the table and the CSV.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Row {
    /// The scene's name (its family or file stem).
    pub scene: String,
    /// Objects in the scene.
    pub objects: usize,
    /// The method's name.
    pub method: &'static str,
    /// Whether it is the structure the tool takes by default for the scene.
    pub default: bool,
    /// Its step (`exact` for kinetic structures).
    pub step: String,
    /// Wall-clock seconds for the whole run.
    pub wall_seconds: Real,
    /// Exact contacts.
    pub contacts: usize,
    /// Exact contacts missed.
    pub missed: usize,
    /// Fraction missed.
    pub missed_fraction: Real,
    /// Median contact-time error (empty when nothing was found).
    pub time_error_median: Option<Real>,
    /// Largest contact-time error.
    pub time_error_max: Option<Real>,
    /// Begins that match no exact contact.
    pub false_contacts: usize,
    /// Why the method could not finish (empty when it did).
    pub error: String,
}

/// A scene to compare, with the name its rows carry.
pub struct NamedScene {
    /// The name.
    pub name: String,
    /// The scene.
    pub scene: Scene,
}

impl NamedScene {
    /// A built-in family (`gas`, or `gas:1000` for a size) or a scene file.
    pub fn load(arg: &str) -> Result<NamedScene, String> {
        let (name, size) = match arg.split_once(':') {
            Some((name, size)) => (name, Some(size)),
            None => (arg, None),
        };
        let is_file = std::path::Path::new(arg).exists();
        if let Some(case) = Case::parse(arg).filter(|_| !is_file) {
            return Ok(NamedScene {
                name: arg.to_string(),
                scene: case.scene(),
            });
        }
        if let Some(family) = Family::parse(name).filter(|_| !is_file) {
            let n = match size {
                None => family.default_size(),
                Some(s) => s
                    .parse::<usize>()
                    .ok()
                    .filter(|&n| n >= 2)
                    .ok_or_else(|| format!("{arg}: size {s:?} is not a whole number >= 2"))?,
            };
            return Ok(NamedScene {
                name: name.to_string(),
                scene: family.scene(n, 1),
            });
        }
        let path = std::path::Path::new(arg);
        let text = std::fs::read_to_string(path).map_err(|e| {
            let families: Vec<&str> = Family::ALL.iter().map(|f| f.name()).collect();
            let cases: Vec<&str> = Case::ALL.iter().map(|c| c.name()).collect();
            format!(
                "{arg}: not a scene file ({e}), a family ({}) or a stability case ({})",
                families.join(", "),
                cases.join(", ")
            )
        })?;
        let scene = Scene::from_json(&text).map_err(|e| format!("{arg}: {e}"))?;
        let name = path
            .file_stem()
            .map_or(arg.to_string(), |s| s.to_string_lossy().into_owned());
        Ok(NamedScene { name, scene })
    }
}

/// Runs `method` on `scene`: its events and wall time, or why it stopped (with the events up
/// to then).
fn run_method(scene: &Scene, method: Method) -> (Vec<ContactEvent>, Real, Option<String>) {
    match method {
        Method::Kinetic(s) => match run_scene(scene, Some(s)) {
            Ok(out) => (out.events, out.wall_seconds, None),
            Err(RunError::Stopped {
                time,
                source,
                partial,
            }) => (
                partial.events,
                partial.wall_seconds,
                Some(format!("stopped at t = {time}: {source}")),
            ),
            Err(e) => (Vec::new(), 0.0, Some(e.to_string())),
        },
        Method::Stepped(dt) => match run_stepped(scene, dt) {
            Ok(out) => (out.events, out.wall_seconds, None),
            Err(e) => (Vec::new(), 0.0, Some(e.to_string())),
        },
        Method::Rapier { dt, broad, ccd } => match run_rapier(scene, dt, broad, ccd) {
            Ok(out) => (out.events, out.wall_seconds, None),
            Err(e) => (Vec::new(), 0.0, Some(e.to_string())),
        },
        #[cfg(feature = "avian")]
        Method::Avian { dt, kinetic, ccd } => {
            match crate::avian_run::run_avian(scene, dt, kinetic, ccd) {
                Ok(out) => (out.events, out.wall_seconds, None),
                Err(e) => (Vec::new(), 0.0, Some(e.to_string())),
            }
        }
        #[cfg(not(feature = "avian"))]
        Method::Avian { .. } => (
            Vec::new(),
            0.0,
            Some("avian: built without the `avian` feature".to_string()),
        ),
    }
}

/// Compares every applicable method on `scene`, calling `progress` after each run. The exact
/// log is the brute force's (in a periodic box, the periodic structure's: nothing else wraps).
pub fn compare_scene(scene: &NamedScene, mut progress: impl FnMut(&Row)) -> Vec<Row> {
    let s = &scene.scene;
    let reference = if s.periodic.is_some() {
        Structure::Periodic
    } else {
        Structure::BruteForce
    };
    let (exact, _, exact_error) = run_method(s, Method::Kinetic(reference));
    let mut rows = Vec::new();
    for method in Method::applicable(s) {
        let (events, wall, error) = run_method(s, method);
        // A sampled method sees a contact up to a step late; f32 poses (rapier) a little more.
        let slack = method
            .dt()
            .map_or(1e-7 * s.horizon.max(1.0), |dt| dt * 1.001);
        let acc = score(&exact, &events, s.horizon, slack);
        let finite = |x: Real| (!x.is_nan()).then_some(x);
        let error = error.or_else(|| {
            exact_error
                .as_ref()
                .map(|e| format!("exact log incomplete: {e}"))
        });
        let row = Row {
            scene: scene.name.clone(),
            objects: s.objects.len(),
            method: method.name(),
            default: method == Method::Kinetic(kinetic_collide::Structure::for_scene(s)),
            step: method.step_label(),
            wall_seconds: wall,
            contacts: acc.contacts,
            missed: acc.missed(),
            missed_fraction: acc.missed_fraction(),
            time_error_median: finite(acc.error_median),
            time_error_max: finite(acc.error_max),
            false_contacts: acc.false_contacts,
            error: error.unwrap_or_default(),
        };
        progress(&row);
        rows.push(row);
    }
    rows
}

/// Writes the rows as CSV.
pub fn write_csv(path: &std::path::Path, rows: &[Row]) -> Result<(), String> {
    let mut w = csv::Writer::from_path(path).map_err(|e| format!("{}: {e}", path.display()))?;
    for row in rows {
        w.serialize(row)
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    w.flush().map_err(|e| format!("{}: {e}", path.display()))
}

/// The rows as a Markdown table.
pub fn markdown(rows: &[Row]) -> String {
    let mut out = String::from(
        "| scene | method | step | wall s | contacts | missed | time error median | max | false |\n\
         |---|---|---|---:|---:|---:|---:|---:|---:|\n",
    );
    let e = |x: Option<Real>| x.map_or("-".to_string(), |x| format!("{x:.2e}"));
    for r in rows {
        out.push_str(&format!(
            "| {} ({}) | {}{} | {} | {:.3} | {} | {} ({:.1}%) | {} | {} | {} |{}\n",
            r.scene,
            r.objects,
            r.method,
            if r.default { " (default)" } else { "" },
            r.step,
            r.wall_seconds,
            r.contacts,
            r.missed,
            100.0 * r.missed_fraction,
            e(r.time_error_median),
            e(r.time_error_max),
            r.false_contacts,
            if r.error.is_empty() {
                String::new()
            } else {
                format!(" {}", r.error)
            },
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use kinetic_core::ObjectId;

    fn ev(time: Real, a: u32, b: u32, kind: ContactKind) -> ContactEvent {
        ContactEvent {
            time,
            a: ObjectId(a),
            b: ObjectId(b),
            kind,
        }
    }

    #[test]
    fn scoring_counts_found_missed_false_and_errors() {
        use ContactKind::{Begin, End};
        let exact = [
            ev(0.10, 0, 1, Begin),
            ev(0.20, 0, 1, End),
            ev(0.50, 0, 1, Begin),
            ev(0.51, 0, 1, End),
            ev(0.70, 2, 3, Begin),
        ];
        // Found (0, 1) first contact 0.05 late; missed the short one; (2, 3) 0.2 early (the
        // intervals overlap) but a begin of (1, 2) that never happened.
        let found = [
            ev(0.15, 0, 1, Begin),
            ev(0.25, 0, 1, End),
            ev(0.50, 2, 3, Begin),
            ev(0.80, 1, 2, Begin),
        ];
        let acc = score(&exact, &found, 1.0, 0.1);
        assert_eq!((acc.contacts, acc.found, acc.false_contacts), (3, 2, 1));
        assert_eq!(acc.missed(), 1);
        assert!((acc.error_median - 0.05).abs() < 1e-12);
        assert!((acc.error_max - 0.2).abs() < 1e-12);
        assert!((acc.missed_fraction() - 1.0 / 3.0).abs() < 1e-12);
        // The exact log scores perfectly against itself.
        let same = score(&exact, &exact, 1.0, 0.0);
        assert_eq!(
            (same.found, same.false_contacts, same.error_max),
            (3, 0, 0.0)
        );
    }
}
