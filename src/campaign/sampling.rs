//! The parameter points of a campaign: the grid product of value lists, and samples of ranges drawn at
//! random or by Latin hypercube, on a linear or logarithmic scale.
//!
//! Samples are drawn in the unit cube and mapped onto each range. Latin hypercube (McKay, Beckman &
//! Conover 1979): with N samples, each range is cut into N strata of equal width (equal ratio on a log
//! scale) and every stratum of every range holds exactly one sample; which stratum sample `i` takes in
//! range `d` is a random permutation per range, and its place inside the stratum is uniform. Random:
//! every coordinate uniform and independent.
//!
//! Every draw comes from [`crate::random`] with the purpose [`Purpose::CampaignSampling`] and the
//! campaign's sampling seed: range `d` (in key order) is stream `d`, its permutation drawn at tick 0
//! and its positions at tick 1. The samples are therefore a function of (sampling seed, number of
//! samples, number of ranges) alone.

use rand::seq::SliceRandom;
use serde::Deserialize;

use crate::random::{Purpose, RandomStream};

/// How a range's values are spread.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Scale {
    /// Uniform in the value (default).
    #[default]
    Linear,
    /// Uniform in the logarithm of the value (both bounds > 0).
    Log,
}

/// A range of one parameter, `[min, max]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// Lower bound.
    pub min: f64,
    /// Upper bound (> `min`).
    pub max: f64,
    /// Linear or logarithmic.
    pub scale: Scale,
}

impl Range {
    /// The value at fraction `u` ∈ \[0, 1\] of the range (on its scale), kept within `[min, max]`.
    pub fn at(&self, u: f64) -> f64 {
        let v = match self.scale {
            Scale::Linear => self.min + (self.max - self.min) * u,
            Scale::Log => (self.min.ln() + (self.max.ln() - self.min.ln()) * u).exp(),
        };
        v.clamp(self.min, self.max)
    }
}

/// How ranges are sampled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Latin hypercube: one sample in every stratum of every range.
    LatinHypercube,
    /// Independent uniform draws.
    Random,
}

/// `samples` points in the unit cube of `dimensions` coordinates (`points[i][d]` ∈ \[0, 1)), drawn by
/// `method` from `seed` (see the module documentation).
pub fn unit_samples(method: Method, dimensions: usize, samples: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut points = vec![vec![0.0; dimensions]; samples];
    for d in 0..dimensions {
        let stream = d as u64;
        match method {
            Method::Random => {
                let mut draws = RandomStream::new(seed, Purpose::CampaignSampling, stream, 0);
                for point in &mut points {
                    point[d] = draws.uniform();
                }
            }
            Method::LatinHypercube => {
                let mut strata: Vec<usize> = (0..samples).collect();
                strata.shuffle(&mut RandomStream::new(
                    seed,
                    Purpose::CampaignSampling,
                    stream,
                    0,
                ));
                let mut draws = RandomStream::new(seed, Purpose::CampaignSampling, stream, 1);
                let n = samples as f64;
                for (point, stratum) in points.iter_mut().zip(strata) {
                    // (k + u)/N < 1 for k < N, u < 1; rounding can only reach 1.0 itself.
                    point[d] = ((stratum as f64 + draws.uniform()) / n).min(1.0);
                }
            }
        }
    }
    points
}

/// The grid product of value lists: every combination, the first list varying slowest. No lists give
/// one empty combination.
pub fn grid<T: Clone>(lists: &[Vec<T>]) -> Vec<Vec<T>> {
    let mut out: Vec<Vec<T>> = vec![Vec::new()];
    for list in lists {
        out = out
            .into_iter()
            .flat_map(|prefix| {
                list.iter().map(move |v| {
                    let mut next = prefix.clone();
                    next.push(v.clone());
                    next
                })
            })
            .collect();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_is_the_product_first_list_slowest() {
        let g = grid(&[vec![1, 2], vec![10, 20, 30]]);
        assert_eq!(
            g,
            vec![
                vec![1, 10],
                vec![1, 20],
                vec![1, 30],
                vec![2, 10],
                vec![2, 20],
                vec![2, 30]
            ]
        );
        assert_eq!(grid::<u8>(&[]), vec![Vec::<u8>::new()]);
    }

    /// Independent property check: map the values back to strata by their own bounds and count.
    #[test]
    fn latin_hypercube_puts_one_sample_in_every_stratum() {
        let ranges = [
            Range {
                min: 1000.0,
                max: 3000.0,
                scale: Scale::Linear,
            },
            Range {
                min: 1e-4,
                max: 1e-1,
                scale: Scale::Log,
            },
            Range {
                min: -5.0,
                max: 5.0,
                scale: Scale::Linear,
            },
        ];
        for n in [1usize, 2, 7, 16, 100] {
            let unit = unit_samples(Method::LatinHypercube, ranges.len(), n, 42);
            for (d, r) in ranges.iter().enumerate() {
                let mut count = vec![0usize; n];
                for p in &unit {
                    let v = r.at(p[d]);
                    assert!((r.min..=r.max).contains(&v));
                    let fraction = match r.scale {
                        Scale::Linear => (v - r.min) / (r.max - r.min),
                        Scale::Log => (v / r.min).log10() / (r.max / r.min).log10(),
                    };
                    count[((fraction * n as f64).floor() as usize).min(n - 1)] += 1;
                }
                assert!(
                    count.iter().all(|&c| c == 1),
                    "n = {n}, range {d}: {count:?}"
                );
            }
        }
    }

    #[test]
    fn random_samples_stay_in_bounds_and_depend_on_the_seed_only() {
        let r = Range {
            min: 2.0,
            max: 2000.0,
            scale: Scale::Log,
        };
        let a = unit_samples(Method::Random, 2, 500, 9);
        assert_eq!(a, unit_samples(Method::Random, 2, 500, 9));
        assert_ne!(a, unit_samples(Method::Random, 2, 500, 10));
        let values: Vec<f64> = a.iter().map(|p| r.at(p[0])).collect();
        assert!(values.iter().all(|v| (2.0..=2000.0).contains(v)));
        // Log scale: about half the draws below the geometric mean sqrt(2 * 2000) = 63.2 (binomial
        // 500, 1/2: 5 standard deviations is ±56).
        let below = values.iter().filter(|&&v| v < 63.245_553).count();
        assert!((194..=306).contains(&below), "{below}");
    }

    #[test]
    fn log_scale_maps_the_unit_interval_geometrically() {
        let r = Range {
            min: 1e-3,
            max: 1e1,
            scale: Scale::Log,
        };
        // 10^(−3 + 4u): the bounds, halfway in log 0.1, a quarter 0.01.
        for (u, expected) in [(0.0, 1e-3), (0.25, 1e-2), (0.5, 0.1), (1.0, 1e1)] {
            let v = r.at(u);
            assert!((v / expected - 1.0).abs() < 1e-14, "{u}: {v}");
        }
    }
}
