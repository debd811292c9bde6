//! The engine's one per-satellite table ([`Satellites`]): what changes only through events and drag
//! commands (the [`Fleet`]: masses and physical properties, radii, actuators, drag attitudes, flags,
//! the storage order) and what the run loop rewrites (truth relative states, applied and held commands,
//! the commands before the actuator when the control history is recorded, the drag-mode bookkeeping),
//! every column in the engine's
//! storage order, permuted as a whole by the storage re-sort ([`Satellites::permute`], whose exhaustive
//! destructuring makes a new column fail to compile until it is permuted too). Read by id through
//! [`Fleet::order`].

use nalgebra::Vector3;
use rayon::prelude::*;

use crate::dynamics::PhysicalProperties;
use crate::orbit::RelativeStateHill;
use crate::swarm::actuator::Actuator;
use crate::swarm::drag_attitude::DragAttitudes;
use crate::swarm::simulation::config::SatelliteInit;
use crate::swarm::storage_order::{Moves, StorageOrder};
use crate::swarm::CHUNK;

/// Per-satellite properties that change only through events, as structure-of-arrays.
pub(in crate::swarm::simulation) struct Fleet {
    pub masses_kg: Vec<f64>,
    /// What force models read besides the mass (drag and SRP areas and coefficients): one entry for
    /// the whole fleet when every satellite has the same and none has drag attitudes (no area can
    /// change), else one per satellite ([`Fleet::surfaces_of`]).
    pub surfaces: Vec<Surfaces>,
    pub radii_m: Vec<f64>,
    pub actuators: Vec<Actuator>,
    /// The drag areas a law may command (`None`: fixed area); empty when no satellite has drag
    /// attitudes, as are the drag columns of [`Satellites`].
    pub drag_attitudes: Vec<Option<DragAttitudes>>,
    /// `false` once a satellite is removed.
    pub active: Vec<bool>,
    /// `false` while a satellite's links are cut.
    pub links_up: Vec<bool>,
    /// The storage order of these and of every per-satellite array of the simulation.
    pub order: StorageOrder,
}

/// A satellite's physical properties besides its mass (kept apart so that the views read the masses as
/// one slice); [`Fleet::properties`] puts them together.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(in crate::swarm::simulation) struct Surfaces {
    drag_area_m2: f64,
    drag_coefficient: f64,
    srp_area_m2: f64,
    reflectivity_coefficient: f64,
}

impl Surfaces {
    /// The physical properties of a satellite of mass `mass_kg` \[kg\] with these surfaces.
    #[inline]
    fn with_mass(&self, mass_kg: f64) -> PhysicalProperties {
        PhysicalProperties {
            mass_kg,
            drag_area_m2: self.drag_area_m2,
            drag_coefficient: self.drag_coefficient,
            srp_area_m2: self.srp_area_m2,
            reflectivity_coefficient: self.reflectivity_coefficient,
        }
    }

    pub fn of(p: &PhysicalProperties) -> Self {
        Self {
            drag_area_m2: p.drag_area_m2,
            drag_coefficient: p.drag_coefficient,
            srp_area_m2: p.srp_area_m2,
            reflectivity_coefficient: p.reflectivity_coefficient,
        }
    }
}

impl Fleet {
    /// The surfaces of every satellite, in id order: one entry for the fleet when they are all the
    /// same and `areas_fixed` (no drag attitudes), else one per satellite.
    pub fn surfaces_of(
        properties: impl Iterator<Item = PhysicalProperties>,
        areas_fixed: bool,
    ) -> Vec<Surfaces> {
        let mut surfaces: Vec<Surfaces> = properties.map(|p| Surfaces::of(&p)).collect();
        if areas_fixed && surfaces.windows(2).all(|w| w[0] == w[1]) {
            surfaces.truncate(1);
            surfaces.shrink_to_fit();
        }
        surfaces
    }

    /// The surfaces of the satellite at storage index `index`.
    #[inline]
    fn surfaces(&self, index: usize) -> &Surfaces {
        match self.surfaces.as_slice() {
            [fleet] => fleet,
            each => &each[index],
        }
    }

    /// Every satellite's drag term `C_d A / m` \[m^2/kg\] by storage index into `out` (one entry per
    /// satellite), by [`PhysicalProperties::drag_area_per_mass_m2_per_kg`]: in parallel over fixed
    /// chunks of plain loops (with one surfaces entry for the fleet, its `C_d A` is the same constant
    /// over each mass).
    pub fn drag_areas_per_mass_into(&self, out: &mut [f64]) {
        let chunks = out
            .par_chunks_mut(CHUNK)
            .zip(self.masses_kg.par_chunks(CHUNK))
            .enumerate();
        match self.surfaces.as_slice() {
            [fleet] => chunks.for_each(|(_, (out, masses_kg))| {
                for (out, mass_kg) in out.iter_mut().zip(masses_kg) {
                    *out = fleet.with_mass(*mass_kg).drag_area_per_mass_m2_per_kg();
                }
            }),
            each => chunks.for_each(|(chunk, (out, masses_kg))| {
                let surfaces = &each[chunk * CHUNK..];
                for ((out, mass_kg), s) in out.iter_mut().zip(masses_kg).zip(surfaces) {
                    *out = s.with_mass(*mass_kg).drag_area_per_mass_m2_per_kg();
                }
            }),
        }
    }

    /// The drag area of the satellite at storage index `index` \[m^2\].
    #[inline]
    pub fn drag_area_m2(&self, index: usize) -> f64 {
        self.surfaces(index).drag_area_m2
    }

    /// Sets the drag area of the satellite at storage index `index` \[m^2\] (a drag command: the
    /// fleet has drag attitudes, so one surface entry per satellite).
    #[inline]
    pub fn set_drag_area_m2(&mut self, index: usize, area_m2: f64) {
        self.surfaces[index].drag_area_m2 = area_m2;
    }

    /// The physical properties of the satellite at storage index `index`.
    #[inline]
    pub fn properties(&self, index: usize) -> PhysicalProperties {
        self.surfaces(index).with_mass(self.masses_kg[index])
    }
}

impl Fleet {
    /// The fleet of `satellites` at t = 0, in id order.
    pub fn new(satellites: &[SatelliteInit]) -> Self {
        let n = satellites.len();
        Self {
            masses_kg: satellites.iter().map(|s| s.properties.mass_kg).collect(),
            surfaces: Fleet::surfaces_of(
                satellites.iter().map(|s| s.properties),
                satellites.iter().all(|s| s.drag_attitudes.is_none()),
            ),
            radii_m: satellites.iter().map(|s| s.radius_m).collect(),
            actuators: satellites.iter().map(|s| s.actuator).collect(),
            drag_attitudes: if satellites.iter().any(|s| s.drag_attitudes.is_some()) {
                satellites.iter().map(|s| s.drag_attitudes).collect()
            } else {
                Vec::new()
            },
            active: vec![true; n],
            links_up: vec![true; n],
            order: StorageOrder::identity(n),
        }
    }
}

/// Every per-satellite column of the simulation that the run loop owns, in storage order.
pub(in crate::swarm::simulation) struct Satellites {
    /// What changes only through events.
    pub fleet: Fleet,
    /// Truth relative states at the simulation's time, Hill frame (refreshed after every segment).
    pub truth: Vec<RelativeStateHill>,
    /// Applied command of the tick, Hill frame (acceleration \[m/s^2\], or velocity \[m/s\]
    /// kinematic).
    pub applied_hill: Vec<Vector3<f64>>,
    /// The law's command of the tick before the actuator, Hill frame \[m/s^2\]: recorded for the
    /// control history only (empty otherwise, and never read by the dynamics).
    pub commanded_hill: Vec<Vector3<f64>>,
    /// Held command in the dynamics frame (ECI or Hill), sampled mode, process noise included.
    pub held_control: Vec<Vector3<f64>>,
    /// When each satellite's drag area last changed \[s\] (−∞: never), for the minimum dwell. This
    /// and the two drag columns below are empty when no satellite has drag attitudes.
    pub drag_changed_s: Vec<f64>,
    /// How many times each satellite's drag area changed.
    pub drag_switches: Vec<u64>,
    /// ∫‖a_drag‖dt of each satellite with drag attitudes \[m/s\] (left-point sum at the control ticks:
    /// not propellant, kept apart from the thrust ledger).
    pub drag_delta_v_mps: Vec<f64>,
    /// Whether the applied, commanded and held commands are all zero (so a law that commands nothing
    /// need not write them): not a column, and unchanged by a permutation.
    pub commands_zero: bool,
}

impl Satellites {
    /// The table of `satellites` at t = 0 (truth computed by the caller).
    pub fn new(satellites: &[SatelliteInit]) -> Self {
        let n = satellites.len();
        let fleet = Fleet::new(satellites);
        let drag_n = if fleet.drag_attitudes.is_empty() {
            0
        } else {
            n
        };
        Self {
            fleet,
            truth: vec![RelativeStateHill::default(); n],
            applied_hill: vec![Vector3::zeros(); n],
            commanded_hill: Vec::new(),
            held_control: vec![Vector3::zeros(); n],
            drag_changed_s: vec![f64::NEG_INFINITY; drag_n],
            drag_switches: vec![0; drag_n],
            drag_delta_v_mps: vec![0.0; drag_n],
            commands_zero: true,
        }
    }

    /// Sets every applied, commanded and held command to zero.
    pub fn zero_commands(&mut self) {
        for column in [
            &mut self.applied_hill,
            &mut self.commanded_hill,
            &mut self.held_control,
        ] {
            column.fill(Vector3::zeros());
        }
        self.commands_zero = true;
    }

    /// Moves every column to the storage order in which new index `k` holds old index `moves[k]`.
    pub fn permute(&mut self, moves: &Moves) {
        // Exhaustive destructuring, no `..`: a column added to the table must be permuted here.
        let Satellites {
            fleet:
                Fleet {
                    masses_kg,
                    surfaces,
                    radii_m,
                    actuators,
                    drag_attitudes,
                    active,
                    links_up,
                    order,
                },
            truth,
            applied_hill,
            commanded_hill,
            held_control,
            drag_changed_s,
            drag_switches,
            drag_delta_v_mps,
            commands_zero: _,
        } = self;
        // Each array on its own: the arrays move in parallel.
        rayon::scope(|scope| {
            scope.spawn(|_| moves.apply(masses_kg));
            if surfaces.len() > 1 {
                scope.spawn(|_| moves.apply(surfaces));
            }
            scope.spawn(|_| moves.apply(radii_m));
            scope.spawn(|_| moves.apply(actuators));
            if !drag_attitudes.is_empty() {
                scope.spawn(|_| moves.apply(drag_attitudes));
                scope.spawn(|_| moves.apply(drag_changed_s));
                scope.spawn(|_| moves.apply(drag_switches));
                scope.spawn(|_| moves.apply(drag_delta_v_mps));
            }
            scope.spawn(|_| moves.apply(active));
            scope.spawn(|_| moves.apply(links_up));
            scope.spawn(|_| moves.apply(truth));
            scope.spawn(|_| moves.apply(applied_hill));
            if !commanded_hill.is_empty() {
                scope.spawn(|_| moves.apply(commanded_hill));
            }
            scope.spawn(|_| moves.apply(held_control));
            scope.spawn(|_| order.apply(moves));
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn with_area(drag_area_m2: f64) -> PhysicalProperties {
        PhysicalProperties {
            mass_kg: 10.0,
            drag_area_m2,
            drag_coefficient: 2.2,
            srp_area_m2: 0.5,
            reflectivity_coefficient: 1.3,
        }
    }

    /// One surfaces entry for a fleet of equal satellites whose areas cannot change; one per satellite
    /// otherwise; and every satellite's properties read back as given either way.
    #[test]
    fn surfaces_are_kept_once_only_for_a_fleet_of_equal_fixed_satellites() {
        let equal = [with_area(0.1); 5];
        let mixed = [0.1, 0.1, 0.3, 0.1, 0.1].map(with_area);
        for (properties, areas_fixed, entries) in [
            (&equal, true, 1),
            (&equal, false, 5),
            (&mixed, true, 5),
            (&mixed, false, 5),
        ] {
            let mut fleet = Fleet {
                masses_kg: properties.iter().map(|p| p.mass_kg).collect(),
                surfaces: Fleet::surfaces_of(properties.iter().copied(), areas_fixed),
                radii_m: vec![0.0; 5],
                actuators: Vec::new(),
                drag_attitudes: Vec::new(),
                active: vec![true; 5],
                links_up: vec![true; 5],
                order: StorageOrder::identity(5),
            };
            assert_eq!(fleet.surfaces.len(), entries);
            for (i, p) in properties.iter().enumerate() {
                assert_eq!(fleet.properties(i), *p);
            }
            // Masses of their own, so that the drag terms differ.
            fleet.masses_kg = vec![10.0, 3.0, 7.5, 11.0, 0.9];
            let drag_terms_agree = |fleet: &Fleet| {
                let mut terms = vec![f64::NAN; 5];
                fleet.drag_areas_per_mass_into(&mut terms);
                for (i, term) in terms.iter().enumerate() {
                    let want = fleet.properties(i).drag_area_per_mass_m2_per_kg();
                    assert_eq!(term.to_bits(), want.to_bits(), "satellite {i}");
                }
            };
            drag_terms_agree(&fleet);
            if !areas_fixed {
                fleet.set_drag_area_m2(3, 0.7);
                assert_eq!(fleet.drag_area_m2(3), 0.7);
                assert_eq!(fleet.drag_area_m2(2), properties[2].drag_area_m2);
                drag_terms_agree(&fleet);
            }
        }
    }
}
