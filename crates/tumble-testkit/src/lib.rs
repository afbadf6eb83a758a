//! Helpers shared by the tests and benchmarks of every crate of the
//! workspace (a dev-dependency only; nothing here ships): deterministic
//! random sources, the same numbers on every machine and in every run, so a
//! randomised test that fails fails again.
//!
//! Three generators, because the tests were written against their streams
//! and their cases (seeds chosen to hit particular configurations) must not
//! change: SplitMix64 (Steele, Lea and Flood 2014), xorshift64* (Vigna 2016)
//! and plain xorshift64 (Marsaglia 2003). All share [`RandomSource`]'s
//! derived draws, so a helper written once serves all three.

use glam::{DQuat, DVec3};

/// A stream of 64-bit words and the draws made from it.
pub trait RandomSource {
    /// The next raw word.
    fn next_u64(&mut self) -> u64;

    /// Uniform in [0, 1), from the top 53 bits.
    fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }

    /// An integer in `lo..=hi` (modulo bias is irrelevant for tests).
    fn int(&mut self, lo: i64, hi: i64) -> i64 {
        lo + (self.next_u64() % (hi - lo + 1) as u64) as i64
    }

    /// An index in `0..n` (0 when `n` is 0).
    fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n.max(1) as u64) as usize
    }

    /// Each component uniform in [-r, r).
    fn vec3(&mut self, r: f64) -> DVec3 {
        DVec3::new(self.range(-r, r), self.range(-r, r), self.range(-r, r))
    }

    /// A direction, uniform on the sphere (rejection from the cube; vectors
    /// shorter than 0.1 are redrawn to keep the normalisation well posed).
    fn unit_vector(&mut self) -> DVec3 {
        loop {
            let v = self.vec3(1.0);
            let l = v.length();
            if l > 0.1 && l <= 1.0 {
                return v / l;
            }
        }
    }

    /// A rotation about a random axis by a uniform angle in [0, 2 pi).
    fn rotation(&mut self) -> DQuat {
        DQuat::from_axis_angle(self.unit_vector(), self.range(0.0, std::f64::consts::TAU))
    }
}

/// SplitMix64; the field is the state (the seed before the first draw).
#[derive(Debug, Clone)]
pub struct SplitMix64(pub u64);

impl RandomSource for SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}

/// xorshift64*; the field is the state (must not be 0).
#[derive(Debug, Clone)]
pub struct XorShift64Star(pub u64);

impl RandomSource for XorShift64Star {
    fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
}

/// Plain xorshift64 (13, 7, 17); the field is the state (must not be 0).
#[derive(Debug, Clone)]
pub struct XorShift64(pub u64);

impl RandomSource for XorShift64 {
    fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
}

/// SplitMix64 as a closure of uniform draws in [0, 1), for tests that pass
/// `&mut impl FnMut() -> f64` around.
pub fn splitmix_f64(seed: u64) -> impl FnMut() -> f64 {
    let mut source = SplitMix64(seed);
    move || source.next_f64()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_streams_are_the_published_ones() {
        // SplitMix64 from state 0: the reference implementation's first word.
        assert_eq!(SplitMix64(0).next_u64(), 0xE220_A839_7B1D_CDAF);
        // xorshift64* and xorshift64 from state 1, worked by hand from the
        // shifts above.
        let mut x = 1u64;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        assert_eq!(
            XorShift64Star(1).next_u64(),
            x.wrapping_mul(0x2545_F491_4F6C_DD1D)
        );
        assert_eq!(XorShift64(1).next_u64(), {
            let mut y = 1u64;
            y ^= y << 13;
            y ^= y >> 7;
            y ^= y << 17;
            y
        });
    }

    #[test]
    fn draws_stay_in_their_ranges() {
        let mut r = SplitMix64(7);
        for _ in 0..10_000 {
            let u = r.next_f64();
            assert!((0.0..1.0).contains(&u));
            assert!((-3..=4).contains(&r.int(-3, 4)));
            assert!(r.below(5) < 5);
            assert!((r.unit_vector().length() - 1.0).abs() < 1e-12);
        }
        let mut f = splitmix_f64(7);
        let mut again = SplitMix64(7);
        assert_eq!(f().to_bits(), again.next_f64().to_bits());
    }
}
