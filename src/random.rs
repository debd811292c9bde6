//! Every random draw of a run, derived in one place from (scenario seed, purpose, satellite, tick).
//!
//! # Why one module
//!
//! A run's random numbers (initial states, navigation noise, process noise, a law's own draws) must be
//! reproducible from the scenario seed alone, independent of the number of threads and of the order in
//! which satellites are visited, and statistically independent across seeds so that a Monte Carlo over
//! seeds 1, 2, 3, … is a Monte Carlo. The previous schemes seeded a generator with
//! `seed ^ C` or `seed + step`: with `seed + step`, seed `s` at step `t + 1` drew exactly the noise of
//! seed `s + 1` at step `t`, so consecutive seeds replayed the same noise shifted by a step and a
//! "Monte Carlo over seeds" was strongly correlated. Each component inventing its own mixing invites the
//! same mistake again; here there is one derivation, tested once (`tests/val_random.rs`).
//!
//! # The derivation
//!
//! A [`RandomStream`] for (seed, purpose, satellite, tick) is the ChaCha8 keystream (64-bit block counter,
//! 64-bit stream id: the original Bernstein layout, [`rand::rngs::ChaCha8Rng`]) with
//!
//! * **key** (256 bits) = four 64-bit words, little-endian:
//!   `[m(seed + γ), m(seed + 2γ), m(tag + γ), m(tag + 2γ)]`, i.e. the first two outputs of a SplitMix64
//!   generator started at `seed` followed by the first two of one started at the purpose's fixed
//!   [`Purpose::tag`]; `m` is the SplitMix64 finaliser and γ = 0x9e37_79b9_7f4a_7c15 its (odd) increment;
//! * **stream id** = the satellite index;
//! * **word position** = `tick ×` [`WORDS_PER_TICK`] (2²⁰ 32-bit words per (satellite, tick)).
//!
//! Why this is sound:
//!
//! * *Distinct keys for distinct (seed, purpose).* `m` is a bijection of u64 (each of its steps, `x ^= x >> k`
//!   and `x *= odd`, is invertible modulo 2⁶⁴), so word 0 determines the seed and word 2 the purpose: two
//!   different (seed, purpose) pairs never share a key.
//! * *Adjacent seeds give unrelated keys.* `m` has full avalanche: seeds `s` and `s + 1` give key words that
//!   differ in about half of their bits, not in one low bit. ChaCha is designed as a pseudo-random function
//!   of its key, so different keys give streams with no usable relation, however the keys are related; the
//!   finaliser only removes low-Hamming-distance key pairs, which is cheap insurance for the reduced
//!   (8-round) variant. (Seeds `s` and `s + γ` share one key word in a shifted position; the keys still
//!   differ, which is all ChaCha needs.)
//! * *Satellites and ticks are counter positions, not seeds.* Within one key, (stream id, word position)
//!   addresses disjoint, non-overlapping pieces of keystream: satellite `i` tick `t` can never replay the
//!   draws of satellite `j` or tick `t'` (which is exactly what `seed + step` seeding did). A stream is
//!   obtained directly from its coordinates in O(1) (counter-based), so any satellite's or tick's draws are
//!   the same whatever thread makes them, in whatever order.
//!
//! # Draw budget per (purpose, satellite, tick)
//!
//! Each stream owns [`WORDS_PER_TICK`] = 2²⁰ 32-bit words = 4 MiB of keystream: 524 288 `u64` draws
//! ([`RandomStream::uniform`], [`RandomStream::uniform_range`]; [`RandomStream::standard_normal`] takes one
//! `u64` in about 99 % of draws, a few more otherwise). Using more would read the next tick's draws, so it is
//! checked on every draw, in release builds too: exceeding the budget panics (the cost is a subtraction and
//! a compare per draw, against a ChaCha block per 8 draws). Ticks run from 0 to 2⁴⁸ − 1 ([`TICK_LIMIT`]).
//!
//! # Campaigns
//!
//! A `satflock campaign` run takes its scenario seed from the campaign's seed list (`seeds = { count,
//! first }` or an explicit list; see `docs/campaigns.md`): run `k` of a campaign with S seeds has seed
//! `seeds[k mod S]`, a function of the campaign file and the run index alone, so any run can be re-run
//! alone, with `satflock run` and that seed, whatever the order or parallelism of the campaign. The
//! campaign's parameter samples draw from [`Purpose::CampaignSampling`] with the campaign's sampling
//! seed. [`sub_seed`] derives many unrelated seeds from one, for tools that need them.

use std::convert::Infallible;
use std::fmt;

use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng, TryRng};
use rand_distr::StandardNormal;

/// Number of 32-bit keystream words that each (purpose, satellite, tick) owns: 2²⁰ (4 MiB).
///
/// A [`RandomStream`] panics if it is asked for more (it would otherwise read the next tick's words).
pub const WORDS_PER_TICK: u64 = 1 << 20;

/// Ticks must be below this bound, 2⁴⁸ (the ChaCha8 word position has 68 bits; 68 − 20 = 48).
pub const TICK_LIMIT: u64 = 1 << 48;

/// SplitMix64's increment γ = 2⁶⁴/φ, odd.
const GOLDEN_GAMMA: u64 = 0x9e37_79b9_7f4a_7c15;

/// Domain tag of [`sub_seed`] (ASCII "sub_seed"), so that a campaign's sub-seed key is not the same
/// function of its parent seed as a [`RandomStream`] key word is of its seed.
const SUB_SEED_TAG: u64 = u64::from_be_bytes(*b"sub_seed");

/// What a stream of draws is for: each purpose has its own ChaCha key, so draws for one purpose never
/// depend on how many draws another purpose made.
///
/// The tags ([`Purpose::tag`]) are part of the reproducibility contract: changing one changes every draw
/// of that purpose for every seed. New purposes (e.g. a campaign's parameter sampling, random failure
/// times) get a new variant with a new tag; an existing tag is never reused or changed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Purpose {
    /// Initial relative states of the satellites (drawn at tick 0, one stream per satellite).
    InitialStates,
    /// Navigation (measurement) noise on the states a guidance law senses, per satellite and step.
    NavigationNoise,
    /// Process noise (unmodelled accelerations) in the truth dynamics, per satellite and step.
    ProcessNoise,
    /// Draws made by a guidance law's per-satellite state update (e.g. a random switch or exploration),
    /// per satellite and control tick.
    LawUpdate,
    /// Draws made by a guidance law's command, per satellite and control tick (independent of the
    /// update's).
    LawCommand,
    /// A campaign's samples of its parameter ranges (`campaign::sampling`): stream = the range's index,
    /// seed = the campaign's sampling seed (not a run's).
    CampaignSampling,
    /// Physical properties drawn from a distribution (`[satellites] mass_kg = { distribution = … }`):
    /// one stream per satellite, the tick slot holding the property's index.
    Properties,
}

impl Purpose {
    /// Every purpose, in declaration order.
    pub const ALL: [Purpose; 7] = [
        Purpose::InitialStates,
        Purpose::NavigationNoise,
        Purpose::ProcessNoise,
        Purpose::LawUpdate,
        Purpose::LawCommand,
        Purpose::CampaignSampling,
        Purpose::Properties,
    ];

    /// The purpose's fixed 64-bit tag (eight ASCII characters, big-endian), mixed into the ChaCha key.
    pub const fn tag(self) -> u64 {
        match self {
            Purpose::InitialStates => u64::from_be_bytes(*b"initials"),
            Purpose::NavigationNoise => u64::from_be_bytes(*b"nav_nois"),
            Purpose::ProcessNoise => u64::from_be_bytes(*b"procnois"),
            Purpose::LawUpdate => u64::from_be_bytes(*b"law_draw"),
            Purpose::LawCommand => u64::from_be_bytes(*b"law_cmnd"),
            Purpose::CampaignSampling => u64::from_be_bytes(*b"campsmpl"),
            Purpose::Properties => u64::from_be_bytes(*b"property"),
        }
    }
}

/// The SplitMix64 finaliser (Stafford's mix 13): a bijection of u64 with full avalanche.
///
/// Each step is invertible modulo 2⁶⁴: `x ^ (x >> k)` with k ≥ 1 (the top k bits are unchanged and give
/// back the next k, and so on) and multiplication by an odd constant.
const fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The 256-bit ChaCha key of (seed, purpose); see the module documentation.
fn chacha_key(seed: u64, purpose: Purpose) -> [u8; 32] {
    let tag = purpose.tag();
    let words = [
        mix64(seed.wrapping_add(GOLDEN_GAMMA)),
        mix64(seed.wrapping_add(GOLDEN_GAMMA.wrapping_mul(2))),
        mix64(tag.wrapping_add(GOLDEN_GAMMA)),
        mix64(tag.wrapping_add(GOLDEN_GAMMA.wrapping_mul(2))),
    ];
    let mut key = [0u8; 32];
    for (chunk, word) in key.chunks_exact_mut(8).zip(words) {
        chunk.copy_from_slice(&word.to_le_bytes());
    }
    key
}

/// The seed of run `index` of a campaign whose seed is `parent_seed`.
///
/// `sub_seed(p, i) = m(k_p + i·γ)` with `k_p = m(p ^ "sub_seed")`, where `m` is the SplitMix64 finaliser
/// and γ its odd increment: the SplitMix64 sequence started at `k_p`.
///
/// * *No collisions over indices:* for a fixed parent, `i ↦ i·γ` is a bijection modulo 2⁶⁴ (γ is odd, hence
///   invertible), adding `k_p` is a bijection, and `m` is a bijection; so distinct indices always give
///   distinct sub-seeds.
/// * *Adjacent parents are unrelated:* `k_p` and `k_{p+1}` differ in about half their bits. Two parents
///   share a sub-seed only where `j − i = (k_p − k_q)·γ⁻¹ mod 2⁶⁴`, a pseudo-random offset, so the runs of
///   campaigns with seeds `p` and `p + 1` are not the same runs shifted by a few indices (the failure mode
///   of `seed + index`).
pub const fn sub_seed(parent_seed: u64, index: u64) -> u64 {
    let key = mix64(parent_seed ^ SUB_SEED_TAG);
    mix64(key.wrapping_add(index.wrapping_mul(GOLDEN_GAMMA)))
}

/// The random draws of one (seed, purpose, satellite, tick): a ChaCha8 keystream positioned at the
/// start of the stream's own block of [`WORDS_PER_TICK`] words (see the module documentation).
///
/// It implements [`rand::TryRng`] (hence [`rand::Rng`] and [`rand::RngExt`]), so every `rand` and
/// `rand_distr` distribution can draw from it; every draw, however made, counts against the budget.
pub struct RandomStream {
    rng: ChaCha8Rng,
    /// Word position of the stream's first word: tick × WORDS_PER_TICK.
    start_word: u128,
    seed: u64,
    purpose: Purpose,
    satellite: u64,
    tick: u64,
}

impl RandomStream {
    /// The stream of draws of satellite `satellite` at tick `tick` for `purpose`, in the run with scenario
    /// seed `seed`. Cheap (a ChaCha key set-up; no keystream is generated until the first draw).
    ///
    /// # Panics
    /// If `tick ≥` [`TICK_LIMIT`] (2⁴⁸).
    pub fn new(seed: u64, purpose: Purpose, satellite: u64, tick: u64) -> Self {
        assert!(
            tick < TICK_LIMIT,
            "random stream tick {tick} is not below the limit 2^48"
        );
        let mut rng = ChaCha8Rng::from_seed(chacha_key(seed, purpose));
        // set_stream resets the position, so it comes first.
        rng.set_stream(satellite);
        let start_word = u128::from(tick) * u128::from(WORDS_PER_TICK);
        rng.set_word_pos(start_word);
        RandomStream {
            rng,
            start_word,
            seed,
            purpose,
            satellite,
            tick,
        }
    }

    /// A draw uniform in \[0, 1) with 53 random bits (the `f64` grid k·2⁻⁵³). Uses one `u64`.
    pub fn uniform(&mut self) -> f64 {
        self.random::<f64>()
    }

    /// A draw uniform in \[`lo`, `hi`): `lo + (hi − lo)·u` with `u =` [`Self::uniform`]. As for any such
    /// affine map, rounding can return `hi` itself when `hi − lo` is tiny relative to `|lo|`. Uses one
    /// `u64`. `lo ≤ hi`, both finite, is checked in debug builds.
    pub fn uniform_range(&mut self, lo: f64, hi: f64) -> f64 {
        debug_assert!(
            lo.is_finite() && hi.is_finite() && lo <= hi,
            "uniform_range needs finite lo <= hi, got [{lo}, {hi})"
        );
        lo + (hi - lo) * self.uniform()
    }

    /// A draw from the standard normal distribution N(0, 1) (`rand_distr::StandardNormal`, ziggurat).
    pub fn standard_normal(&mut self) -> f64 {
        self.sample(StandardNormal)
    }

    /// Number of 32-bit words drawn so far from this stream's budget of [`WORDS_PER_TICK`].
    pub fn words_used(&self) -> u64 {
        // The ChaCha word position has 68 bits and wraps; the difference is taken modulo 2^68.
        let used = self.rng.get_word_pos().wrapping_sub(self.start_word) & ((1u128 << 68) - 1);
        used as u64
    }

    /// Panics if the last draw went past the stream's block (into the next tick's draws).
    #[inline]
    fn check_budget(&self) {
        let used = self.words_used();
        assert!(
            used <= WORDS_PER_TICK,
            "random stream (seed {}, {:?}, satellite {}, tick {}) used {used} words, more than its \
             budget of {WORDS_PER_TICK}: the draws would overlap the next tick's",
            self.seed,
            self.purpose,
            self.satellite,
            self.tick
        );
    }
}

impl TryRng for RandomStream {
    type Error = Infallible;

    #[inline]
    fn try_next_u32(&mut self) -> Result<u32, Infallible> {
        let value = self.rng.try_next_u32()?;
        self.check_budget();
        Ok(value)
    }

    #[inline]
    fn try_next_u64(&mut self) -> Result<u64, Infallible> {
        let value = self.rng.try_next_u64()?;
        self.check_budget();
        Ok(value)
    }

    #[inline]
    fn try_fill_bytes(&mut self, dst: &mut [u8]) -> Result<(), Infallible> {
        self.rng.try_fill_bytes(dst)?;
        self.check_budget();
        Ok(())
    }
}

impl fmt::Debug for RandomStream {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("RandomStream")
            .field("seed", &self.seed)
            .field("purpose", &self.purpose)
            .field("satellite", &self.satellite)
            .field("tick", &self.tick)
            .field("words_used", &self.words_used())
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::Rng;

    /// Reference values of the SplitMix64 generator seeded with 0 (Vigna's `splitmix64.c`), which
    /// `mix64(k·γ)` must reproduce for k = 1, 2, 3.
    #[test]
    fn val_mix64_is_splitmix64() {
        let expected = [
            0xe220_a839_7b1d_cdaf_u64,
            0x6e78_9e6a_a1b9_65f4,
            0x06c4_5d18_8009_454f,
        ];
        for (k, e) in (1..=3u64).zip(expected) {
            assert_eq!(mix64(GOLDEN_GAMMA.wrapping_mul(k)), e);
        }
    }

    #[test]
    fn val_purpose_tags_are_distinct() {
        for (i, a) in Purpose::ALL.iter().enumerate() {
            for b in &Purpose::ALL[i + 1..] {
                assert_ne!(a.tag(), b.tag());
            }
        }
    }

    #[test]
    fn val_stream_starts_at_its_tick_block() {
        // Tick t of a stream is the keystream of the same key and stream id from word t × 2^20.
        let mut a = RandomStream::new(5, Purpose::LawUpdate, 3, 2);
        let mut b = ChaCha8Rng::from_seed(chacha_key(5, Purpose::LawUpdate));
        b.set_stream(3);
        b.set_word_pos(2 * u128::from(WORDS_PER_TICK));
        for _ in 0..100 {
            assert_eq!(a.next_u64(), b.next_u64());
        }
        assert_eq!(a.words_used(), 200);
    }

    #[test]
    fn val_last_tick_is_usable() {
        let mut s = RandomStream::new(1, Purpose::ProcessNoise, 0, TICK_LIMIT - 1);
        for _ in 0..WORDS_PER_TICK / 2 {
            s.next_u64();
        }
        assert_eq!(s.words_used(), WORDS_PER_TICK);
    }

    #[test]
    #[should_panic(expected = "budget")]
    fn val_exhausting_the_budget_panics() {
        let mut s = RandomStream::new(1, Purpose::NavigationNoise, 7, 3);
        let mut buffer = vec![0u8; (WORDS_PER_TICK * 4) as usize];
        s.fill_bytes(&mut buffer); // exactly the budget: fine
        s.next_u32(); // one word more: panics
    }

    #[test]
    #[should_panic(expected = "limit")]
    fn val_tick_beyond_limit_panics() {
        let _ = RandomStream::new(1, Purpose::LawUpdate, 0, TICK_LIMIT);
    }
}
