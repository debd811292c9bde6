//! The `equilibrium-shaping` law's results (`summary.json` `law`) and headline outcomes: the
//! strategy and its fields (the Eq. 4 attractions or the ES solution), the final formation error and
//! miss distance, and every satellite's mode, distances, stored warning and timeline of switches.

use nalgebra::Vector3;
use serde::Serialize;

use super::desired::{self, FieldSet};
use super::{shaping, EquilibriumShaping, EsState, Formation, ModeEvent, MAX_LISTED_NODES};
use crate::swarm::{Better, Headline, Reports, SwarmView};

/// The law's results.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EquilibriumShapingResults {
    /// The strategy, as written in scenario files.
    pub es_strategy: &'static str,
    /// The formation: `rhombus`, `hexagon` or `custom`.
    pub es_formation: &'static str,
    /// The nodes ξ_i, Hill \[m\] (satellite i ↔ node i).
    pub es_nodes_hill_m: Vec<[f64; 3]>,
    /// The Eq. 4 attraction of every node pair (strategies with the pair field, up to
    /// [`MAX_LISTED_NODES`] nodes; absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub es_pair_attraction: Option<Vec<EsPairAttraction>>,
    /// The equilibrium-shaping solution of the avoid field (absent for strategies without it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub es_avoid: Option<EsAvoidResults>,
    /// The field's fastest rate at the nodes \[1/s\].
    pub es_field_rate_at_nodes_per_s: f64,
    /// Final formation error \[m\].
    pub es_formation_error_m: f64,
    /// Final centroid displacement \[m\].
    pub es_centroid_displacement_m: f64,
    /// Smallest satellite–threat distance over the recordings \[m\] (null without the law's threat).
    pub es_min_threat_distance_m: Option<f64>,
    /// Every satellite (up to the node count), by id.
    pub es_satellites: Vec<EsSatelliteResults>,
}

/// The Eq. 4 attraction of one node pair.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EsPairAttraction {
    /// The two nodes.
    pub pair: [usize; 2],
    /// Their distance \[m\].
    pub distance_m: f64,
    /// The attraction a_ij \[1/s\].
    pub a_per_s: f64,
}

/// The equilibrium-shaping solution of the avoid field.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EsAvoidResults {
    /// The coefficient of every pair.
    pub coefficients: Vec<EsCoefficient>,
    /// Residual of the least-squares solution \[m/s\].
    pub residual_mps: f64,
    /// Norm of its right-hand side \[m/s\].
    pub rhs_norm_mps: f64,
    /// Rank of the system.
    pub rank: usize,
    /// Number of unknowns (pairs).
    pub unknowns: usize,
    /// Condition number of the system.
    pub condition_number: f64,
    /// Whether a coefficient is negative (a repulsive pair).
    pub negative_coefficients: bool,
    /// Whether the system is ill-conditioned.
    pub ill_conditioned: bool,
}

/// One pair's coefficient of the avoid field.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EsCoefficient {
    /// The two nodes.
    pub pair: [usize; 2],
    /// Their distance \[m\].
    pub distance_m: f64,
    /// The coefficient b_ij \[1/s\].
    pub b_per_s: f64,
}

/// One satellite's results.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EsSatelliteResults {
    /// The satellite's id.
    pub id: usize,
    /// Whether it is alive.
    pub active: bool,
    /// Its final mode ([`super::Mode::name`]).
    pub mode: &'static str,
    /// Distance to its node \[m\].
    pub node_distance_m: f64,
    /// Distance to its node shifted by the live satellites' mean offset from their nodes \[m\].
    pub node_distance_about_centroid_m: f64,
    /// Speed relative to the LVLH frame \[m/s\].
    pub speed_mps: f64,
    /// The warning it stored (null if never warned).
    pub warning: Option<EsWarningResults>,
    /// Its mode switches and threat sightings, in time order.
    pub timeline: Vec<EsTimelineEntry>,
}

/// A satellite's stored warning.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EsWarningResults {
    /// t_w \[s\].
    pub warned_at_s: f64,
    /// Virtual sensing radius R_s,i \[m\].
    pub virtual_sensing_radius_m: f64,
    /// K_i \[m²\].
    pub width_m2: f64,
    /// The escape direction, Hill unit vector.
    pub escape_direction_hill: [f64; 3],
}

/// One entry of a satellite's timeline.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EsTimelineEntry {
    /// When \[s\].
    pub time_s: f64,
    /// `mode`, `threat-sensed` or `threat-lost`.
    pub event: &'static str,
    /// The mode left (a `mode` event only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub from: Option<&'static str>,
    /// The mode entered (a `mode` event only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub to: Option<&'static str>,
}

fn components(v: &Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

impl Reports<EsState> for EquilibriumShaping {
    type Results = EquilibriumShapingResults;

    fn headlines(&self) -> &'static [Headline] {
        const HEADLINES: &[Headline] = &[
            Headline::new(
                "es_formation_error_m",
                "final formation error",
                "m",
                Better::Lower,
            ),
            Headline::new(
                "es_min_threat_distance_m",
                "miss distance to its threat",
                "m",
                Better::Higher,
            ),
        ];
        HEADLINES
    }

    /// `es_strategy`, `es_formation`, `es_nodes_hill_m`, the Eq. 4 attractions (`es_pair_attraction`, up
    /// to [`MAX_LISTED_NODES`] nodes) or the ES solution (`es_avoid`: coefficients, residual, rank,
    /// condition number, warnings),
    /// `es_field_rate_at_nodes_per_s`, final `es_formation_error_m` and `es_centroid_displacement_m`,
    /// `es_min_threat_distance_m` (over the recordings), and `es_satellites`: per satellite its mode,
    /// distance to its node and to its node relative to the centroid, speed, the stored warning
    /// (t_w, virtual sensing radius, K_i, escape direction) and its timeline of switches.
    fn results(&self, swarm: &SwarmView<'_>, states: &[EsState]) -> EquilibriumShapingResults {
        let p = &self.parameters;
        let t = &self.tables;
        let n = t.nodes_m.len();
        let fields = desired::fields_of(p.strategy);
        let es_pair_attraction = (fields.iter().any(|(s, _)| *s == FieldSet::Pair)
            && n <= MAX_LISTED_NODES)
            .then(|| {
                shaping::all_pairs(n)
                    .into_iter()
                    .map(|(i, j)| {
                        let delta = t.distance_m(i, j);
                        EsPairAttraction {
                            pair: [i, j],
                            distance_m: delta,
                            a_per_s: shaping::pair_attraction_per_s(
                                delta,
                                p.pair_b_per_s,
                                p.pair_c_m2,
                            ),
                        }
                    })
                    .collect()
            });
        let es_avoid = self.avoid.as_ref().map(|s| EsAvoidResults {
            coefficients: s
                .pairs
                .iter()
                .zip(&s.coefficients_per_s)
                .map(|(&(i, j), &b)| EsCoefficient {
                    pair: [i, j],
                    distance_m: t.distance_m(i, j),
                    b_per_s: b,
                })
                .collect(),
            residual_mps: s.residual,
            rhs_norm_mps: s.rhs_norm,
            rank: s.rank,
            unknowns: s.pairs.len(),
            condition_number: s.condition_number,
            negative_coefficients: s.has_negative_coefficients(),
            ill_conditioned: s.is_ill_conditioned(),
        });
        let (error, displacement) = self.formation_error(swarm);
        let live: Vec<usize> = (0..swarm.len().min(n))
            .filter(|i| swarm.active[*i])
            .collect();
        let centroid_shift = if live.is_empty() {
            Vector3::zeros()
        } else {
            live.iter()
                .map(|i| swarm.relative_states[*i].position_m - t.nodes_m[*i])
                .sum::<Vector3<f64>>()
                / live.len() as f64
        };
        let es_satellites = states
            .iter()
            .enumerate()
            .take(n)
            .map(|(i, s)| {
                let state = swarm.relative_states[i];
                let offset = state.position_m - t.nodes_m[i];
                let timeline = s
                    .timeline
                    .iter()
                    .map(|c| {
                        let (event, from, to) = match c.event {
                            ModeEvent::Mode { from, to } => {
                                ("mode", Some(from.name()), Some(to.name()))
                            }
                            ModeEvent::ThreatSensed => ("threat-sensed", None, None),
                            ModeEvent::ThreatLost => ("threat-lost", None, None),
                        };
                        EsTimelineEntry {
                            time_s: c.time_s,
                            event,
                            from,
                            to,
                        }
                    })
                    .collect();
                EsSatelliteResults {
                    id: i,
                    active: swarm.active[i],
                    mode: s.mode.name(),
                    node_distance_m: offset.norm(),
                    node_distance_about_centroid_m: (offset - centroid_shift).norm(),
                    speed_mps: state.velocity_mps.norm(),
                    warning: s.warning.map(|w| EsWarningResults {
                        warned_at_s: w.warned_at_s,
                        virtual_sensing_radius_m: w.virtual_sensing_radius_m,
                        width_m2: w.width_m2,
                        escape_direction_hill: components(&w.escape_direction_hill),
                    }),
                    timeline,
                }
            })
            .collect();
        EquilibriumShapingResults {
            es_strategy: p.strategy.name(),
            es_formation: match p.formation {
                Formation::Rhombus => "rhombus",
                Formation::Hexagon => "hexagon",
                Formation::Custom => "custom",
            },
            es_nodes_hill_m: t.nodes_m.iter().map(components).collect(),
            es_pair_attraction,
            es_avoid,
            es_field_rate_at_nodes_per_s: self.field_rate_per_s,
            es_formation_error_m: error,
            es_centroid_displacement_m: displacement,
            es_min_threat_distance_m: self
                .min_threat_distance_m
                .is_finite()
                .then_some(self.min_threat_distance_m),
            es_satellites,
        }
    }
}
