#!/usr/bin/env bash
# Coverage-guided fuzzing of the ingestion path with cargo fuzz (libFuzzer + AddressSanitizer).
#
#   scripts/fuzz.sh [TARGET] [SECONDS]     # TARGET: ingest_step (default), ingest_iges,
#                                          #         p21_vs_ruststep; SECONDS: 600
#
# Needs a nightly toolchain (`rustup toolchain list` shows one on the build machines) and
# `cargo install cargo-fuzz`. The corpus is seeded from the small samples; crashes land in
# fuzz/artifacts/TARGET/ and are replayed with `cargo +nightly fuzz run TARGET FILE`.
# Not part of CI: CI has no nightly. tests/it/bad_input.rs runs a deterministic mutation
# suite on stable instead, and every crash found here becomes a case there.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
target="${1:-ingest_step}"
seconds="${2:-600}"
corpus="fuzz/corpus/$target"
mkdir -p "$corpus"
case "$target" in
    ingest_iges) seeds=$(find samples/iges -name '*.igs' -size -12k) ;;
    *) seeds=$(find samples -maxdepth 1 -name '*.step' -size -16k) ;;
esac
for f in $seeds; do cp -n "$f" "$corpus/" ; done
cargo +nightly fuzz run "$target" "$corpus" -- \
    -max_total_time="$seconds" -max_len=32768 -timeout=20 -rss_limit_mb=2048 \
    -dict=fuzz/step.dict -print_final_stats=1
