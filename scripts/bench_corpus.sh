#!/usr/bin/env bash
# Times the whole corpus — every reference sample (STEP and IGES) and, when present, the
# third-party parts in ../shared/realworld — with the release binary, one part at a time
# (`matrace batch -j 1`, every output, verified), and writes one CSV row per part.
#
#   scripts/bench_corpus.sh [OUT.csv]      (default: target/bench-corpus/corpus.csv)
#
# Columns: the batch summary's (part, status, error, faces, seams, junctions, seconds,
# worst_error, ...) plus the stage timings from each part's report (read, classify, trace,
# sheets, fit, mesh, picture, verify). Prints the total and the median seconds per part.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
csv=${1:-target/bench-corpus/corpus.csv}
out=target/bench-corpus/out
cargo build --release --quiet
rm -rf "$out"
inputs=(samples)
[ -d ../shared/realworld ] && inputs+=(../shared/realworld)
status=0
target/release/matrace batch "${inputs[@]}" -o "$out" -j 1 --verify || status=$?
mkdir -p "$(dirname "$csv")"
python3 - "$out" "$csv" <<'PY'
import csv, json, os, statistics, sys
out, dest = sys.argv[1], sys.argv[2]
summary = json.load(open(os.path.join(out, "summary.json")))
stages = ["read", "classify", "trace", "sheets", "fit", "mesh", "picture", "verify"]
rows = []
for p in summary["parts"]:
    row = {k: p.get(k) for k in ["part", "status", "error", "faces", "seams", "junctions", "seconds", "worst_error"]}
    report = os.path.join(out, p["output"] + ".mat.json") if p.get("output") else None
    t = {}
    if report and os.path.exists(report):
        t = json.load(open(report))["stats"].get("timings", {})
    for s in stages:
        row[s] = t.get(s)
    rows.append(row)
with open(dest, "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
    w.writeheader()
    w.writerows(rows)
secs = [r["seconds"] for r in rows if r["seconds"] is not None]
print(f"{len(rows)} parts, {sum(secs):.2f} s in all, median {statistics.median(secs):.3f} s per part -> {dest}")
PY
exit $status
