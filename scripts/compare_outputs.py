#!/usr/bin/env python3
"""Compares what two matrace binaries write for every part of the corpus.

    scripts/compare_outputs.py OLD_BINARY NEW_BINARY [--work DIR] [--jobs N] [--ignore KEY]...

Runs both binaries on every corpus part (samples/*.step, samples/iges/*, and, when present,
../shared/realworld/* and ../shared/realworld/more/*): `inspect`, `inspect --json`, and
`trace --verify` (with `--with-solid` for STEP parts), and once `batch --verify` over
samples/. Then compares, part by part, the exit status, stdout, stderr and every file written.

Left out of the comparison, because they cannot be equal between two runs:
- timings: the report's `stats.seconds` and `stats.timings`, the summary's `seconds` (per
  part and in all), and the seconds in `trace`'s printed summary and `batch`'s closing line;
- the date in the STEP header (`FILE_NAME(...)`);
- the keys given with `--ignore` (dotted paths into the report, e.g.
  `stats.open_ends_by_reason`, or `mat.degenerate[].touch` for a key of every element of an
  array), for fields that one binary adds or changes on purpose.

Prints one line per difference and exits 1 when there is any, 0 when every output is
identical. Needs only Python 3 (no third-party modules).
"""

import argparse
import concurrent.futures
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CORPUS_SUFFIXES = {".step", ".stp", ".igs", ".iges"}
# A part that takes longer than this is reported as a difference (both binaries should
# finish the corpus in about a minute).
TIMEOUT_SECONDS = 600


def corpus() -> list[Path]:
    """Every part of the corpus, in a fixed order."""
    dirs = [ROOT / "samples", ROOT / "samples" / "iges"]
    shared = ROOT.parent / "shared" / "realworld"
    dirs += [shared, shared / "more"]
    parts = []
    for d in dirs:
        if d.is_dir():
            parts += sorted(p for p in d.iterdir() if p.suffix.lower() in CORPUS_SUFFIXES)
    return parts


def is_iges(part: Path) -> bool:
    return part.suffix.lower() in {".igs", ".iges"}


def run(cmd: list[str], out: Path, name: str) -> None:
    """Runs `cmd`, keeping its exit status, stdout and stderr under `out/name.*`."""
    try:
        p = subprocess.run(cmd, capture_output=True, timeout=TIMEOUT_SECONDS)
        status, stdout, stderr = str(p.returncode), p.stdout, p.stderr
    except subprocess.TimeoutExpired:
        status, stdout, stderr = "timeout", b"", b""
    (out / f"{name}.status").write_text(status)
    (out / f"{name}.stdout").write_bytes(stdout)
    (out / f"{name}.stderr").write_bytes(stderr)


def run_part(binary: str, part: Path, out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    run([binary, "inspect", str(part)], out, "inspect")
    run([binary, "inspect", "--json", str(part)], out, "inspect-json")
    trace = [binary, "trace", str(part), "-o", str(out / "trace"), "--verify"]
    if not is_iges(part):
        trace.append("--with-solid")
    run(trace, out, "trace")


def run_all(binary: str, parts: list[Path], work: Path, jobs: int) -> None:
    with concurrent.futures.ThreadPoolExecutor(jobs) as pool:
        list(pool.map(lambda ip: run_part(binary, ip[1], work / f"{ip[0]:03}-{ip[1].name}"),
                      enumerate(parts)))
    run([binary, "batch", str(ROOT / "samples"), "-o", str(work / "batch"), "-j", str(jobs),
         "--verify"], work, "batch")


SECONDS = re.compile(rb"\d+\.\d+ s\b")
TIME_LINE = re.compile(rb"^  time: .*$", re.M)
STEP_DATE = re.compile(rb"FILE_NAME\('((?:[^']|'')*)','[^']*'")


def drop(obj, dotted: str) -> None:
    """Removes the key at the dotted path `dotted` from a JSON object, where present; a key
    written `name[]` stands for every element of the array `name` (`mat.degenerate[].touch`)."""
    key, _, rest = dotted.partition(".")
    if not isinstance(obj, dict):
        return
    if key.endswith("[]"):
        for item in obj.get(key[:-2], []) if rest else []:
            drop(item, rest)
        return
    if not rest:
        obj.pop(key, None)
    elif key in obj:
        drop(obj[key], rest)


def normalise(name: str, data: bytes, ignore: list[str], here: Path) -> bytes:
    """`data` of the file `name` with what may differ between runs taken out; `here`, the
    folder the run wrote to, becomes `<out>`."""
    data = data.replace(str(here).encode(), b"<out>")
    if name.endswith(".mat.json"):
        report = json.loads(data)
        for key in ["stats.seconds", "stats.timings", *ignore]:
            drop(report, key)
        return json.dumps(report, indent=1, sort_keys=True).encode()
    if name.endswith("summary.json"):
        summary = json.loads(data)
        summary.pop("seconds", None)
        for part in summary.get("parts", []):
            part.pop("seconds", None)
        return json.dumps(summary, indent=1, sort_keys=True).encode()
    if name.endswith("summary.csv"):
        rows = data.decode().splitlines()
        header = rows[0].split(",") if rows else []
        col = header.index("seconds") if "seconds" in header else None
        out = []
        for row in rows:
            cells = row.split(",")
            if col is not None and len(cells) == len(header):
                cells[col] = "-"
            out.append(",".join(cells))
        return "\n".join(out).encode()
    if name.endswith(".step") or name.endswith(".stp"):
        return STEP_DATE.sub(rb"FILE_NAME('\1','-'", data)
    if name.endswith(".stdout") or name.endswith(".stderr"):
        data = SECONDS.sub(b"- s", TIME_LINE.sub(b"  time: -", data))
        if name == "batch.stderr":
            # One line per finished part, in the order they finished; the counter
            # `[k/n]` in front follows that order too.
            lines = [re.sub(rb"^\[\d+/", b"[-/", x) for x in data.splitlines()]
            data = b"\n".join(sorted(lines))
        return data
    return data


def files_under(d: Path) -> dict[str, Path]:
    return {str(p.relative_to(d)): p for p in sorted(d.rglob("*")) if p.is_file()}


def compare(old: Path, new: Path, ignore: list[str]) -> list[str]:
    a, b = files_under(old), files_under(new)
    diffs = []
    for name in sorted(set(a) | set(b)):
        if name not in a or name not in b:
            diffs.append(f"{name}: only in {'new' if name in b else 'old'}")
            continue
        try:
            na = normalise(name, a[name].read_bytes(), ignore, old)
            nb = normalise(name, b[name].read_bytes(), ignore, new)
        except (ValueError, IndexError) as e:
            diffs.append(f"{name}: cannot normalise ({e})")
            continue
        if na != nb:
            diffs.append(f"{name}: differs{first_difference(na, nb)}")
    return diffs


def first_difference(a: bytes, b: bytes) -> str:
    la, lb = a.splitlines(), b.splitlines()
    for i, (x, y) in enumerate(zip(la, lb)):
        if x != y:
            return f" (line {i + 1}: {x[:120]!r} vs {y[:120]!r})"
    return f" ({len(la)} vs {len(lb)} lines)"


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def corpus_digest(parts: list[Path]) -> str:
    h = hashlib.sha256()
    for p in parts:
        h.update(str(p).encode() + b"\0" + digest(p).encode())
    return h.hexdigest()


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--work", type=Path, help="keep the outputs here (default: a temp dir)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--ignore", action="append", default=[],
                    help="dotted report key left out of the comparison (repeatable)")
    args = ap.parse_args()
    parts = corpus()
    work = args.work or Path(tempfile.mkdtemp(prefix="matrace-compare-"))
    work.mkdir(parents=True, exist_ok=True)
    for side, binary in [("old", args.old), ("new", args.new)]:
        # With --work, the old side's outputs are kept and reused while the binary and the
        # corpus are the same (the stamp holds both's hashes).
        stamp = work / f"{side}.stamp"
        key = f"{digest(Path(binary))} {corpus_digest(parts)}"
        if side == "old" and stamp.is_file() and stamp.read_text() == key:
            print(f"reusing {side} outputs ({binary} unchanged)", file=sys.stderr)
            continue
        shutil.rmtree(work / side, ignore_errors=True)
        stamp.unlink(missing_ok=True)
        print(f"running {side} ({binary}) on {len(parts)} parts", file=sys.stderr)
        run_all(str(Path(binary).resolve()), parts, work / side, args.jobs)
        stamp.write_text(key)
    diffs = compare(work / "old", work / "new", args.ignore)
    for d in diffs:
        print(d)
    n = len(files_under(work / "old"))
    print(f"{len(parts)} parts, {n} files compared, {len(diffs)} differences ({work})",
          file=sys.stderr)
    return 1 if diffs else 0


if __name__ == "__main__":
    sys.exit(main())
