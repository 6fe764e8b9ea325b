//! Feeds arbitrary UTF-8 to the .fold importer and, when it parses, to the
//! sheet builder: both may refuse the input, neither may panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pleat::origami::{parse_fold, Sheet, SheetOptions};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(pattern) = parse_fold(text) {
        let _ = Sheet::from_pattern(&pattern, &SheetOptions::default());
    }
});
