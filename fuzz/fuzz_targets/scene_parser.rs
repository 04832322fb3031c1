//! Fuzzes the whole way from text to pixels: any text, with `--set` overrides in its
//! trailing `#set KEY=VALUE` lines, is parsed and validated; refused, its diagnostics
//! are rendered; valid, it is simulated and its first frames drawn small, with every
//! layer it has (see `physframes::fuzzing`). Nothing may panic, whatever the input.
#![no_main]

use libfuzzer_sys::fuzz_target;
use physframes::fuzzing::{exercise, Outcome};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    // Drawn in memory: a blow-up or a refusal is a correct outcome; only a panic (or a
    // hang, which libFuzzer's -timeout reports) is a finding.
    match exercise(text, None) {
        Outcome::Refused(message) => assert!(message.contains("nothing was written")),
        Outcome::Drawn { .. } => {}
    }
});
