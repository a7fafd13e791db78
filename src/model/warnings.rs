//! What the readers repaired or ignored in a file: [`ReadWarning`]s, grouped by what was done.
//!
//! The readers' policy (`docs/design.md#reading-real-files`): read what the solids use, ignore
//! the rest with a warning, repair what exporters commonly get wrong with a warning, and refuse
//! only what cannot be repaired. Every repair and every entity ignored is one of these, in the
//! report's `input.warnings`; similar ones are counted in one warning that names the first
//! entity.

use serde::Serialize;

/// One kind of repair or omission, with how many entities it concerned.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ReadWarning {
    /// A short key for what was done: `unused`, `direction`, `gap`, `text`, `void`,
    /// `orientation`, `assembly`, `surface_model`, `range`, `sewn`, `cycle` (a reference cycle
    /// through entities nothing reads), `fold` (faces folded back onto each other at an edge,
    /// found when classifying).
    pub kind: &'static str,
    /// The first entity concerned, as `#41 EDGE_CURVE` (STEP) or `DE 17 (126)` (IGES), or
    /// the file when no one entity is to blame.
    pub entity: String,
    /// How many entities it concerned.
    pub count: usize,
    /// What was wrong.
    pub problem: String,
    /// What the reader did about it.
    pub action: String,
    /// The largest gap accepted, in millimetres, where the warning is about gaps.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub largest_gap_mm: Option<f64>,
}

/// The warnings of one read, merged by `(kind, problem)`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Warnings(Vec<ReadWarning>);

impl Warnings {
    /// Records that `entity` had `problem` and the reader did `action`; counted into an
    /// earlier warning with the same kind and problem.
    pub fn add(&mut self, kind: &'static str, entity: String, problem: &str, action: &str) {
        self.add_gap(kind, entity, problem, action, None);
    }

    /// As [`Self::add`], for a gap of `gap_mm` that was accepted (the largest is kept).
    pub fn add_gap(
        &mut self,
        kind: &'static str,
        entity: String,
        problem: &str,
        action: &str,
        gap_mm: Option<f64>,
    ) {
        if let Some(w) = self
            .0
            .iter_mut()
            .find(|w| w.kind == kind && w.problem == problem)
        {
            w.count += 1;
            if let Some(g) = gap_mm {
                w.largest_gap_mm = Some(w.largest_gap_mm.map_or(g, |h| h.max(g)));
            }
            return;
        }
        self.0.push(ReadWarning {
            kind,
            entity,
            count: 1,
            problem: problem.into(),
            action: action.into(),
            largest_gap_mm: gap_mm,
        });
    }

    /// Adds `n` entities at once (nothing when `n` is 0).
    pub fn add_many(
        &mut self,
        kind: &'static str,
        entity: String,
        n: usize,
        problem: &str,
        action: &str,
    ) {
        if n == 0 {
            return;
        }
        self.add(kind, entity, problem, action);
        if let Some(w) = self
            .0
            .iter_mut()
            .find(|w| w.kind == kind && w.problem == problem)
        {
            w.count += n - 1;
        }
    }

    /// The warnings, in the order first met.
    pub fn into_vec(self) -> Vec<ReadWarning> {
        self.0
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

/// One line for people: `17 EDGE_CURVE defined in the file but not part of any solid (first
/// #41): ignored; …`.
pub fn summary_line(warnings: &[ReadWarning]) -> String {
    warnings
        .iter()
        .map(|w| {
            let gap = w
                .largest_gap_mm
                .map(|g| format!(", largest {g:.3e} mm"))
                .unwrap_or_default();
            if w.count == 1 {
                format!("{}: {}{gap}: {}", w.entity, w.problem, w.action)
            } else {
                format!(
                    "{} × {} (first {}){gap}: {}",
                    w.count, w.problem, w.entity, w.action
                )
            }
        })
        .collect::<Vec<_>>()
        .join("; ")
}

/// What [`gaps_beyond`] says of faces whose edges lie off their surfaces.
pub const GAP_BEYOND_ACCURACY_PROBLEM: &str =
    "face's edges lie off its surface by more than the accuracy (the file's own gap)";

/// What is done about it.
pub const GAP_BEYOND_ACCURACY_ACTION: &str =
    "traced on the surfaces; balls near those faces are verified to the accuracy plus the gap";

/// A warning (kind `gap`) when some face's edges lie off its surface by more than `accuracy`
/// ([`Face::gap_mm`](super::Face::gap_mm), measured on reading): the first such face, how
/// many there are and the largest gap. Exporters write edges that follow one of their faces
/// and not the other, within the file's declared uncertainty; near them the boundary is
/// defined only to that gap, whatever accuracy is asked for.
pub fn gaps_beyond(model: &super::Model, accuracy: f64) -> Option<ReadWarning> {
    let over: Vec<(usize, &super::Face)> = model
        .faces
        .iter()
        .enumerate()
        .filter(|(_, f)| f.gap_mm() > accuracy)
        .collect();
    let &(i, first) = over.first()?;
    Some(ReadWarning {
        kind: "gap",
        entity: format!("face F{i} (entity {})", first.source_id),
        count: over.len(),
        problem: GAP_BEYOND_ACCURACY_PROBLEM.into(),
        action: GAP_BEYOND_ACCURACY_ACTION.into(),
        largest_gap_mm: Some(over.iter().map(|(_, f)| f.gap_mm()).fold(0.0, f64::max)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The roof whose plane F2 was moved 3e-4 mm off its edges: the reader measures that face's
    /// gap (and no other), and `gaps_beyond` warns of it at an accuracy finer than the gap
    /// only; the same block without the gap has none.
    #[test]
    fn a_faces_gap_is_measured_on_reading_and_warned_of_beyond_the_accuracy() {
        let gapped = crate::testing::sample("trace/roof_off_its_ridge.step");
        let gaps: Vec<f64> = gapped.faces.iter().map(|f| f.gap_mm()).collect();
        assert!((gaps[2] - 3e-4).abs() < 1e-9, "{gaps:?}");
        for (i, g) in gaps.iter().enumerate() {
            assert!(i == 2 || *g < 1e-9, "{gaps:?}");
        }
        let w = gaps_beyond(&gapped, 5e-5).expect("a warning at 5e-5 mm");
        assert_eq!((w.kind, w.count), ("gap", 1));
        assert!(w.entity.starts_with("face F2 "), "{}", w.entity);
        assert!(gaps_beyond(&gapped, 1e-3).is_none());
        let clean = crate::testing::sample("trace/shallow_roof.step");
        assert!(clean.faces.iter().all(|f| f.gap_mm() < 1e-9));
        assert!(gaps_beyond(&clean, 1e-9).is_none());
    }

    #[test]
    fn similar_warnings_are_counted_once_with_the_first_entity_and_the_largest_gap() {
        let mut w = Warnings::default();
        w.add_gap(
            "gap",
            "#5 EDGE_CURVE".into(),
            "vertex off curve",
            "accepted",
            Some(1e-3),
        );
        w.add(
            "unused",
            "#7 EDGE_CURVE".into(),
            "not part of any solid",
            "ignored",
        );
        w.add_gap(
            "gap",
            "#9 EDGE_CURVE".into(),
            "vertex off curve",
            "accepted",
            Some(5e-3),
        );
        w.add_gap(
            "gap",
            "#11 EDGE_CURVE".into(),
            "vertex off curve",
            "accepted",
            Some(2e-3),
        );
        w.add_many("unused", "#12 FACE".into(), 0, "x", "y");
        let v = w.into_vec();
        assert_eq!(v.len(), 2);
        assert_eq!(v[0].entity, "#5 EDGE_CURVE");
        assert_eq!(v[0].count, 3);
        assert_eq!(v[0].largest_gap_mm, Some(5e-3));
        assert_eq!(v[1].count, 1);
        let line = summary_line(&v);
        assert!(
            line.contains(
                "3 × vertex off curve (first #5 EDGE_CURVE), largest 5.000e-3 mm: accepted"
            ),
            "{line}"
        );
        assert!(
            line.contains("#7 EDGE_CURVE: not part of any solid: ignored"),
            "{line}"
        );
    }
}
