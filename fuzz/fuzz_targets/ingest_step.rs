//! The whole STEP ingestion path on arbitrary bytes: file checks, the Part 21 reader, the
//! entity checks, truck's conversion, the B-rep walk and the UV domains. Any outcome but a
//! panic, a hang or an out-of-memory is fine; errors must be ordinary `Err`s.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    // libFuzzer's hook aborts on any panic; panics that matrace's guard turns into errors
    // (truck's, ruststep's) are expected, only escaping ones are findings.
    matrace::panic_guard::install_quiet_hook();
    if let Ok(model) = matrace::ingest::read_model_from_bytes(Path::new("fuzz.step"), data) {
        // A model that reads must classify.
        let _ = matrace::classify(&model, &Default::default());
    }
});
