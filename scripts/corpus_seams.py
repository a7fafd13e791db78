#!/usr/bin/env python3
"""Open seam ends by reason and time per seam over the corpus: every reference sample
(`samples/`, `samples/trace`, `samples/iges`, `samples/distance`) and, when present, the
third-party parts in `../shared/realworld` and its `more/`, each through
`matrace trace PART -o OUT/<folder>__<file> --verify`, JOBS at a time.

    scripts/corpus_seams.py run BIN OUT [JOBS] [DIR...]
                                                 trace every part with the binary BIN (and the
                                                 STEP and IGES files of each DIR)
    scripts/corpus_seams.py show OUT             the table again from OUT's reports
    scripts/corpus_seams.py diff A B             parts whose exit status, open ends or seam
                                                 count differ between two runs

Prints each part that fails `--verify` or has open ends, the open ends by reason (the
report's `stats.open_ends_by_reason`), the trace time summed over the parts and the
per-seam time (`stats.seam_trace_ms`): median, 90th percentile, their ratio and the largest.
Times are wall-clock: run with JOBS = 1 on a quiet machine, and compare runs made back to
back. Needs only Python 3's standard library.
"""
import collections
import glob
import json
import os
import statistics
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FOLDERS = ["samples", "samples/trace", "samples/iges", "samples/distance",
           "../shared/realworld", "../shared/realworld/more"]
EXTENSIONS = ("step", "stp", "STEP", "STP", "igs", "iges", "IGS", "IGES")


def parts(extra=()):
    found = set()
    for folder in FOLDERS + list(extra):
        for ext in EXTENSIONS:
            found.update(glob.glob(os.path.join(ROOT, folder, "*." + ext)))
    return sorted(found)


def trace(args):
    binary, out, part = args
    name = os.path.basename(os.path.dirname(part)) + "__" + os.path.basename(part)
    folder = os.path.join(out, name)
    os.makedirs(folder, exist_ok=True)
    run = subprocess.run([binary, "trace", part, "-o", folder, "--verify", "--no-svg"],
                         capture_output=True, text=True, timeout=900)
    result = {"part": name, "exit": run.returncode, "stderr": run.stderr[-2000:]}
    reports = glob.glob(os.path.join(folder, "*.mat.json"))
    if reports:
        stats = json.load(open(reports[0]))["stats"]
        result.update(seams=stats["seams"], open=stats["open_ends"],
                      reasons=stats["open_ends_by_reason"],
                      trace=stats["timings"].get("trace", 0.0),
                      seam_ms=stats["seam_trace_ms"])
    with open(os.path.join(folder, "result.json"), "w") as f:
        json.dump(result, f)
    return result


def load(out):
    return [json.load(open(f)) for f in sorted(glob.glob(os.path.join(out, "*", "result.json")))]


def show(out):
    results = load(out)
    if not results:
        sys.exit(f"no results in {out}")
    reasons = collections.Counter()
    seam_ms = []
    for r in results:
        reasons.update(r.get("reasons") or {})
        seam_ms += r.get("seam_ms", [])
        if r["exit"] != 0 or r.get("open"):
            print(f'{r["part"]}: exit {r["exit"]}, open ends {r.get("open")} {r.get("reasons") or ""}')
    passed = sum(r["exit"] == 0 for r in results)
    print(f"\n{len(results)} parts, {passed} pass --verify, "
          f"{sum(reasons.values())} open seam ends")
    for reason, n in reasons.most_common():
        print(f"  {n:5}  {reason}")
    trace_s = sum(r.get("trace") or 0.0 for r in results)
    print(f"trace time {trace_s:.2f} s over the parts, {len(seam_ms)} seams")
    if seam_ms:
        seam_ms.sort()
        median = statistics.median(seam_ms)
        p90 = seam_ms[int(0.9 * len(seam_ms))]
        print(f"per seam: median {median:.3f} ms, 90th percentile {p90:.3f} ms "
              f"({p90 / median:.2f}x the median), largest {seam_ms[-1]:.1f} ms")


def diff(a, b):
    key = lambda r: (r["exit"], r.get("open"), r.get("seams"))
    before = {r["part"]: r for r in load(a)}
    for r in load(b):
        old = before.get(r["part"])
        if old and key(old) != key(r):
            print(f'{r["part"]}: (exit, open ends, seams) {key(old)} -> {key(r)}')


def main(argv):
    if len(argv) >= 3 and argv[0] == "run":
        jobs = int(argv[3]) if len(argv) > 3 else 1
        binary = os.path.abspath(argv[1])
        with ThreadPoolExecutor(jobs) as pool:
            list(pool.map(trace, [(binary, argv[2], p) for p in parts(argv[4:])]))
        show(argv[2])
    elif len(argv) == 2 and argv[0] == "show":
        show(argv[1])
    elif len(argv) == 3 and argv[0] == "diff":
        diff(argv[1], argv[2])
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:])
