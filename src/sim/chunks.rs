//! The drivers of the per-body loops over flat arrays: chunks that stay in cache,
//! split across rayon's threads for many bodies so that each body's arithmetic, and so
//! every bit, is the same for any number of threads; the finiteness checks over those
//! arrays; and the switch to the loops' AVX2 build.

use std::sync::atomic::{AtomicU8, Ordering};

use glam::DVec2;
use rayon::prelude::*;

/// Bodies per chunk of the per-body loops: 512 bodies keep a chunk's positions,
/// velocities and accelerations (8 KiB each) in the L1 cache between computing the
/// forces and using them.
pub const CHUNK: usize = 512;

/// Bodies per task when the per-body loops are split across threads: large enough that
/// scheduling a task costs little beside it.
pub const BLOCK: usize = 32 * CHUNK;

/// The fewest bodies for which the per-body loops are split across threads; below it
/// they run on the calling thread. Each body's update is independent of the others',
/// so splitting gives the same bits for any number of threads.
pub const PARALLEL_MIN: usize = 4 * BLOCK;

/// Calls `f(start, chunk)` for consecutive chunks of at most [`CHUNK`] bodies of `out`,
/// split across threads in blocks of [`BLOCK`] when there are [`PARALLEL_MIN`] bodies or
/// more. `f` must touch only its own chunk, so the result does not depend on threads.
pub fn for_each_chunk(out: &mut [DVec2], f: impl Fn(usize, &mut [DVec2]) + Sync) {
    let run = |start: usize, block: &mut [DVec2]| {
        for (k, chunk) in block.chunks_mut(CHUNK).enumerate() {
            f(start + k * CHUNK, chunk);
        }
    };
    if out.len() < PARALLEL_MIN {
        run(0, out);
    } else {
        out.par_chunks_mut(BLOCK)
            .enumerate()
            .for_each(|(b, block)| run(b * BLOCK, block));
    }
}

/// Like [`for_each_chunk`] over the positions and velocities together: calls
/// `f(start, pos, vel)` for matching chunks of both, for integrators that update each
/// body on its own. Returns true when every call returned true.
pub fn for_each_chunk_pair(
    pos: &mut [DVec2],
    vel: &mut [DVec2],
    f: impl Fn(usize, &mut [DVec2], &mut [DVec2]) -> bool + Sync,
) -> bool {
    debug_assert_eq!(pos.len(), vel.len());
    let run = |start: usize, pos: &mut [DVec2], vel: &mut [DVec2]| {
        let mut all = true;
        for (k, (p, v)) in pos.chunks_mut(CHUNK).zip(vel.chunks_mut(CHUNK)).enumerate() {
            all &= f(start + k * CHUNK, p, v);
        }
        all
    };
    if pos.len() < PARALLEL_MIN {
        run(0, pos, vel)
    } else {
        pos.par_chunks_mut(BLOCK)
            .zip(vel.par_chunks_mut(BLOCK))
            .enumerate()
            .map(|(b, (p, v))| run(b * BLOCK, p, v))
            .reduce(|| true, |a, b| a && b)
    }
}

/// Returns true when every component of `pos` and `vel` is finite.
///
/// 0·x is ±0 for a finite x and NaN for an infinite or NaN one, and a sum of zeros and
/// NaNs is NaN as soon as one term is: so the sums below are finite exactly when every
/// number is. Four independent sums let the loop run on vector registers.
pub fn all_finite(pos: &[DVec2], vel: &[DVec2]) -> bool {
    debug_assert_eq!(pos.len(), vel.len());
    #[cfg(target_arch = "x86_64")]
    if wide_vectors() {
        #[target_feature(enable = "avx2")]
        unsafe fn wide(pos: &[DVec2], vel: &[DVec2]) -> bool {
            all_finite_kernel(pos, vel)
        }
        // SAFETY: `wide_vectors` has checked that this processor has AVX2.
        return unsafe { wide(pos, vel) };
    }
    all_finite_kernel(pos, vel)
}

/// The loop of [`all_finite`], to inline into loops compiled for wider registers.
#[inline(always)]
pub fn all_finite_kernel(pos: &[DVec2], vel: &[DVec2]) -> bool {
    let mut sums = [DVec2::ZERO; 4];
    let mut p4 = pos.chunks_exact(4);
    let mut v4 = vel.chunks_exact(4);
    for (p, v) in (&mut p4).zip(&mut v4) {
        for j in 0..4 {
            // 0·x: ±0 when x is finite, NaN otherwise.
            sums[j] += p[j] * 0.0 + v[j] * 0.0;
        }
    }
    for (p, v) in p4.remainder().iter().zip(v4.remainder()) {
        sums[0] += *p * 0.0 + *v * 0.0;
    }
    (sums[0] + sums[1] + sums[2] + sums[3]).is_finite()
}

/// Returns true only when every component of `pos` and `vel` is finite, by one sum of
/// them all: a sum is finite only if every term is (an infinity or NaN stays one). A
/// false answer means that some value is not finite or that the sum overflowed, which
/// [`all_finite`] can then tell apart. Cheaper than `all_finite`, for data in cache.
#[inline(always)]
pub fn sum_is_finite(pos: &[DVec2], vel: &[DVec2]) -> bool {
    let mut sums = [DVec2::ZERO; 4];
    let mut p4 = pos.chunks_exact(4);
    let mut v4 = vel.chunks_exact(4);
    for (p, v) in (&mut p4).zip(&mut v4) {
        for j in 0..4 {
            sums[j] += p[j] + v[j];
        }
    }
    for (p, v) in p4.remainder().iter().zip(v4.remainder()) {
        sums[0] += *p + *v;
    }
    (sums[0] + sums[1] + sums[2] + sums[3]).is_finite()
}

/// Whether the hot loops may use 256-bit AVX2 registers: 0 not yet known, 1 yes, 2 no.
static WIDE_VECTORS: AtomicU8 = AtomicU8::new(0);

/// Returns true when the hot loops run their AVX2 versions: when the processor has
/// AVX2, unless [`use_wide_vectors`] turned them off. The same arithmetic runs either
/// way (Rust never fuses a multiply and an add), so only the speed differs, not the
/// bits.
#[inline]
pub fn wide_vectors() -> bool {
    match WIDE_VECTORS.load(Ordering::Relaxed) {
        1 => true,
        2 => false,
        _ => {
            let wide = detect_avx2();
            WIDE_VECTORS.store(if wide { 1 } else { 2 }, Ordering::Relaxed);
            wide
        }
    }
}

/// Turns the AVX2 versions of the hot loops on (where the processor has AVX2) or off,
/// for tests and measurements that compare the two.
pub fn use_wide_vectors(enabled: bool) {
    let wide = enabled && detect_avx2();
    WIDE_VECTORS.store(if wide { 1 } else { 2 }, Ordering::Relaxed);
}

fn detect_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}
