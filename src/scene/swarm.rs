//! Swarms: many bodies declared at once, with initial states drawn from a seeded,
//! portable random number generator, so that the same seed gives the same bodies on
//! every platform and in every version.
//!
//! The generator is SplitMix64 (Steele, Lea and Flood, "Fast splittable pseudorandom
//! number generators", OOPSLA 2014), with the reference constants of Vigna's
//! `splitmix64.c`. Its k-th output depends only on the seed and k, so member i of a
//! swarm takes the outputs 4i + 1 to 4i + 4 (x, y, vx, vy) whatever the swarm's size:
//! growing `count` adds bodies and leaves the earlier ones where they were. Angles and
//! angular velocities, when a swarm draws them, come from a second stream of the same
//! generator, seeded with seed ⊕ [`SPIN_STREAM`] (outputs 2i + 1 and 2i + 2 of member
//! i), so a swarm that draws none gives exactly the bodies it gave before bodies
//! turned.

use glam::DVec2;

/// The increment of SplitMix64's Weyl sequence: 2^64 divided by the golden ratio.
const GAMMA: u64 = 0x9e37_79b9_7f4a_7c15;

/// The k-th output (counted from 1) of SplitMix64 started from `seed`.
///
/// The state after k steps is s_k = seed + k·γ (mod 2^64), and the output is the
/// finaliser z ↦ z ⊕ (z ≫ 31) applied after the two multiply-xorshift rounds
/// z ← (z ⊕ (z ≫ 30))·0xbf58476d1ce4e5b9 and z ← (z ⊕ (z ≫ 27))·0x94d049bb133111eb.
#[inline]
pub fn splitmix64(seed: u64, k: u64) -> u64 {
    let mut z = seed.wrapping_add(k.wrapping_mul(GAMMA));
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Turns 64 random bits into a uniform number in [0, 1): the top 53 bits times 2^-53,
/// so every result is an exact multiple of 2^-53.
#[inline]
pub fn unit(bits: u64) -> f64 {
    (bits >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// A rectangle of vectors from which values are drawn uniformly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Uniform2 {
    pub min: DVec2,
    pub max: DVec2,
}

impl Uniform2 {
    /// Maps two uniform numbers u, w in [0, 1) into the rectangle:
    /// (min.x + u·(max.x - min.x), min.y + w·(max.y - min.y)).
    #[inline]
    pub fn at(&self, u: f64, w: f64) -> DVec2 {
        DVec2::new(
            self.min.x + u * (self.max.x - self.min.x),
            self.min.y + w * (self.max.y - self.min.y),
        )
    }
}

/// An interval of numbers from which values are drawn uniformly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Uniform1 {
    pub min: f64,
    pub max: f64,
}

impl Uniform1 {
    /// Maps a uniform number u in [0, 1) into the interval: min + u·(max - min).
    #[inline]
    pub fn at(&self, u: f64) -> f64 {
        self.min + u * (self.max - self.min)
    }
}

/// The constant a swarm's seed is xored with to seed the stream of its angles and
/// angular velocities: the first 64 bits of the fractional part of π, so that the two
/// streams of one seed are unrelated.
pub const SPIN_STREAM: u64 = 0x243f_6a88_85a3_08d3;

/// Returns the initial angle and angular velocity of member `i` of a swarm seeded with
/// `seed`: outputs 2i + 1 (θ) and 2i + 2 (ω) of SplitMix64 seeded with
/// seed ⊕ [`SPIN_STREAM`].
pub fn member_spin(seed: u64, i: u64, angle: Uniform1, omega: Uniform1) -> (f64, f64) {
    let stream = seed ^ SPIN_STREAM;
    let draw = |j: u64| unit(splitmix64(stream, 2 * i + j));
    (angle.at(draw(1)), omega.at(draw(2)))
}

/// Returns the initial position and velocity of member `i` of a swarm seeded with
/// `seed`: the SplitMix64 outputs 4i + 1 and 4i + 2 give x and y, 4i + 3 and 4i + 4
/// give vx and vy.
pub fn member_state(seed: u64, i: u64, position: Uniform2, velocity: Uniform2) -> (DVec2, DVec2) {
    let k = 4 * i;
    let draw = |j: u64| unit(splitmix64(seed, k + j));
    (position.at(draw(1), draw(2)), velocity.at(draw(3), draw(4)))
}

/// Returns the centre of cell i of a grid of `count` cells filling `area` row by row
/// from its lower-left corner: `cols` = ⌈√(count·w/h)⌉ columns of width w/cols and
/// ⌈count/cols⌉ rows, so that the cells are as near square as the count allows. A
/// swarm with `layout = "grid"` puts member i there, so that members never overlap
/// when each fits its cell.
pub fn grid_position(i: u64, count: u64, area: Uniform2) -> DVec2 {
    let (cols, rows) = grid_shape(count, area);
    let size = area.max - area.min;
    let cell = DVec2::new(size.x / cols as f64, size.y / rows as f64);
    let (col, row) = (i % cols, i / cols);
    area.min + DVec2::new((col as f64 + 0.5) * cell.x, (row as f64 + 0.5) * cell.y)
}

/// Returns the columns and rows of the grid of [`grid_position`].
pub fn grid_shape(count: u64, area: Uniform2) -> (u64, u64) {
    let size = area.max - area.min;
    let aspect = if size.y > 0.0 { size.x / size.y } else { 1.0 };
    let cols = ((count as f64 * aspect).sqrt().ceil() as u64).clamp(1, count.max(1));
    (cols, count.div_ceil(cols).max(1))
}

/// Splits a name into a prefix and the number its trailing digits write, when those
/// digits are how a swarm names a member: no leading zero unless the number is 0.
/// `dust17` gives ("dust", 17); `dust017`, `dust` and `17x` give `None`.
pub fn split_member_name(name: &str) -> Option<(&str, u64)> {
    let prefix = name.trim_end_matches(|c: char| c.is_ascii_digit());
    let digits = &name[prefix.len()..];
    if prefix.is_empty() || digits.is_empty() || (digits.len() > 1 && digits.starts_with('0')) {
        return None;
    }
    digits.parse().ok().map(|n| (prefix, n))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix64_gives_the_reference_outputs() {
        // The first outputs of Vigna's splitmix64.c seeded with 1234567 and with 0.
        let from = |seed: u64| (1..=5).map(|k| splitmix64(seed, k)).collect::<Vec<_>>();
        assert_eq!(
            from(1_234_567),
            [
                6457827717110365317,
                3203168211198807973,
                9817491932198370423,
                4593380528125082431,
                16408922859458223821
            ]
        );
        assert_eq!(
            from(0)[..3],
            [0xe220a8397b1dcdaf, 0x6e789e6aa1b965f4, 0x06c45d188009454f]
        );
    }

    #[test]
    fn unit_numbers_lie_in_the_half_open_interval() {
        assert_eq!(unit(0), 0.0);
        assert_eq!(unit(u64::MAX), 1.0 - 2f64.powi(-53));
        assert_eq!(unit(1 << 63), 0.5);
    }

    #[test]
    fn member_names_split_only_when_canonical() {
        assert_eq!(split_member_name("dust17"), Some(("dust", 17)));
        assert_eq!(split_member_name("dust0"), Some(("dust", 0)));
        assert_eq!(split_member_name("a-b9"), Some(("a-b", 9)));
        assert_eq!(split_member_name("dust017"), None);
        assert_eq!(split_member_name("dust"), None);
        assert_eq!(split_member_name("123"), None);
        assert_eq!(split_member_name("dust99999999999999999999999"), None);
    }
}
