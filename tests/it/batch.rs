//! `matrace batch`: failures recorded and isolated, summaries, `--resume`, `-j` independence,
//! `--shard`, the time limit, name clashes and argument errors.

use crate::common::{matrace, root, sample};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// A folder holding copies of `samples` plus `empty.step` (no bytes) and `garbage.step` (the
/// first 300 bytes of a STEP file).
fn inputs_with_two_broken(samples: &[&str]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in");
    std::fs::create_dir(&input).unwrap();
    for s in samples {
        std::fs::copy(sample(s), input.join(s)).unwrap();
    }
    std::fs::write(input.join("empty.step"), b"").unwrap();
    let text = std::fs::read(sample("box.step")).unwrap();
    std::fs::write(input.join("garbage.step"), &text[..300]).unwrap();
    dir
}

fn read_json(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

/// Status of every part of a summary, by the part's file name.
fn statuses(summary: &serde_json::Value) -> BTreeMap<String, String> {
    summary["parts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let name = Path::new(p["part"].as_str().unwrap())
                .file_name()
                .unwrap()
                .to_string_lossy()
                .into_owned();
            (name, p["status"].as_str().unwrap().to_string())
        })
        .collect()
}

/// Every file below `dir` with its modification time.
fn files_with_times(dir: &Path) -> BTreeMap<PathBuf, SystemTime> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let t = std::fs::metadata(&p).unwrap().modified().unwrap();
                out.insert(p.strip_prefix(dir).unwrap().to_path_buf(), t);
            }
        }
    }
    out
}

fn no_temp_files(dir: &Path) {
    for f in files_with_times(dir).keys() {
        let name = f.file_name().unwrap().to_string_lossy();
        assert!(!name.ends_with(".tmp"), "temp file left: {}", f.display());
    }
}

#[test]
fn batch_records_two_failures_and_resume_redoes_only_them() {
    let dir = inputs_with_two_broken(&["box.step", "l_bracket.step", "cylinder.step"]);
    let out = matrace(&["batch", "in", "-o", "out", "-j", "2"], dir.path());
    assert_eq!(
        out.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.lines().count(), 5, "one line per part: {stderr}");
    let o = dir.path().join("out");
    let summary = read_json(&o.join("summary.json"));
    assert_eq!(summary["schema"], "matrace.batch/1");
    assert_eq!(summary["counts"]["ok"], 3);
    assert_eq!(summary["counts"]["failed"], 2);
    let parts = summary["parts"].as_array().unwrap();
    // Input order: sorted by output name.
    let names: Vec<&str> = parts
        .iter()
        .map(|p| p["output"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["box", "cylinder", "empty", "garbage", "l_bracket"]);
    for p in parts {
        let part = p["part"].as_str().unwrap();
        if part.ends_with("empty.step") || part.ends_with("garbage.step") {
            assert_eq!(p["status"], "failed");
            let e = p["error"].as_str().unwrap();
            assert!(e.contains(part), "error names the file: {e}");
            assert!(p["seams"].is_null());
        } else {
            assert_eq!(p["status"], "ok", "{p}");
            assert!(p["error"].is_null());
            let stem = p["output"].as_str().unwrap();
            let outputs: Vec<&str> = p["outputs"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_str().unwrap())
                .collect();
            let want =
                ["mat.step", "sheets.obj", "mat.svg", "mat.json"].map(|s| format!("{stem}.{s}"));
            assert_eq!(outputs, want);
            for f in &want {
                assert!(o.join(f).is_file(), "{f}");
            }
            let report = read_json(&o.join(format!("{stem}.mat.json")));
            assert_eq!(p["seams"], report["stats"]["seams"]);
            assert_eq!(p["junctions"], report["stats"]["junctions"]);
            assert_eq!(p["open_ends"], report["stats"]["open_ends"]);
            assert_eq!(
                p["open_ends_by_reason"],
                report["stats"]["open_ends_by_reason"]
            );
            assert_eq!(
                p["degenerate_open_ends"],
                report["stats"]["degenerate_open_ends"]
            );
            assert_eq!(
                p["degenerate_open_ends_by_reason"],
                report["stats"]["degenerate_open_ends_by_reason"]
            );
            assert_eq!(
                p["faces"].as_u64().unwrap() as usize,
                report["model"]["faces"].as_array().unwrap().len()
            );
        }
    }
    let l = parts.iter().find(|p| p["output"] == "l_bracket").unwrap();
    assert_eq!(
        (l["faces"].as_u64(), l["seams"].as_u64()),
        (Some(8), Some(17))
    );
    let open: u64 = parts.iter().filter_map(|p| p["open_ends"].as_u64()).sum();
    assert_eq!(summary["counts"]["open_ends"], open);
    let open: u64 = parts
        .iter()
        .filter_map(|p| p["degenerate_open_ends"].as_u64())
        .sum();
    assert_eq!(summary["counts"]["degenerate_open_ends"], open);
    let csv = std::fs::read_to_string(o.join("summary.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 6, "{csv}");
    assert!(lines[0].starts_with("part,status,error,faces,seams,junctions,seconds,worst_error"));
    assert!(lines[3].contains("empty.step,failed,") && lines[3].contains("file is empty"));
    assert!(
        lines[5].contains("l_bracket.step,ok,,8,17,"),
        "{}",
        lines[5]
    );
    no_temp_files(&o);

    // --resume: the good parts are not run again (no output touched), the broken ones are
    // tried again and fail again.
    let before = files_with_times(&o);
    let again = matrace(
        &["batch", "in", "-o", "out", "-j", "2", "--resume"],
        dir.path(),
    );
    assert_eq!(again.status.code(), Some(1));
    let resumed = read_json(&o.join("summary.json"));
    assert_eq!(resumed["counts"]["resumed"], 3);
    assert_eq!(statuses(&resumed), statuses(&summary));
    for (p, q) in parts.iter().zip(resumed["parts"].as_array().unwrap()) {
        assert_eq!(q["resumed"], p["status"] == "ok");
        for k in ["part", "output", "faces", "seams", "junctions", "outputs"] {
            assert_eq!(p[k], q[k], "{k}");
        }
        if p["status"] == "ok" {
            // The time is the report's: the part was not traced again.
            assert_eq!(p["seconds"], q["seconds"]);
        }
    }
    let after = files_with_times(&o);
    for (f, t) in &before {
        if !f.to_string_lossy().starts_with("summary") {
            assert_eq!(after.get(f), Some(t), "{} was rewritten", f.display());
        }
    }
    assert_eq!(
        after.keys().collect::<Vec<_>>(),
        before.keys().collect::<Vec<_>>()
    );

    // An input newer than its report is traced again; so is one whose outputs are not all
    // there.
    let future = SystemTime::now() + std::time::Duration::from_secs(60);
    let f = std::fs::File::options()
        .append(true)
        .open(dir.path().join("in/box.step"))
        .unwrap();
    f.set_modified(future).unwrap();
    std::fs::remove_file(o.join("cylinder.mat.svg")).unwrap();
    let third = matrace(&["batch", "in", "-o", "out", "--resume"], dir.path());
    assert_eq!(third.status.code(), Some(1));
    let s = read_json(&o.join("summary.json"));
    let resumed: Vec<(&str, bool)> = s["parts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            (
                p["output"].as_str().unwrap(),
                p["resumed"].as_bool().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        resumed,
        [
            ("box", false),
            ("cylinder", false),
            ("empty", false),
            ("garbage", false),
            ("l_bracket", true)
        ]
    );
    assert!(o.join("cylinder.mat.svg").is_file());
}

/// The report without its timings (the stages' and each seam's).
fn report_without_times(path: &Path) -> serde_json::Value {
    let mut v = read_json(path);
    let stats = v["stats"].as_object_mut().unwrap();
    stats.remove("seconds").unwrap();
    stats.remove("timings").unwrap();
    stats.remove("seam_trace_ms").unwrap();
    v
}

/// A file's bytes, but the date in a STEP header's `FILE_NAME` (the time of writing).
fn without_date(path: &Path) -> Vec<u8> {
    let bytes = std::fs::read(path).unwrap();
    let Ok(text) = String::from_utf8(bytes.clone()) else {
        return bytes;
    };
    text.lines()
        .map(|l| match l.strip_prefix("FILE_NAME(") {
            Some(rest) => {
                let fields: Vec<&str> = rest.splitn(3, ',').collect();
                assert_eq!(fields.len(), 3, "{l}");
                format!("FILE_NAME({},<date>,{}", fields[0], fields[2])
            }
            None => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
        .into_bytes()
}

#[test]
fn outputs_do_not_depend_on_the_number_of_jobs() {
    let dir = inputs_with_two_broken(&[
        "box.step",
        "l_bracket.step",
        "cylinder.step",
        "two_solids.step",
    ]);
    for j in ["1", "2"] {
        let out = matrace(
            &["batch", "in", "-o", &format!("out{j}"), "-j", j],
            dir.path(),
        );
        assert_eq!(out.status.code(), Some(1));
    }
    let (a, b) = (dir.path().join("out1"), dir.path().join("out2"));
    let files: Vec<PathBuf> = files_with_times(&a).into_keys().collect();
    assert_eq!(files, files_with_times(&b).into_keys().collect::<Vec<_>>());
    assert_eq!(files.len(), 4 * 4 + 2, "{files:?}");
    for f in &files {
        let name = f.to_string_lossy();
        if name.ends_with(".mat.json") {
            assert_eq!(
                report_without_times(&a.join(f)),
                report_without_times(&b.join(f)),
                "{name}"
            );
        } else if name.starts_with("summary") {
            continue;
        } else {
            assert!(
                without_date(&a.join(f)) == without_date(&b.join(f)),
                "{name} differs between -j 1 and -j 2"
            );
        }
    }
    let (sa, sb) = (
        read_json(&a.join("summary.json")),
        read_json(&b.join("summary.json")),
    );
    assert_eq!(
        (sa["jobs"].as_u64(), sb["jobs"].as_u64()),
        (Some(1), Some(2))
    );
    for (p, q) in sa["parts"]
        .as_array()
        .unwrap()
        .iter()
        .zip(sb["parts"].as_array().unwrap())
    {
        let mut p = p.clone();
        let mut q = q.clone();
        p["seconds"] = 0.into();
        q["seconds"] = 0.into();
        assert_eq!(p, q);
    }
}

#[test]
fn shards_cover_every_input_exactly_once() {
    let dir =
        inputs_with_two_broken(&["box.step", "l_bracket.step", "cylinder.step", "wedge.step"]);
    let all = matrace(
        &["batch", "in", "-o", "all", "--no-mesh", "--no-svg"],
        dir.path(),
    );
    assert_eq!(all.status.code(), Some(1));
    let all = read_json(&dir.path().join("all/summary.json"));
    let mut seen = vec![];
    for k in ["1/2", "2/2"] {
        let out = matrace(
            &[
                "batch",
                "in",
                "-o",
                "shared",
                "--shard",
                k,
                "--no-mesh",
                "--no-svg",
            ],
            dir.path(),
        );
        assert!(matches!(out.status.code(), Some(0 | 1)));
        let name = format!("summary.{}.json", k.replace('/', "-of-"));
        let s = read_json(&dir.path().join("shared").join(name));
        assert_eq!(s["shard"], k);
        assert_eq!(s["inputs"], 6);
        let parts = s["parts"].as_array().unwrap();
        assert_eq!(parts.len(), 3);
        seen.extend(
            parts
                .iter()
                .map(|p| p["part"].as_str().unwrap().to_string()),
        );
    }
    assert!(!dir.path().join("shared/summary.json").exists());
    let mut want: Vec<String> = all["parts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["part"].as_str().unwrap().to_string())
        .collect();
    // Shard 1 has inputs 1, 3, 5 and shard 2 inputs 2, 4, 6.
    let interleaved: Vec<String> = (0..3)
        .flat_map(|i| [seen[i].clone(), seen[i + 3].clone()])
        .collect();
    assert_eq!(interleaved, want);
    want.sort();
    seen.sort();
    assert_eq!(seen, want);
}

#[test]
fn a_part_over_the_time_limit_is_killed_and_recorded() {
    let dir = inputs_with_two_broken(&["box.step", "l_bracket.step"]);
    std::fs::remove_file(dir.path().join("in/empty.step")).unwrap();
    std::fs::remove_file(dir.path().join("in/garbage.step")).unwrap();
    // No process starts, reads and traces a part within a millisecond.
    let out = matrace(
        &["batch", "in", "-o", "out", "--timeout", "0.001"],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(1));
    let o = dir.path().join("out");
    let s = read_json(&o.join("summary.json"));
    assert_eq!(s["counts"]["timeout"], 2);
    for p in s["parts"].as_array().unwrap() {
        assert_eq!(p["status"], "timeout");
        assert!(
            p["error"]
                .as_str()
                .unwrap()
                .contains("time limit of 0.001 s"),
            "{p}"
        );
    }
    no_temp_files(&o);
    assert!(!o.join("box.mat.json").exists());
    // Within a generous limit the same batch succeeds, exit status 0.
    let out = matrace(
        &["batch", "in", "-o", "out", "--timeout", "600", "--resume"],
        dir.path(),
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let s = read_json(&o.join("summary.json"));
    assert_eq!(s["counts"]["ok"], 2);
    assert_eq!(s["counts"]["resumed"], 0);
}

#[test]
fn a_part_over_the_memory_limit_crashes_alone() {
    if matrace::batch::find_in_path("prlimit").is_none() {
        eprintln!("prlimit not installed: no memory limit to test");
        return;
    }
    let dir = inputs_with_two_broken(&["box.step"]);
    std::fs::copy(sample("l_bracket.step"), dir.path().join("big.step")).unwrap();
    // 10 MiB of address space: too little for any trace (16 MiB is enough for box.step).
    let out = matrace(
        &[
            "batch",
            "big.step",
            "in",
            "-o",
            "out",
            "--max-memory",
            "10",
            "--no-mesh",
            "--no-svg",
        ],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(1));
    let s = read_json(&dir.path().join("out/summary.json"));
    assert_eq!(s["memory_limit_bytes"], 10 << 20);
    assert_eq!(s["parts"].as_array().unwrap().len(), 4);
    for p in s["parts"].as_array().unwrap() {
        assert_eq!(p["status"], "failed", "{p}");
        let e = p["error"].as_str().unwrap();
        assert!(e.starts_with(p["part"].as_str().unwrap()), "{e}");
        if p["output"] == "big" || p["output"] == "box" {
            assert!(e.contains("crashed"), "{e}");
        }
    }
    no_temp_files(&dir.path().join("out"));
}

#[test]
fn parts_with_the_same_name_do_not_overwrite_each_other() {
    let dir = tempfile::tempdir().unwrap();
    for (sub, s) in [("a", "box.step"), ("b", "wedge.step")] {
        let d = dir.path().join("lib").join(sub);
        std::fs::create_dir_all(&d).unwrap();
        std::fs::copy(sample(s), d.join("part.step")).unwrap();
    }
    // As a folder: its tree is mirrored.
    let out = matrace(&["batch", "lib", "-o", "out1", "--no-svg"], dir.path());
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let o = dir.path().join("out1");
    assert_eq!(read_json(&o.join("a/part.mat.json"))["stats"]["seams"], 12);
    assert_eq!(read_json(&o.join("b/part.mat.json"))["stats"]["seams"], 7);
    assert!(o.join("a/part.sheets.obj").is_file() && o.join("b/part.mat.step").is_file());
    // An output folder inside the input folder is not taken for input.
    for _ in 0..2 {
        let out = matrace(&["batch", "lib", "-o", "lib/mat", "--no-svg"], dir.path());
        assert_eq!(
            out.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let s = read_json(&dir.path().join("lib/mat/summary.json"));
        assert_eq!(s["inputs"], 2);
    }
    std::fs::remove_dir_all(dir.path().join("lib/mat")).unwrap();
    // As files: the names get a hash of the path.
    let out = matrace(
        &[
            "batch",
            "a/part.step",
            "b/part.step",
            "-o",
            "../out2",
            "--no-svg",
        ],
        &dir.path().join("lib"),
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let s = read_json(&dir.path().join("out2/summary.json"));
    assert_eq!(s["parts"].as_array().unwrap().len(), 2);
    let mut seams = BTreeMap::new();
    for p in s["parts"].as_array().unwrap() {
        let stem = p["output"].as_str().unwrap();
        assert!(stem.starts_with("part-") && stem.len() == 13, "{stem}");
        let r = read_json(&dir.path().join("out2").join(format!("{stem}.mat.json")));
        assert_eq!(r["input"]["path"], p["part"]);
        seams.insert(
            p["part"].as_str().unwrap().to_string(),
            r["stats"]["seams"].clone(),
        );
    }
    assert_eq!(seams["a/part.step"], 12);
    assert_eq!(seams["b/part.step"], 7);
}

#[test]
fn unusable_batch_arguments_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("empty")).unwrap();
    std::fs::write(dir.path().join("a_file"), b"").unwrap();
    let box_step = sample("box.step");
    let b = box_step.to_str().unwrap();
    for args in [
        vec!["batch", "empty", "-o", "out"],
        vec!["batch", "missing.step", "-o", "out"],
        vec!["batch", b],
        vec!["batch", b, "-o", "out", "--shard", "3/2"],
        vec!["batch", b, "-o", "out", "--shard", "0/2"],
        vec!["batch", b, "-o", "out", "-j", "0"],
        vec!["batch", b, "-o", "out", "--timeout", "-1"],
        vec!["batch", b, "-o", "out", "--tol", "0"],
        vec!["batch", b, "-o", "a_file/out"],
    ] {
        let out = matrace(&args, dir.path());
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(!out.stderr.is_empty());
    }
    assert!(!dir.path().join("out").exists());
}

/// The demonstration: every sample plus two broken files; `--resume` does no work.
/// (Without sheet meshes and pictures, to keep the test short.)
#[test]
fn batch_over_all_samples_and_two_broken_files() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in");
    std::fs::create_dir(&input).unwrap();
    let mut good = vec![];
    for e in std::fs::read_dir(root().join("samples")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "step") {
            std::fs::copy(&p, input.join(p.file_name().unwrap())).unwrap();
            good.push(p.file_stem().unwrap().to_string_lossy().into_owned());
        }
    }
    assert_eq!(good.len(), 29);
    std::fs::write(input.join("empty.step"), b"").unwrap();
    std::fs::write(
        input.join("garbage.stp"),
        b"ISO-10303-21;\nHEADER;\n#1=garbage(",
    )
    .unwrap();
    let args = ["batch", "in", "-o", "out", "--no-mesh", "--no-svg"];
    let out = matrace(&args, dir.path());
    assert_eq!(
        out.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let o = dir.path().join("out");
    let s = read_json(&o.join("summary.json"));
    assert_eq!(
        (s["counts"]["ok"].as_u64(), s["counts"]["failed"].as_u64()),
        (Some(29), Some(2)),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let st = statuses(&s);
    assert_eq!(st["empty.step"], "failed");
    assert_eq!(st["garbage.stp"], "failed");
    for stem in &good {
        for suffix in ["mat.step", "mat.json"] {
            assert!(
                o.join(format!("{stem}.{suffix}")).is_file(),
                "{stem}.{suffix}"
            );
        }
    }
    no_temp_files(&o);
    let before = files_with_times(&o);
    let again = matrace(&[&args[..], &["--resume"]].concat(), dir.path());
    assert_eq!(again.status.code(), Some(1));
    let s = read_json(&o.join("summary.json"));
    assert_eq!(s["counts"]["resumed"], 29);
    for (f, t) in &before {
        if !f.to_string_lossy().starts_with("summary") {
            assert_eq!(files_with_times(&o).get(f), Some(t), "{}", f.display());
        }
    }
}
