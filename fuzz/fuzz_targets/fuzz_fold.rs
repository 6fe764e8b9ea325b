//! Feeds arbitrary UTF-8 to the .fold importer and, when it parses, to its
//! frames' reader (`file_frames`, a fold in steps) and the sheet builder,
//! then each step's angles to the sheet again: all may refuse the input,
//! none may panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pleat::fold_steps::sheet_step_angles;
use pleat::origami::{parse_fold, parse_fold_frames, Sheet, SheetOptions};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(pattern) = parse_fold(text) {
        let steps = parse_fold_frames(text, &pattern);
        let options = SheetOptions::default();
        if let Ok(sheet) = Sheet::from_pattern(&pattern, &options) {
            if let Ok(steps) = steps {
                let _ = sheet_step_angles(&pattern, &options, &sheet, &steps);
            }
        }
    }
});
