//! The IGES reader (fixed-format sections, B-rep and sewn trimmed-surface soups) on
//! arbitrary bytes.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(model) = matrace::brep::read_model_from_bytes(Path::new("fuzz.igs"), data) {
        let _ = matrace::classify(&model, &Default::default());
    }
});
