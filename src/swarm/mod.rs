//! Swarm-level machinery: data structures that look at all satellites at once.
//!
//! [`neighbours`] holds the cell-list grid used for fixed-radius neighbour queries (collision-avoidance
//! terms, link ranges) and exact nearest-neighbour queries (metrics), in O(N) per rebuild.

pub mod neighbours;
