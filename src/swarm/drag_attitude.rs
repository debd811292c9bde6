//! Drag as an actuator: a satellite whose drag area a guidance law may command (by attitude), its
//! limits, and the command a law gives.
//!
//! A satellite flies in one of a few **drag modes** (attitudes), each with its drag reference area, or
//! at any area within a range. A law commands a mode or an area ([`DragCommand`]) through its state
//! ([`crate::swarm::CommandsDrag::drag_command`]); the engine applies it at the control tick, holds it
//! until the next, keeps a mode at least [`DragAttitudes::min_dwell_s`] before switching again, counts
//! the switches, and records the area. Changing the area changes only the drag the force set computes:
//! no propellant is spent, so the thrust Δv ledger is not touched.

use thiserror::Error;

/// Largest number of named drag modes a satellite may have.
pub const MAX_DRAG_MODES: usize = 4;

/// The drag areas a satellite can present.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DragAttitudes {
    /// The mode areas \[m^2\], ascending (the first `mode_count` entries); for a continuous range, its
    /// two ends.
    areas_m2: [f64; MAX_DRAG_MODES],
    /// How many modes (2 for a continuous range: its ends).
    mode_count: usize,
    /// Whether any area between the ends may be commanded.
    continuous: bool,
    /// Shortest time between two changes of the area \[s\] (0: none).
    pub min_dwell_s: f64,
}

/// What a law commands of a satellite's drag.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DragCommand {
    /// The mode of smallest area.
    Minimum,
    /// The mode of largest area.
    Maximum,
    /// The mode of that index, modes in ascending area.
    Mode(usize),
    /// An area \[m^2\]: clamped to the range of a continuous satellite; the nearest mode's area for a
    /// satellite with discrete modes.
    Area(f64),
}

/// Drag attitudes that cannot be used.
#[derive(Clone, Debug, Error, PartialEq)]
#[non_exhaustive]
pub enum DragAttitudeError {
    /// An area is not finite and positive.
    #[error("drag mode area {area_m2} m^2 is not finite and > 0")]
    BadArea {
        /// The area \[m^2\].
        area_m2: f64,
    },
    /// Fewer than one or more than [`MAX_DRAG_MODES`] modes.
    #[error("{count} drag modes (allowed: 1 to {MAX_DRAG_MODES})")]
    ModeCount {
        /// How many were given.
        count: usize,
    },
    /// Two modes with the same area.
    #[error("two drag modes have the same area {area_m2} m^2")]
    DuplicateArea {
        /// The area \[m^2\].
        area_m2: f64,
    },
    /// A continuous range whose ends are not ordered.
    #[error("drag area range [{min_m2}, {max_m2}] m^2 is not ordered (min < max)")]
    Range {
        /// Lower end \[m^2\].
        min_m2: f64,
        /// Upper end \[m^2\].
        max_m2: f64,
    },
    /// A negative or non-finite dwell time.
    #[error("minimum dwell {dwell_s} s is not finite and >= 0")]
    Dwell {
        /// The dwell time \[s\].
        dwell_s: f64,
    },
}

fn check_area(area_m2: f64) -> Result<(), DragAttitudeError> {
    if area_m2.is_finite() && area_m2 > 0.0 {
        Ok(())
    } else {
        Err(DragAttitudeError::BadArea { area_m2 })
    }
}

fn check_dwell(dwell_s: f64) -> Result<(), DragAttitudeError> {
    if dwell_s.is_finite() && dwell_s >= 0.0 {
        Ok(())
    } else {
        Err(DragAttitudeError::Dwell { dwell_s })
    }
}

impl DragAttitudes {
    /// Discrete modes of the given areas \[m^2\] (any order; stored ascending).
    pub fn modes(areas_m2: &[f64], min_dwell_s: f64) -> Result<Self, DragAttitudeError> {
        if areas_m2.is_empty() || areas_m2.len() > MAX_DRAG_MODES {
            return Err(DragAttitudeError::ModeCount {
                count: areas_m2.len(),
            });
        }
        areas_m2.iter().try_for_each(|a| check_area(*a))?;
        check_dwell(min_dwell_s)?;
        let mut areas = [0.0; MAX_DRAG_MODES];
        areas[..areas_m2.len()].copy_from_slice(areas_m2);
        areas[..areas_m2.len()].sort_by(f64::total_cmp);
        if let Some(w) = areas[..areas_m2.len()].windows(2).find(|w| w[0] == w[1]) {
            return Err(DragAttitudeError::DuplicateArea { area_m2: w[0] });
        }
        Ok(Self {
            areas_m2: areas,
            mode_count: areas_m2.len(),
            continuous: false,
            min_dwell_s,
        })
    }

    /// Any area in `[min_m2, max_m2]`.
    pub fn range(min_m2: f64, max_m2: f64, min_dwell_s: f64) -> Result<Self, DragAttitudeError> {
        check_area(min_m2)?;
        check_area(max_m2)?;
        check_dwell(min_dwell_s)?;
        if min_m2 >= max_m2 {
            return Err(DragAttitudeError::Range { min_m2, max_m2 });
        }
        let mut areas = [0.0; MAX_DRAG_MODES];
        areas[0] = min_m2;
        areas[1] = max_m2;
        Ok(Self {
            areas_m2: areas,
            mode_count: 2,
            continuous: true,
            min_dwell_s,
        })
    }

    /// The mode areas, ascending \[m^2\] (a continuous range: its two ends).
    pub fn areas_m2(&self) -> &[f64] {
        &self.areas_m2[..self.mode_count]
    }

    /// Whether any area of the range may be commanded.
    pub fn is_continuous(&self) -> bool {
        self.continuous
    }

    /// The smallest area \[m^2\].
    pub fn min_area_m2(&self) -> f64 {
        self.areas_m2[0]
    }

    /// The largest area \[m^2\].
    pub fn max_area_m2(&self) -> f64 {
        self.areas_m2[self.mode_count - 1]
    }

    /// The modes or the range, as text for messages (`0.01 or 0.035 m^2`, `0.01 to 0.035 m^2`).
    pub fn describe(&self) -> String {
        if self.continuous {
            format!("{} to {} m^2", self.min_area_m2(), self.max_area_m2())
        } else {
            let areas: Vec<String> = self.areas_m2().iter().map(|a| a.to_string()).collect();
            format!("{} m^2", areas.join(" or "))
        }
    }

    /// Whether `area_m2` is one this satellite can present.
    pub fn admits(&self, area_m2: f64) -> bool {
        if self.continuous {
            (self.min_area_m2()..=self.max_area_m2()).contains(&area_m2)
        } else {
            self.areas_m2().contains(&area_m2)
        }
    }

    /// The area a command asks for \[m^2\], within the satellite's limits (`None`: a mode index the
    /// satellite does not have, or a non-finite area).
    pub fn area_of(&self, command: DragCommand) -> Option<f64> {
        match command {
            DragCommand::Minimum => Some(self.min_area_m2()),
            DragCommand::Maximum => Some(self.max_area_m2()),
            DragCommand::Mode(k) => self.areas_m2().get(k).copied(),
            DragCommand::Area(a) if !a.is_finite() => None,
            DragCommand::Area(a) if self.continuous => {
                Some(a.clamp(self.min_area_m2(), self.max_area_m2()))
            }
            DragCommand::Area(a) => self
                .areas_m2()
                .iter()
                .copied()
                .min_by(|x, y| (x - a).abs().total_cmp(&(y - a).abs())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modes_are_sorted_and_commands_resolve_within_the_limits() {
        let d = DragAttitudes::modes(&[0.035, 0.01], 60.0).unwrap();
        assert_eq!(d.areas_m2(), &[0.01, 0.035]);
        assert_eq!(d.area_of(DragCommand::Minimum), Some(0.01));
        assert_eq!(d.area_of(DragCommand::Maximum), Some(0.035));
        assert_eq!(d.area_of(DragCommand::Mode(1)), Some(0.035));
        assert_eq!(d.area_of(DragCommand::Mode(2)), None);
        assert_eq!(d.area_of(DragCommand::Area(0.03)), Some(0.035));
        assert_eq!(d.area_of(DragCommand::Area(f64::NAN)), None);
        assert!(d.admits(0.01) && !d.admits(0.02));
        let r = DragAttitudes::range(0.01, 0.035, 0.0).unwrap();
        assert_eq!(r.area_of(DragCommand::Area(0.02)), Some(0.02));
        assert_eq!(r.area_of(DragCommand::Area(1.0)), Some(0.035));
        assert!(r.admits(0.02) && !r.admits(0.04));
    }

    #[test]
    fn unusable_attitudes_are_refused_with_their_values() {
        assert!(matches!(
            DragAttitudes::modes(&[0.01, -0.1], 0.0),
            Err(DragAttitudeError::BadArea { area_m2 }) if area_m2 == -0.1
        ));
        assert!(matches!(
            DragAttitudes::modes(&[], 0.0),
            Err(DragAttitudeError::ModeCount { count: 0 })
        ));
        assert!(matches!(
            DragAttitudes::modes(&[0.01, 0.01], 0.0),
            Err(DragAttitudeError::DuplicateArea { .. })
        ));
        assert!(matches!(
            DragAttitudes::range(0.03, 0.01, 0.0),
            Err(DragAttitudeError::Range { .. })
        ));
        assert!(matches!(
            DragAttitudes::modes(&[0.01], -1.0),
            Err(DragAttitudeError::Dwell { .. })
        ));
    }
}
