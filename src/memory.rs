//! Whether a render fits in memory, decided before it starts.
//!
//! A render holds, per drawing thread, the frame's pixmap (width × height × 4 bytes),
//! an unpremultiplied copy when the frame is not opaque, and the encoded PNG, which is
//! at most about as large: three frame buffers. Add the static layer every frame
//! starts from, and, with trails, the positions of every body at every frame, held once
//! and shared by the frames queued between the simulation and the threads (each holds a
//! pointer and a length, whatever its index), and each thread's trail layer: the static
//! layer with the trails over it, and 5 bytes a pixel of what holds each pixel, and once
//! more those 5 bytes a pixel for the rasterisation the threads share, with the changed
//! pixels it keeps for them (at most 64 MiB). When that exceeds
//! the memory available, physframes refuses to start and says what would fit.
//!
//! The memory available is `MemAvailable` from `/proc/meminfo` on Linux, lowered to a
//! cgroup's (container's) remaining allowance when one is set. Where neither can be
//! read, physframes does not guess and starts the render.

use crate::error::{Error, Result};
use crate::scene::Scene;

/// Frame buffers each drawing thread holds at once.
const BUFFERS_PER_THREAD: u64 = 3;

/// What a render would hold in memory, in bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Estimate {
    /// Bytes of one frame: width × height × 4.
    pub frame: u64,
    /// Bytes that do not depend on the number of threads.
    pub fixed: u64,
    /// Bytes each drawing thread adds.
    pub per_thread: u64,
}

impl Estimate {
    /// Estimates the memory of rendering `scene`.
    pub fn of(scene: &Scene) -> Self {
        let r = &scene.render;
        let frame = u64::from(r.width) * u64::from(r.height) * 4;
        // Each frame's positions (16 bytes a body, plus the shared pointer's header),
        // and the history's slot for the pointer (24 bytes, in segments of doubling size
        // that may be half empty). Queued jobs share the history, so it is counted once.
        let trails = if r.trails {
            r.frame_count * (16 * scene.bodies.len() as u64 + 16 + 2 * 24)
        } else {
            0
        };
        // A thread's trail layer: a frame, a coverage byte and a 4-byte colour a pixel;
        // and the same bytes a pixel once more for the segments rasterised once for all
        // threads (`render::trails::SharedTrails`), with the frames' changed pixels it
        // keeps for the threads, at most `MAX_KEPT_BYTES`.
        let layer = if r.trails { frame + frame / 4 * 5 } else { 0 };
        let shared = if r.trails {
            frame / 4 * 5 + crate::render::trails::MAX_KEPT_BYTES as u64
        } else {
            0
        };
        Estimate {
            frame,
            fixed: frame + trails + shared,
            per_thread: BUFFERS_PER_THREAD * frame + layer,
        }
    }

    /// Returns the bytes needed with `threads` drawing threads.
    pub fn total(&self, threads: usize) -> u64 {
        self.fixed
            .saturating_add(self.per_thread.saturating_mul(threads as u64))
    }

    /// Returns the most threads that fit in `available` bytes (0 when none does).
    pub fn threads_that_fit(&self, available: u64) -> u64 {
        available.saturating_sub(self.fixed) / self.per_thread.max(1)
    }
}

/// Returns the bytes of memory available to this process, when the system says.
pub fn available() -> Option<u64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok();
    let mem = meminfo.as_deref().and_then(parse_mem_available);
    let cgroup = cgroup_allowance();
    match (mem, cgroup) {
        (Some(m), Some(c)) => Some(m.min(c)),
        (m, c) => m.or(c),
    }
}

/// Reads `MemAvailable:   123456 kB` from the text of `/proc/meminfo`.
pub fn parse_mem_available(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let mut words = line.split_whitespace().skip(1);
    let value: u64 = words.next()?.parse().ok()?;
    let unit = match words.next() {
        Some("kB") => 1024,
        None => 1,
        Some(_) => return None,
    };
    value.checked_mul(unit)
}

/// Returns the remaining allowance of a cgroup v2 memory limit (`memory.max` minus
/// `memory.current`), when this process is in one that sets a limit.
fn cgroup_allowance() -> Option<u64> {
    let read = |name: &str| std::fs::read_to_string(format!("/sys/fs/cgroup/{name}")).ok();
    let max: u64 = read("memory.max")?.trim().parse().ok()?;
    let current: u64 = read("memory.current")?.trim().parse().ok()?;
    Some(max.saturating_sub(current))
}

/// Decides how many threads draw. `requested` 0 means one per core, lowered to what
/// fits in memory; an explicit number is kept. Refuses, with the numbers, a render that
/// does not fit in `available` bytes (when known).
pub fn plan_threads(scene: &Scene, requested: usize, available: Option<u64>) -> Result<usize> {
    let cores = crate::threads::or_cores(0);
    let estimate = Estimate::of(scene);
    let Some(available) = available else {
        return Ok(crate::threads::or_cores(requested));
    };
    let fit = estimate.threads_that_fit(available);
    let threads = match requested {
        0 => cores.min(usize::try_from(fit).unwrap_or(usize::MAX)).max(1),
        n => n,
    };
    let needed = estimate.total(threads);
    if needed <= available {
        return Ok(threads);
    }
    let r = &scene.render;
    let hint = if fit >= 1 {
        format!("use --threads {fit} or fewer, or a smaller image")
    } else {
        "make the image smaller (render.width and render.height)".to_string()
    };
    Err(Error::Usage(format!(
        "this render needs about {} of memory ({threads} thread{} × {BUFFERS_PER_THREAD} buffers of {}×{}×4 bytes = {} each{}), but only {} is available; nothing was written\nhint: {hint}",
        human(needed),
        if threads == 1 { "" } else { "s" },
        r.width,
        r.height,
        human(estimate.frame),
        if r.trails { ", plus trails" } else { "" },
        human(available),
    )))
}

/// Writes a byte count for a person: 1.5 GiB, 200.0 MiB, 12.0 KiB.
pub fn human(bytes: u64) -> String {
    const UNITS: [&str; 5] = ["bytes", "KiB", "MiB", "GiB", "TiB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{bytes} bytes")
    } else {
        format!("{value:.1} {}", UNITS[unit])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::parse;

    fn scene(width: u32, height: u32) -> Scene {
        let text = format!(
            "[render]\nwidth = {width}\nheight = {height}\nview = {{ min = [0.0, 0.0], max = [1.0, 1.0] }}\n"
        );
        parse(std::path::Path::new("m.toml"), &text).expect("a valid scene")
    }

    #[test]
    fn mem_available_is_read_in_bytes() {
        let meminfo = "MemTotal:       16318412 kB\nMemFree:  1 kB\nMemAvailable:   12000000 kB\n";
        assert_eq!(parse_mem_available(meminfo), Some(12_000_000 * 1024));
        assert_eq!(parse_mem_available("MemTotal: 5 kB\n"), None);
    }

    #[test]
    fn a_render_that_cannot_fit_is_refused_with_what_would() {
        let s = scene(16384, 16384);
        let frame = 16384 * 16384 * 4;
        let e = Estimate::of(&s);
        assert_eq!(e.frame, frame);
        assert_eq!(e.total(2), frame + 2 * 3 * frame);
        // Room for exactly two threads: two are kept, four are refused with the hint.
        let room = e.total(2);
        assert_eq!(plan_threads(&s, 2, Some(room)).ok(), Some(2));
        let err = plan_threads(&s, 4, Some(room)).expect_err("too many threads");
        let text = err.to_string();
        assert!(text.contains("use --threads 2 or fewer"), "{text}");
        assert_eq!(err.exit_code(), crate::error::exit::BAD_INPUT);
        // Automatic threads are lowered to fit; not even one thread is refused.
        assert!(plan_threads(&s, 0, Some(room)).is_ok_and(|t| t <= 2));
        let err = plan_threads(&s, 0, Some(frame)).expect_err("nothing fits");
        assert!(err.to_string().contains("make the image smaller"), "{err}");
        // Where the memory is unknown, the render goes ahead.
        assert_eq!(plan_threads(&s, 4, None).ok(), Some(4));
    }

    /// The most bytes of changed trail pixels kept for the threads.
    fn kept_trail_pixels() -> u64 {
        crate::render::trails::MAX_KEPT_BYTES as u64
    }

    #[test]
    fn trails_are_counted_once_however_many_threads_draw() {
        let text = "[simulation]\nduration = 100.0\n[render]\nwidth = 64\nheight = 48\nfps = 30\ntrails = true\nview = { min = [0.0, 0.0], max = [1.0, 1.0] }\n[[body]]\nname = \"a\"\nmass = 1.0\n[[body]]\nname = \"b\"\nmass = 1.0\n";
        let s = parse(std::path::Path::new("m.toml"), text).expect("a valid scene");
        let frames = s.render.frame_count;
        assert!(frames > 3000, "{frames} frames");
        let e = Estimate::of(&s);
        // The frames share one history: a thread adds its buffers and its trail layer,
        // and nothing that grows with the number of frames.
        assert_eq!(e.per_thread, 3 * 64 * 48 * 4 + 64 * 48 * (4 + 5));
        // Two bodies' positions, the pointer's header and its slot for every frame; the
        // slot is no larger than the estimate says. And once, the coverage and owner of
        // the segments rasterised for every thread.
        let slot = std::mem::size_of::<std::sync::OnceLock<std::sync::Arc<[glam::DVec2]>>>();
        assert!(slot <= 24, "a slot takes {slot} bytes");
        assert_eq!(
            e.fixed,
            64 * 48 * 4 + frames * (2 * 16 + 16 + 48) + 64 * 48 * 5 + kept_trail_pixels()
        );
    }

    #[test]
    fn byte_counts_read_like_people_write_them() {
        assert_eq!(human(512), "512 bytes");
        assert_eq!(human(1536), "1.5 KiB");
        assert_eq!(human(3 << 30), "3.0 GiB");
    }
}
