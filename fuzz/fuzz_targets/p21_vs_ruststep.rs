//! Differential: wherever ruststep's parser reads a text, matrace's Part 21 reader must read
//! it to the same AST (ours accepts more: `''` in strings, lower-case exponents, `.5`; it refuses
//! what the standard does not allow: infinite reals, empty complex instances).
#![no_main]
use libfuzzer_sys::fuzz_target;
use truck_stepio::r#in::ruststep;

fuzz_target!(|data: &[u8]| {
    // libFuzzer's hook aborts on any panic; panics that matrace's guard turns into errors
    // (truck's, ruststep's) are expected, only escaping ones are findings.
    matrace::panic_guard::install_quiet_hook();
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let ours = matrace::ingest::p21::parse(text, 64);
    // ruststep recurses per nested list and panics on integer overflow: only compare where
    // it can answer.
    if text.bytes().filter(|&b| b == b'(').count() > 64 {
        return;
    }
    let theirs = matrace::panic_guard::catch(|| ruststep::parser::parse(text));
    if let Ok(Ok(theirs)) = theirs {
        let ours = match ours {
            Ok(ours) => ours,
            // Deliberate differences: a real beyond f64 (ruststep reads infinity) and an
            // empty complex instance `#1 = ( );` (the standard needs one record or more).
            Err(e) if e.message.contains("overflows") || e.message.contains("empty complex") => {
                return
            }
            Err(e) => panic!("ruststep reads it, we do not: {e}"),
        };
        assert_eq!(ours.header, theirs.header);
        assert_eq!(ours.data_sections(), theirs.data);
    }
});
