//! The IGES reader (fixed-format sections, B-rep and sewn trimmed-surface soups) on
//! arbitrary bytes.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    // libFuzzer's hook aborts on any panic; panics that matrace's guard turns into errors
    // (truck's, ruststep's) are expected, only escaping ones are findings.
    matrace::panic_guard::install_quiet_hook();
    if let Ok(model) = matrace::ingest::read_model_from_bytes(Path::new("fuzz.igs"), data) {
        let _ = matrace::classify(&model, &Default::default());
    }
});
