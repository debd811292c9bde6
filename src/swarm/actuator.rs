//! Actuator model: what a satellite's thrusters can deliver of a commanded acceleration — saturation
//! (per LVLH axis or in norm) and thruster failures. The delta-v ledger that integrates the applied
//! acceleration lives in the swarm state (see [`super::state`]).

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// How the acceleration limit applies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum LimitKind {
    /// ‖a‖ ≤ limit: the command is scaled down along its own direction.
    #[default]
    Norm,
    /// |a_k| ≤ limit on each Hill axis: each component is clipped.
    PerAxis,
}

/// One satellite's thrusters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Actuator {
    /// Acceleration limit \[m/s^2\]; `f64::INFINITY` for an unlimited actuator.
    pub max_accel_m_s2: f64,
    /// How the limit applies.
    pub limit: LimitKind,
    /// Working thrust axes (Hill x, y, z); a failed axis delivers nothing.
    pub working_axes: [bool; 3],
}

impl Actuator {
    /// An actuator with all axes working.
    pub fn new(max_accel_m_s2: f64, limit: LimitKind) -> Self {
        Self {
            max_accel_m_s2,
            limit,
            working_axes: [true; 3],
        }
    }

    /// The acceleration actually applied for a commanded one, Hill frame \[m/s^2\]: failed axes zeroed,
    /// then the limit applied. A command with a non-finite component, or (norm limit) whose norm
    /// overflows (above about 1e154 m/s^2), is returned as it is, never saturated to zero or to the
    /// limit: the engine refuses it ([`crate::swarm::SimError::BadCommand`]).
    #[inline]
    pub fn apply(&self, commanded_hill_m_s2: &Vector3<f64>) -> Vector3<f64> {
        if self.max_accel_m_s2 == f64::INFINITY && self.working_axes == [true; 3] {
            // Nothing to apply: no norm exceeds an infinite limit, and clamping to ±infinity keeps
            // every value (a NaN too). Skips the norm's square root on the common unlimited actuator.
            return *commanded_hill_m_s2;
        }
        let mut a = *commanded_hill_m_s2;
        for k in 0..3 {
            if !self.working_axes[k] {
                a[k] = 0.0;
            }
        }
        let limit = self.max_accel_m_s2;
        match self.limit {
            LimitKind::Norm => {
                let norm = a.norm();
                if norm.is_finite() && norm > limit {
                    a *= limit / norm;
                }
            }
            LimitKind::PerAxis if a.iter().any(|x| !x.is_finite()) => {}
            LimitKind::PerAxis => {
                for k in 0..3 {
                    a[k] = a[k].clamp(-limit, limit);
                }
            }
        }
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 25: an overflowing norm made the saturation scale zero (no thrust); a non-finite or
    /// overflowing command now passes through unsaturated, for the engine to refuse.
    #[test]
    fn regress_overflowing_command_is_not_saturated_to_zero() {
        let huge = Vector3::new(1e160, 1e160, 0.0);
        assert_eq!(Actuator::new(1.0, LimitKind::Norm).apply(&huge), huge);
        let inf = Vector3::new(f64::INFINITY, 0.0, 0.0);
        assert_eq!(Actuator::new(1.0, LimitKind::PerAxis).apply(&inf), inf);
        // Finite commands saturate as before.
        let big = Vector3::new(3.0, 4.0, 0.0);
        assert!((Actuator::new(1.0, LimitKind::Norm).apply(&big).norm() - 1.0).abs() < 1e-15);
        assert_eq!(
            Actuator::new(1.0, LimitKind::PerAxis).apply(&big),
            Vector3::new(1.0, 1.0, 0.0)
        );
    }

    /// An unlimited actuator with every axis working delivers the command bit for bit, whatever it
    /// is (as the limit would: no norm exceeds infinity, clamping to ±infinity changes nothing); a
    /// failed axis still delivers nothing.
    #[test]
    fn unlimited_actuator_delivers_the_command_itself() {
        let commands = [
            Vector3::new(0.1, -0.2, 0.3),
            Vector3::new(-0.0, 0.0, -0.0),
            Vector3::new(1e160, -1e160, 1e300),
            Vector3::new(f64::NAN, 1.0, f64::NEG_INFINITY),
        ];
        for kind in [LimitKind::Norm, LimitKind::PerAxis] {
            let unlimited = Actuator::new(f64::INFINITY, kind);
            for c in &commands {
                assert_eq!(unlimited.apply(c).map(f64::to_bits), c.map(f64::to_bits));
            }
            let failed = Actuator {
                working_axes: [true, false, true],
                ..unlimited
            };
            let a = failed.apply(&commands[0]);
            assert_eq!(a, Vector3::new(0.1, 0.0, 0.3));
        }
    }

    #[test]
    fn val_norm_limit_keeps_direction() {
        let act = Actuator::new(1.0, LimitKind::Norm);
        let a = act.apply(&Vector3::new(3.0, 4.0, 0.0));
        // scaled to norm 1 along (0.6, 0.8): exact in binary for these values up to one rounding
        assert!((a - Vector3::new(0.6, 0.8, 0.0)).norm() < 1e-15);
        let small = Vector3::new(0.1, -0.2, 0.3);
        assert_eq!(act.apply(&small), small);
    }

    #[test]
    fn val_per_axis_limit_clips_each_component() {
        let act = Actuator::new(1.0, LimitKind::PerAxis);
        assert_eq!(
            act.apply(&Vector3::new(3.0, -4.0, 0.5)),
            Vector3::new(1.0, -1.0, 0.5)
        );
    }

    #[test]
    fn val_failed_axis_delivers_nothing() {
        let mut act = Actuator::new(f64::INFINITY, LimitKind::Norm);
        act.working_axes[1] = false;
        assert_eq!(
            act.apply(&Vector3::new(1.0, 2.0, 3.0)),
            Vector3::new(1.0, 0.0, 3.0)
        );
    }
}
