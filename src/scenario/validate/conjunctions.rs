//! `[conjunctions]`: the miss-distance threshold of the conjunction monitor.

use crate::scenario::schema::ConjunctionsSection;
use crate::scenario::ScenarioError;

use super::Checker;

/// The threshold of `[conjunctions] threshold_m` \[m\] (finite, >= 0), or `None` without the section.
pub(super) fn threshold_m(
    c: &Checker<'_>,
    section: Option<&ConjunctionsSection>,
) -> Result<Option<f64>, ScenarioError> {
    section
        .map(|s| c.non_negative("conjunctions.threshold_m", s.threshold_m))
        .transpose()
}
