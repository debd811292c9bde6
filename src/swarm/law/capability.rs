//! A law's optional capabilities: what a law may do beyond the core [`GuidanceLaw`] (a state, a
//! command, its parameters), each a trait of its own, written once and implemented only by the laws
//! that have it.
//!
//! * [`Centralised`]: a periodic step with the whole swarm (a ground-computed grouping).
//! * [`Reports`]: the law's results for `summary.json` (a typed, serialisable struct) and its headline
//!   outcomes, the rows `satflock compare` shows for it.
//! * [`Diagnostics`]: per-satellite trajectory columns and per-recording metrics columns.
//! * [`TargetFormation`]: the points the law steers to, for the run's pictures.
//! * [`CommandsDrag`]: a drag attitude per satellite, for satellites with drag modes.
//!
//! A law says which ones it implements with the [`capabilities!`](crate::capabilities) macro inside
//! its `impl GuidanceLaw` block: the macro writes the accessors of [`GuidanceLaw`] that hand the
//! engine the law as that capability (each returns `None` by default), so the engine's one
//! type-erased wrapper ([`super::Law`]) forwards every capability once.

use std::collections::BTreeMap;

use nalgebra::Vector3;
use serde::Serialize;

#[cfg(doc)]
use super::GuidanceLaw;
use super::{Headline, LawError, SwarmView};
use crate::swarm::DragCommand;

/// A **centralised** step: a computation that needs every satellite at once (a ground segment or an
/// elected leader), scheduled by the law itself. Laws that use it are not fully decentralised and must
/// say so.
pub trait Centralised {
    /// Whether the step is due at the control tick `time_s` \[s\].
    fn centralised_due(&self, time_s: f64) -> bool;

    /// The step, with the whole swarm (truth states, who is alive and linked), run before the state
    /// updates of a tick at which [`Centralised::centralised_due`] is `true`.
    fn centralised_update(&mut self, swarm: &SwarmView<'_>) -> Result<(), LawError>;
}

/// The law's results for `summary.json` (its `law` object) and its headline outcomes. `S` is the law's
/// per-satellite state ([`GuidanceLaw::State`]).
pub trait Reports<S> {
    /// The results, one struct per law: serialised as the `law` object of `summary.json` (keys in
    /// alphabetical order, non-finite numbers as `null`). It must serialise to a JSON object, or to
    /// `null` (an `Option`'s `None`) for no results.
    type Results: Serialize;

    /// The law's headline outcomes: keys of [`Reports::Results`] that say how well it did, with their
    /// labels, units and which way is better (`satflock compare` shows them as rows of its table, in
    /// this order). Default: none.
    fn headlines(&self) -> &'static [Headline] {
        &[]
    }

    /// The results, from the final swarm (by id) and every satellite's state (by id).
    fn results(&self, swarm: &SwarmView<'_>, states: &[S]) -> Self::Results;
}

/// [`Reports`] with its results serialised, as the engine reads it (implemented for every
/// [`Reports`]; not implemented by hand).
#[doc(hidden)]
pub trait SerialisedReports<S> {
    /// [`Reports::headlines`].
    fn report_headlines(&self) -> &'static [Headline];
    /// [`Reports::results`] as the JSON object's entries.
    fn report_json(
        &self,
        swarm: &SwarmView<'_>,
        states: &[S],
    ) -> BTreeMap<String, serde_json::Value>;
}

impl<S, R: Reports<S>> SerialisedReports<S> for R {
    fn report_headlines(&self) -> &'static [Headline] {
        self.headlines()
    }

    fn report_json(
        &self,
        swarm: &SwarmView<'_>,
        states: &[S],
    ) -> BTreeMap<String, serde_json::Value> {
        match serde_json::to_value(self.results(swarm, states)) {
            Ok(serde_json::Value::Object(map)) => map.into_iter().collect(),
            Ok(serde_json::Value::Null) => BTreeMap::new(),
            Ok(other) => panic!("a law's results must serialise to a JSON object, not {other}"),
            Err(e) => panic!("a law's results must serialise to JSON: {e}"),
        }
    }
}

/// Diagnostics columns: per-satellite outputs (trajectory columns) and swarm metrics (`metrics.csv`
/// columns). `S` is the law's per-satellite state. Both halves default to none.
pub trait Diagnostics<S> {
    /// Names of the per-satellite outputs a user may want to see (e.g. a warning mode), each with its
    /// unit or meaning; written as per-satellite columns of the trajectory. Default: none.
    fn output_names(&self) -> &'static [&'static str] {
        &[]
    }

    /// Writes the values of [`Diagnostics::output_names`] for one satellite's state into `values`.
    fn write_outputs(&self, _state: &S, _values: &mut [f64]) {}

    /// Names of the scalar metrics the law reports at every recording time (extra columns of
    /// `metrics.csv`, each name with its unit). Default: none.
    fn metric_names(&self) -> &'static [&'static str] {
        &[]
    }

    /// Called at every recording time (outside the integrator, in time order) with the truth swarm and
    /// every satellite's state (by id): writes the values of [`Diagnostics::metric_names`] into `values`
    /// (same order and length). The law may keep what it needs across calls. Default: nothing.
    fn record_metrics(&mut self, _swarm: &SwarmView<'_>, _states: &[S], _values: &mut [f64]) {}
}

/// The formation the law steers to, for the run's pictures (`scene.json`).
pub trait TargetFormation {
    /// The target as points in the Hill frame relative to the LVLH origin \[m\]: one per slot for a law
    /// with slots, or points sampled along the target curve or surface of a law with a target shape.
    /// Read after [`GuidanceLaw::initialise`]; `None` when there is none (yet).
    fn target_formation_hill_m(&self) -> Option<Vec<Vector3<f64>>>;
}

/// A drag attitude per satellite. `S` is the law's per-satellite state.
pub trait CommandsDrag<S>: Sync {
    /// The drag command of one satellite, from its state after this tick's update (the law decides its
    /// drag mode in [`GuidanceLaw::update_state`], where it keeps whatever memory the decision needs):
    /// `None` keeps the current area. The engine applies it to a satellite with drag attitudes, holds it
    /// to the next tick and keeps a mode at least the satellite's minimum dwell; a command the satellite
    /// cannot present stops the run.
    fn drag_command(&self, state: &S) -> Option<DragCommand>;
}

/// Declares the capabilities a law implements, inside its `impl GuidanceLaw` block: any of
/// `Centralised`, `Reports`, `Diagnostics`, `TargetFormation`, `CommandsDrag` (the traits of the same
/// names in [`crate::swarm`], which the law implements too).
///
/// ```ignore
/// impl GuidanceLaw for MyLaw {
///     type State = MyState;
///     type Parameters = MyParameters;
///     satflock::capabilities!(Reports, Diagnostics);
///     // name, command, set_parameters, ...
/// }
/// ```
#[macro_export]
macro_rules! capabilities {
    ($($capability:ident),* $(,)?) => {
        $($crate::capabilities!(@one $capability);)*
    };
    (@one Centralised) => {
        fn as_centralised(&mut self) -> Option<&mut dyn $crate::swarm::Centralised> {
            Some(self)
        }
    };
    (@one Reports) => {
        fn as_reports(&self) -> Option<&dyn $crate::swarm::SerialisedReports<Self::State>> {
            Some(self)
        }
    };
    (@one Diagnostics) => {
        fn as_diagnostics(&self) -> Option<&dyn $crate::swarm::Diagnostics<Self::State>> {
            Some(self)
        }
        fn as_diagnostics_mut(
            &mut self,
        ) -> Option<&mut dyn $crate::swarm::Diagnostics<Self::State>> {
            Some(self)
        }
    };
    (@one TargetFormation) => {
        fn as_target_formation(&self) -> Option<&dyn $crate::swarm::TargetFormation> {
            Some(self)
        }
    };
    (@one CommandsDrag) => {
        fn as_commands_drag(&self) -> Option<&dyn $crate::swarm::CommandsDrag<Self::State>> {
            Some(self)
        }
    };
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;
    use serde::Serialize;

    use super::Reports;
    use crate::swarm::law::test_swarm::{grid_of, random_swarm, view};
    use crate::swarm::{
        Better, GuidanceLaw, Headline, Law, LawContext, LawError, SatelliteView, SwarmView,
    };

    /// A law with only the core, and one that reports (typed results, `None` when told to).
    struct Plain;
    struct Reporting {
        none: bool,
    }

    /// Fields deliberately out of alphabetical order, one of them non-finite.
    #[derive(Serialize)]
    struct Counted {
        zeta_count: usize,
        alpha_m: f64,
        not_a_number: f64,
        nested: [Option<f64>; 2],
    }

    macro_rules! core {
        ($name:literal) => {
            type State = ();
            type Parameters = ();
            fn name(&self) -> &'static str {
                $name
            }
            fn command(&self, _: &SatelliteView<'_>, _: &(), _: &LawContext) -> Vector3<f64> {
                Vector3::zeros()
            }
            fn set_parameters(&mut self, _: &()) -> Result<(), LawError> {
                Ok(())
            }
        };
    }
    impl GuidanceLaw for Plain {
        core!("plain");
    }
    impl GuidanceLaw for Reporting {
        core!("reporting");
        crate::capabilities!(Reports);
    }
    impl Reports<()> for Reporting {
        type Results = Option<Counted>;
        fn headlines(&self) -> &'static [Headline] {
            const HEADLINES: &[Headline] = &[Headline::new("alpha_m", "alpha", "m", Better::Lower)];
            HEADLINES
        }
        fn results(&self, swarm: &SwarmView<'_>, _: &[()]) -> Option<Counted> {
            (!self.none).then(|| Counted {
                zeta_count: swarm.len(),
                alpha_m: 1.5,
                not_a_number: f64::NAN,
                nested: [Some(2.0), None],
            })
        }
    }

    /// A law without capabilities has none of them; a reporting law's typed results reach the summary
    /// as the JSON object of their fields, sorted by key, non-finite as null, and `None` as no results.
    #[test]
    fn capabilities_reach_the_engine_only_when_declared() {
        let states = random_swarm(5);
        let (masses_kg, flags) = (vec![1.0; 5], vec![true; 5]);
        let grid = grid_of(&states);
        let swarm = view(&states, &masses_kg, &flags, &flags, &grid, 0.0);

        let mut plain = Law::new(Plain);
        plain.initialise(&swarm, None).unwrap();
        assert!(plain.headlines().is_empty() && plain.output_names().is_empty());
        assert!(plain.metric_names().is_empty() && !plain.commands_drag());
        assert!(plain.target_formation_hill_m().is_none() && !plain.centralised_due(0.0));
        assert!(plain.results(&swarm, None).is_empty());
        assert!(!plain.drag_commands(&mut [None; 5]));

        let mut reporting = Law::new(Reporting { none: false });
        reporting.initialise(&swarm, None).unwrap();
        assert_eq!(reporting.headlines()[0].name, "alpha_m");
        let results = reporting.results(&swarm, None);
        assert_eq!(
            serde_json::to_string(&results).unwrap(),
            r#"{"alpha_m":1.5,"nested":[2.0,null],"not_a_number":null,"zeta_count":5}"#
        );
        let mut none = Law::new(Reporting { none: true });
        none.initialise(&swarm, None).unwrap();
        assert!(none.results(&swarm, None).is_empty());
    }
}
