//! The CLI's argument handling: `fixshade_sim::cli::parse` on arbitrary argument
//! lists (NUL-separated UTF-8). Nothing is run and no file is opened; asserted: no
//! panic, and every error is a usage error (exit code 2) with a message.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let args: Vec<String> = if text.is_empty() {
        Vec::new()
    } else {
        text.split('\0').map(str::to_string).collect()
    };
    if let Err(e) = fixshade_sim::cli::parse(&args) {
        assert_eq!(e.code, 2, "{}", e.message);
        assert!(!e.message.is_empty());
    }
});
