//! What `--threads N` means wherever a command takes it: N threads, or one per core
//! when N is 0 (the default).

/// `threads`, or the number of cores when it is 0 (1 if that cannot be known).
pub fn or_cores(threads: usize) -> usize {
    match threads {
        0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
        n => n,
    }
}
