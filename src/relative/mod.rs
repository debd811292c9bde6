//! Linearised relative motion of a deputy satellite about a reference ("chief") orbit.
//!
//! # Frame and state layout
//!
//! Every relative state in this module is expressed in the **Hill/RSW LVLH frame** of the reference
//! orbit: `x` radially outward (along the reference position vector), `z` along the reference orbit
//! normal (angular momentum `r × v`), `y = z × x` along-track (the direction of flight). Positions
//! are in metres, velocities in metres per second *as seen in the rotating frame*, and a state is the
//! 6-vector `[x, y, z, vx, vy, vz]` (`nalgebra::Vector6<f64>`). Control accelerations are Hill-frame
//! 3-vectors in m/s². This is the frame {O} of Takahashi & Sakai
//! (`docs/methods/j2-distance.md` §1.1), which states that {O} *is* the Hill/RSW
//! convention, so no axis permutation or sign change is needed between the paper and this module.
//!
//! # Models
//!
//! | type | model | reference orbit |
//! | --- | --- | --- |
//! | [`Hcw`] | Hill–Clohessy–Wiltshire equations, closed-form state transition matrix and exact zero-order-hold input matrix | circular Keplerian, mean motion `n` |
//! | [`j2_averaged`] | averaged-J2 relative orbital parameters C₁…C₆ of Takahashi & Sakai on the SS model (`docs/methods/j2-distance.md` §2.4–5.7): parameter maps, their dynamics, connectable time, swarm plane | as SS |
//! | [`SchweighartSedwick`] | J2-linearised relative motion of Schweighart & Sedwick (2002), `docs/methods/j2-distance.md` §2.3 (Eq. 4) in physical coordinates, constants of its §1.3, closed-form free motion of its §2.4 (Eq. 5) | the SS artificial circular orbit, radius `r_ref`, inclination `i_ref` |
//!
//! Both models are linear and time-invariant, so each offers its continuous-time derivative (for
//! numerical integration), a closed-form state transition matrix, an exact zero-order-hold input
//! matrix and the along-track drift rate with the matching no-drift initial condition.
//!
//! The closed forms are written with the well-conditioned functions of the private `series` module,
//! so they stay accurate for short steps and tiny mean motions (the HCW model tends to the double
//! integrator as `n → 0`).

mod hcw;
pub mod j2_averaged;
mod schweighart_sedwick;
mod series;

pub use hcw::Hcw;
pub use schweighart_sedwick::SchweighartSedwick;
