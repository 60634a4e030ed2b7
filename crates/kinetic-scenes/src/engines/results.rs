//! The engine benches' figures over the draws of [`super::space`]: one row per draw and
//! engine, kinetic beside the engine's own broad phase, then the worst draw and the median
//! of each ratio, written to one CSV file that both engines' benches share (each replaces
//! its own engine's rows and keeps the other's).

use super::space::Draw;
use std::fmt::Write as _;

/// One side's figures on one draw, per step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Side {
    /// The whole step, milliseconds.
    pub step_ms: f64,
    /// The broad phase as the engine counts it, milliseconds.
    pub broad_phase_ms: f64,
    /// The pairs handed to the narrow phase (in the contact graph).
    pub pairs: f64,
}

/// One draw's figures on one engine: the engine's own broad phase and the kinetic one.
#[derive(Clone, Debug, PartialEq)]
pub struct DrawRow {
    /// The draw (its axes; the scene is not written).
    pub draw: String,
    /// The draw's seed.
    pub seed: u64,
    /// Steps timed.
    pub steps: usize,
    /// The engine's own broad phase.
    pub own: Side,
    /// The kinetic broad phase.
    pub kinetic: Side,
    /// What the kinetic broad phase ran as (its structure or mode).
    pub structure: String,
    /// Where measured, the engine's own broad phase once more with the pairs of each update
    /// handed over in reverse order, its step in milliseconds: the same pairs in another
    /// order, which a solver that visits contacts in the order they came may settle
    /// differently (a stack's contact points, so its step, can move by a fifth). The step
    /// ratio's reference: how far the step moves with the order of the pairs alone.
    pub own_reversed_step_ms: Option<f64>,
}

impl DrawRow {
    /// The row of `draw` run `steps` steps.
    pub fn new(draw: &Draw, steps: usize, own: Side, kinetic: Side, structure: &str) -> Self {
        DrawRow {
            draw: draw.to_string(),
            seed: draw.seed,
            steps,
            own,
            kinetic,
            structure: structure.to_string(),
            own_reversed_step_ms: None,
        }
    }

    /// The engine's own step with its pairs handed over in reverse order, over its step as
    /// it is, where measured.
    pub fn reversed_ratio(&self) -> Option<f64> {
        self.own_reversed_step_ms
            .map(|r| r / self.own.step_ms)
            .filter(|x| x.is_finite())
    }

    /// Kinetic over own: the whole step, the broad phase and the pairs (1 where both are 0).
    pub fn ratios(&self) -> [f64; 3] {
        let r = |k: f64, o: f64| {
            if o > 0.0 {
                k / o
            } else if k > 0.0 {
                f64::INFINITY
            } else {
                1.0
            }
        };
        [
            r(self.kinetic.step_ms, self.own.step_ms),
            r(self.kinetic.broad_phase_ms, self.own.broad_phase_ms),
            r(self.kinetic.pairs, self.own.pairs),
        ]
    }
}

/// The worst (largest) and median of each ratio over `rows`: `[[step, bp, pairs]; 2]`.
pub fn worst_and_median(rows: &[DrawRow]) -> [[f64; 3]; 2] {
    let mut out = [[f64::NAN; 3]; 2];
    for i in 0..3 {
        [out[0][i], out[1][i]] = largest_and_median(rows.iter().map(|r| r.ratios()[i]).collect());
    }
    out
}

/// The largest and the median of `xs` (NaN for none).
fn largest_and_median(mut xs: Vec<f64>) -> [f64; 2] {
    if xs.is_empty() {
        return [f64::NAN; 2];
    }
    xs.sort_by(f64::total_cmp);
    let n = xs.len();
    let median = if n % 2 == 1 {
        xs[n / 2]
    } else {
        (xs[n / 2 - 1] + xs[n / 2]) / 2.0
    };
    [xs[n - 1], median]
}

/// Over the rows where it was measured, the largest and the median of the engine's own step
/// with its pairs reversed over its step as it is ([`DrawRow::reversed_ratio`]), and the
/// smallest; `None` where no row has it.
pub fn reversed_spread(rows: &[DrawRow]) -> Option<[f64; 3]> {
    let xs: Vec<f64> = rows.iter().filter_map(DrawRow::reversed_ratio).collect();
    let least = xs.iter().copied().reduce(f64::min)?;
    let [largest, median] = largest_and_median(xs);
    Some([largest, median, least])
}

/// The CSV header.
pub const HEADER: &str = "engine,seed,draw,steps,own_step_ms,kinetic_step_ms,step_ratio,own_broad_phase_ms,kinetic_broad_phase_ms,broad_phase_ratio,own_pairs,kinetic_pairs,pairs_ratio,structure,own_reversed_step_ratio";

/// `engine`'s rows, then its worst and median lines (`seed` column `worst` / `median`).
pub fn csv_lines(engine: &str, rows: &[DrawRow]) -> Vec<String> {
    let mut lines = Vec::with_capacity(rows.len() + 2);
    for r in rows {
        let [s, b, p] = r.ratios();
        let mut line = String::new();
        let _ = write!(
            line,
            "{engine},{},{},{},{:.3},{:.3},{s:.3},{:.4},{:.4},{b:.3},{:.0},{:.0},{p:.3},{},{}",
            r.seed,
            r.draw,
            r.steps,
            r.own.step_ms,
            r.kinetic.step_ms,
            r.own.broad_phase_ms,
            r.kinetic.broad_phase_ms,
            r.own.pairs,
            r.kinetic.pairs,
            r.structure,
            r.reversed_ratio()
                .map_or(String::new(), |x| format!("{x:.3}"))
        );
        lines.push(line);
    }
    let [worst, median] = worst_and_median(rows);
    let reversed = reversed_spread(rows);
    for (k, (label, v)) in [("worst", worst), ("median", median)]
        .into_iter()
        .enumerate()
    {
        lines.push(format!(
            "{engine},{label},{} draws,,,,{:.3},,,{:.3},,,{:.3},,{}",
            rows.len(),
            v[0],
            v[1],
            v[2],
            reversed.map_or(String::new(), |r| format!("{:.3}", r[k]))
        ));
    }
    lines
}

/// Prints the worst and the median of `engine`'s `rows`, and writes them with the rows as
/// `engine`'s lines of the CSV file `path`, keeping the other engines' lines.
pub fn report(engine: &str, rows: &[DrawRow], path: &str) {
    let [worst, median] = worst_and_median(rows);
    println!(
        "\nworst: step {:.2}x, broad phase {:.2}x, pairs {:.2}x; median: step {:.2}x, broad phase {:.2}x, pairs {:.2}x ({} draws)",
        worst[0],
        worst[1],
        worst[2],
        median[0],
        median[1],
        median[2],
        rows.len()
    );
    if let Some([largest, median, least]) = reversed_spread(rows) {
        println!(
            "own broad phase, pairs handed over in reverse order, step over its own: {least:.2}x to {largest:.2}x, median {median:.2}x"
        );
    }
    let existing = std::fs::read_to_string(path).unwrap_or_default();
    let text = merge(&existing, engine, &csv_lines(engine, rows));
    match std::fs::write(path, text) {
        Ok(()) => println!("wrote {path}"),
        Err(e) => eprintln!("could not write {path}: {e}"),
    }
}

/// `existing` (a CSV file's text, empty if none) with `engine`'s lines replaced by `lines`:
/// the other engines' lines kept, in their order, this engine's after them.
pub fn merge(existing: &str, engine: &str, lines: &[String]) -> String {
    let mut out = vec![HEADER.to_string()];
    let prefix = format!("{engine},");
    out.extend(
        existing
            .lines()
            .skip(1)
            .filter(|l| !l.is_empty() && !l.starts_with(&prefix))
            .map(str::to_string),
    );
    out.extend(lines.iter().cloned());
    out.join("\n") + "\n"
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engines::space::draw;

    fn row(seed: u64, own: f64, kinetic: f64) -> DrawRow {
        let side = |ms: f64| Side {
            step_ms: ms,
            broad_phase_ms: ms / 10.0,
            pairs: 100.0,
        };
        DrawRow::new(&draw(seed), 60, side(own), side(kinetic), "grid")
    }

    #[test]
    fn the_worst_and_median_are_over_the_draws_and_each_engine_keeps_the_others_rows() {
        let rows = [row(1, 10.0, 5.0), row(2, 10.0, 12.0), row(3, 10.0, 9.0)];
        let [worst, median] = worst_and_median(&rows);
        assert!((worst[0] - 1.2).abs() < 1e-12 && (median[0] - 0.9).abs() < 1e-12);
        assert!((worst[2] - 1.0).abs() < 1e-12);
        let rapier = csv_lines("rapier", &rows);
        assert_eq!(rapier.len(), 5);
        assert!(rapier[3].starts_with("rapier,worst,3 draws,") && rapier[3].contains("1.200"));
        let file = merge("", "rapier", &rapier);
        let avian = csv_lines("avian", &rows[..1]);
        let both = merge(&file, "avian", &avian);
        assert_eq!(both.lines().count(), 1 + 5 + 3);
        let again = merge(&both, "rapier", &rapier[..2]);
        assert_eq!(again.lines().count(), 1 + 3 + 2);
        assert!(again.lines().nth(1).unwrap().starts_with("avian,"));
        assert_eq!(again.lines().next(), Some(HEADER));
        assert!(reversed_spread(&rows).is_none() && rapier[0].ends_with(",grid,"));
    }

    #[test]
    fn the_reversed_order_reference_is_over_the_rows_that_have_it() {
        let mut rows = vec![row(1, 10.0, 5.0), row(2, 10.0, 12.0), row(3, 8.0, 9.0)];
        rows[0].own_reversed_step_ms = Some(12.0);
        rows[2].own_reversed_step_ms = Some(6.0);
        assert_eq!(rows[1].reversed_ratio(), None);
        let [largest, median, least] = reversed_spread(&rows).expect("two rows have it");
        assert!((largest - 1.2).abs() < 1e-12 && (least - 0.75).abs() < 1e-12);
        assert!((median - 0.975).abs() < 1e-12);
        let lines = csv_lines("rapier", &rows);
        assert!(lines[0].ends_with(",grid,1.200") && lines[1].ends_with(",grid,"));
        assert!(lines[3].ends_with(",,1.200") && lines[4].ends_with(",,0.975"));
    }
}
