//! Bad input: each case gives exit status 2 and one clear line on stderr naming the file and
//! the problem, never a panic. Each test writes its input into its own temp dir.

use crate::common::{matrace, sample};
use std::path::Path;

/// Runs `matrace inspect FILE` and checks: status 2, stderr one line, naming the file, and
/// containing `needle`; no panic message.
fn rejects(file: &Path, needle: &str) {
    let out = matrace(&["inspect", file.to_str().unwrap()], file.parent().unwrap());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        out.status.code(),
        Some(2),
        "status for {file:?}; stderr: {err}"
    );
    assert!(
        out.stdout.is_empty(),
        "stdout for a bad file: {}",
        String::from_utf8_lossy(&out.stdout)
    );
    assert_eq!(
        err.trim_end().lines().count(),
        1,
        "one line expected: {err}"
    );
    assert!(!err.contains("panicked"), "panic: {err}");
    let name = file.file_name().unwrap().to_str().unwrap();
    assert!(err.contains(name), "error does not name the file: {err}");
    assert!(err.contains(needle), "error does not say {needle:?}: {err}");
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

fn box_text() -> String {
    std::fs::read_to_string(sample("box.step")).unwrap()
}

#[test]
fn missing_file() {
    let dir = tempfile::tempdir().unwrap();
    rejects(&dir.path().join("nope.step"), "cannot read file");
}

#[test]
fn empty_file() {
    let dir = tempfile::tempdir().unwrap();
    rejects(&write(dir.path(), "empty.step", b""), "file is empty");
}

#[test]
fn random_bytes() {
    let dir = tempfile::tempdir().unwrap();
    // Deterministic pseudo-random bytes (xorshift), not valid UTF-8.
    let mut x: u64 = 0x9e3779b97f4a7c15;
    let bytes: Vec<u8> = (0..4096)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 24) as u8
        })
        .collect();
    rejects(
        &write(dir.path(), "noise.step", &bytes),
        "not a readable STEP file",
    );
}

#[test]
fn not_a_step_file() {
    let dir = tempfile::tempdir().unwrap();
    rejects(
        &write(dir.path(), "part.step", b"solid cube\nfacet normal 0 0 1\n"),
        "not a STEP file",
    );
}

#[test]
fn truncated_step() {
    let dir = tempfile::tempdir().unwrap();
    let text = box_text();
    let cut = &text[..text.len() / 2];
    rejects(
        &write(dir.path(), "truncated.step", cut.as_bytes()),
        "truncated",
    );
}

#[test]
fn truncated_inside_an_entity_with_end_marker() {
    // Cut mid-record, but keep the end marker: the parser itself must report it.
    let dir = tempfile::tempdir().unwrap();
    let text = box_text();
    let cut = format!("{}\nENDSEC;\nEND-ISO-10303-21;\n", &text[..text.len() / 2]);
    rejects(
        &write(dir.path(), "cut.step", cut.as_bytes()),
        "not a readable STEP file",
    );
}

/// An assembly whose parts are in files of their own (AP214 external references, as CATIA V5
/// writes them): the error names those files.
#[test]
fn step_assembly_of_external_files() {
    let dir = tempfile::tempdir().unwrap();
    let text = "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\n\
        FILE_NAME('x','',(''),(''),'','','');\nFILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\n\
        DATA;\n#1=DOCUMENT_TYPE('geometry');\n\
        #2=DOCUMENT_FILE('FOOT_FRONT_000.stp','','',#1,'',$);\n\
        #3=DOCUMENT_FILE('FOOT_BACK_000.stp','','',#1,'',$);\nENDSEC;\nEND-ISO-10303-21;\n";
    rejects(
        &write(dir.path(), "foot.step", text.as_bytes()),
        "its parts are in other files it refers to (FOOT_FRONT_000.stp, FOOT_BACK_000.stp)",
    );
}

#[test]
fn step_without_a_solid() {
    let dir = tempfile::tempdir().unwrap();
    let text = "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\nFILE_NAME('x','',(''),(''),'','','');\nFILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\nDATA;\n#1=CARTESIAN_POINT('',(0.,0.,0.));\nENDSEC;\nEND-ISO-10303-21;\n";
    rejects(
        &write(dir.path(), "nosolid.step", text.as_bytes()),
        "no solid",
    );
}

#[test]
fn unsupported_surface_type() {
    // Replace the box's first PLANE by an OFFSET_SURFACE of it (a type we do not read).
    let dir = tempfile::tempdir().unwrap();
    let text = box_text();
    let (id, rest) = first_instance_of(&text, "PLANE(");
    let plane_args = &rest[rest.find('(').unwrap()..];
    let new_id = 99999;
    let patched = text.replacen(
        &format!("#{id} = PLANE{plane_args};"),
        &format!("#{id} = OFFSET_SURFACE('',#{new_id},1.,.F.);\n#{new_id} = PLANE{plane_args};"),
        1,
    );
    assert_ne!(patched, text, "patch applied");
    rejects(
        &write(dir.path(), "offset.step", patched.as_bytes()),
        "unsupported surface type",
    );
}

#[test]
fn unsorted_knots() {
    // The bicubic top is written `...,(4,1,4),(4,1,4),(0.,0.5,1.),(0.,0.5,1.)`: reverse the
    // u-knots.
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(sample("box_bspline_top.step")).unwrap();
    let patched = text.replacen("(4,1,4),(0.,0.5,1.),", "(4,1,4),(1.,0.5,0.),", 1);
    assert_ne!(
        patched, text,
        "the sample's knot vector changed: update this test"
    );
    rejects(
        &write(dir.path(), "knots.step", patched.as_bytes()),
        "knots not sorted",
    );
}

/// Multiplicities that are not one per knot (truck indexes one by the other and panicked):
/// a knot vector of the top loses its middle value, its multiplicities keep three.
#[test]
fn knot_multiplicities_not_one_per_knot() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(sample("box_bspline_top.step")).unwrap();
    let patched = text.replacen("(4,1,4),(0.,0.5,1.),", "(4,1,4),(0.,1.),", 1);
    assert_ne!(
        patched, text,
        "the sample's knot vector changed: update this test"
    );
    rejects(
        &write(dir.path(), "mults.step", patched.as_bytes()),
        "do not match the knots",
    );
}

#[test]
fn open_shell() {
    // Drop one face from the box's shell: its edges are then used once.
    let dir = tempfile::tempdir().unwrap();
    let text = box_text();
    let (id, rest) = first_instance_of(&text, "CLOSED_SHELL(");
    let list_start = rest.find("(#").unwrap() + 1;
    let first_face_end = rest[list_start..].find(',').unwrap() + list_start;
    let patched_rest = format!("{}{}", &rest[..list_start], &rest[first_face_end + 1..]);
    let patched = text.replacen(rest, &patched_rest, 1);
    assert_ne!(patched, text);
    let _ = id;
    rejects(
        &write(dir.path(), "open.step", patched.as_bytes()),
        "closed shell",
    );
}

#[test]
fn reference_to_undefined_entity() {
    let dir = tempfile::tempdir().unwrap();
    let text = box_text();
    let (id, rest) = first_instance_of(&text, "VERTEX_POINT(");
    let patched_rest = rest.replacen("#", "#777777", 1);
    let patched = text.replacen(rest, &patched_rest, 1);
    let _ = id;
    rejects(
        &write(dir.path(), "dangling.step", patched.as_bytes()),
        "does not define",
    );
}

/// A constant name (`#FACE_BOUND31`) or a value instance (`@3`) where an entity is expected:
/// truck's reader panics on them ("not implemented"); found by `cargo fuzz` (ingest_step).
#[test]
fn constant_and_value_instance_names() {
    let dir = tempfile::tempdir().unwrap();
    let text = box_text();
    let (_, rest) = first_instance_of(&text, "VERTEX_POINT(");
    for (name, file) in [("#FACE_BOUND31", "constant.step"), ("@3", "value.step")] {
        let at = rest.find('#').unwrap();
        let digits = rest[at + 1..].find(|c: char| !c.is_ascii_digit()).unwrap();
        let patched_rest = format!("{}{name}{}", &rest[..at], &rest[at + 1 + digits..]);
        let patched = text.replacen(rest, &patched_rest, 1);
        rejects(
            &write(dir.path(), file, patched.as_bytes()),
            &format!("refers to {name}: constant and value-instance names are not supported"),
        );
    }
}

#[test]
fn reference_cycle() {
    let dir = tempfile::tempdir().unwrap();
    let text = box_text();
    let (id, rest) = first_instance_of(&text, "EDGE_CURVE(");
    // Make the edge its own start vertex.
    let open = rest.find("#").unwrap();
    let comma = open + rest[open..].find(',').unwrap();
    let patched_rest = format!("{}#{id}{}", &rest[..open], &rest[comma..]);
    let patched = text.replacen(rest, &patched_rest, 1);
    rejects(
        &write(dir.path(), "cycle.step", patched.as_bytes()),
        "reference cycle",
    );
}

/// A cycle through entities nothing reads is no reason to refuse the part: a CAx-IF file
/// written by Datakit/Open CASCADE holds a material density as `REPRESENTATION('density',
/// (#3381),#1454)`, its own item. The part is read, with a warning naming the entity.
#[test]
fn reference_cycle_nothing_reads() {
    let dir = tempfile::tempdir().unwrap();
    let text = box_text();
    let end = text.rfind("ENDSEC;").unwrap();
    let patched = format!(
        "{}#999998 = REPRESENTATION('density',(#999998),#999997);\n\
         #999997 = REPRESENTATION_CONTEXT('','');\n{}",
        &text[..end],
        &text[end..]
    );
    let file = write(dir.path(), "density.step", patched.as_bytes());
    let out = matrace(&["inspect", file.to_str().unwrap()], dir.path());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "stderr: {err}");
    assert!(
        err.contains("#999998 REPRESENTATION")
            && err.contains("reference cycle through entities the reader does not use"),
        "stderr: {err}"
    );
}

#[test]
fn a_directory() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("part.step");
    std::fs::create_dir(&sub).unwrap();
    rejects(&sub, "directory");
}

/// A FIFO named like a part would block a reader forever, and a device never ends: both are
/// refused at once, before any byte is read.
#[test]
fn not_a_regular_file() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("x.step");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .expect("run mkfifo");
    assert!(made.success(), "mkfifo failed");
    rejects(&fifo, "not a regular file");
    let out = matrace(&["inspect", "/dev/zero"], dir.path());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("/dev/zero") && err.contains("not a regular file"),
        "{err}"
    );
}

/// A negative radius is refused naming its entity (truck would build a circle of radius 5
/// run the other way from `CIRCLE(…, -5.)`).
#[test]
fn negative_radius() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(sample("cylinder.step")).unwrap();
    let bad = text.replacen(
        "CYLINDRICAL_SURFACE('',#32,10.)",
        "CYLINDRICAL_SURFACE('',#32,-10.)",
        1,
    );
    assert_ne!(bad, text);
    let file = write(dir.path(), "negative_radius.step", bad.as_bytes());
    rejects(&file, "#31 CYLINDRICAL_SURFACE: radius -10");
    let bad = text.replacen("CIRCLE('',#26,10.)", "CIRCLE('',#26,-10.)", 1);
    assert_ne!(bad, text);
    let file = write(dir.path(), "negative_circle.step", bad.as_bytes());
    rejects(&file, "#25 CIRCLE: radius -10");
}

/// The id and the text (from `NAME(` to the end of the record) of the first instance of
/// entity `name_paren` (e.g. `"PLANE("`), as written by FreeCAD (`#12 = PLANE(...);`).
fn first_instance_of<'a>(text: &'a str, name_paren: &str) -> (u64, &'a str) {
    let at = text
        .find(&format!("= {name_paren}"))
        .expect("entity present");
    let line_start = text[..at].rfind('#').unwrap();
    let id: u64 = text[line_start + 1..at].trim().parse().unwrap();
    let body_start = at + 2;
    let end = body_start + text[body_start..].find(';').unwrap();
    (id, &text[body_start..end])
}

/// Parentheses nested 100 000 deep overflowed ruststep's recursive parser (an abort, not even a
/// panic): our reader refuses them past depth 64, naming the line.
#[test]
fn deeply_nested_lists() {
    let dir = tempfile::tempdir().unwrap();
    let text = box_text();
    let deep = format!("{}1.{}", "(".repeat(100_000), ")".repeat(100_000));
    let text = text.replacen(
        "CARTESIAN_POINT('',(0.,0.,0.))",
        &format!("CARTESIAN_POINT('',{deep})"),
        1,
    );
    rejects(
        &write(dir.path(), "deep.step", text.as_bytes()),
        "nested more than 64 deep",
    );
}

/// A coordinate that overflows to infinity (`1.E400`) on a vertex is refused.
#[test]
fn infinite_coordinate() {
    let dir = tempfile::tempdir().unwrap();
    let text = box_text();
    // The first vertex's point.
    let v = text.find("VERTEX_POINT('',#").unwrap() + "VERTEX_POINT('',#".len();
    let id: String = text[v..]
        .chars()
        .take_while(|c| c.is_ascii_digit())
        .collect();
    let start = text.find(&format!("#{id} = CARTESIAN_POINT(")).unwrap();
    let end = start + text[start..].find(';').unwrap();
    let text = format!(
        "{}#{id} = CARTESIAN_POINT('',(1.E400,0.,0.)){}",
        &text[..start],
        &text[end..]
    );
    rejects(&write(dir.path(), "inf.step", text.as_bytes()), "finite");
}

/// xorshift64: deterministic pseudo-random numbers for the mutation tests.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// One random damage to a STEP text: a digit changed, a line dropped, duplicated or swapped,
/// a reference redirected, junk inserted, or the text cut.
fn mutate(text: &str, rng: &mut Rng) -> Vec<u8> {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let n = lines.len();
    match rng.below(7) {
        0 => {
            let mut b = text.as_bytes().to_vec();
            let digits: Vec<usize> = (0..b.len()).filter(|&i| b[i].is_ascii_digit()).collect();
            let i = digits[rng.below(digits.len())];
            b[i] = b'0' + rng.below(10) as u8;
            return b;
        }
        1 => {
            lines.remove(rng.below(n));
        }
        2 => {
            let l = lines[rng.below(n)].clone();
            lines.insert(rng.below(n), l);
        }
        3 => {
            let (a, b) = (rng.below(n), rng.below(n));
            lines.swap(a, b);
        }
        4 => {
            let i = rng.below(n);
            if let Some(p) = lines[i].rfind('#') {
                let to = format!("#{}", 1 + rng.below(2 * n));
                let end = p
                    + 1
                    + lines[i][p + 1..]
                        .find(|c: char| !c.is_ascii_digit())
                        .unwrap_or(lines[i].len() - p - 1);
                lines[i].replace_range(p..end, &to);
            }
        }
        5 => {
            let junk = [
                "(", ")", "'", ",", ";", "$", "*", "#", "1.E999", "-", "\u{0}",
            ];
            let i = rng.below(n);
            let at = rng.below(lines[i].len() + 1);
            if lines[i].is_char_boundary(at) {
                lines[i].insert_str(at, junk[rng.below(junk.len())]);
            }
        }
        _ => {
            let cut = rng.below(text.len());
            return text.as_bytes()[..cut].to_vec();
        }
    }
    (lines.join("\n") + "\n").into_bytes()
}

/// Damaged STEP files read as a model or fail with an error naming the file — never a panic,
/// never a hang. (A long run: `MATRACE_FUZZ_CASES=100000 cargo test --release --test it
/// damaged_step`.)
#[test]
fn damaged_step_never_panics() {
    let cases: usize = std::env::var("MATRACE_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(300);
    for (k, name) in ["box.step", "l_bracket_nurbs.step", "cylinder.step"]
        .iter()
        .enumerate()
    {
        let text = std::fs::read_to_string(sample(name)).unwrap();
        let mut rng = Rng(0x2545f4914f6cdd1d ^ (k as u64 + 1));
        for case in 0..cases {
            let bytes = mutate(&text, &mut rng);
            let path = Path::new("damaged.step");
            let result = std::panic::catch_unwind(|| {
                matrace::ingest::read_model_from_bytes(path, &bytes).map(|_| ())
            });
            match result {
                Ok(Ok(())) => {}
                Ok(Err(e)) => {
                    let msg = e.to_string();
                    assert!(
                        msg.starts_with("damaged.step: "),
                        "{name} case {case}: {msg}"
                    );
                    // A panic in truck that the reader caught is a check the reader lacks.
                    assert!(
                        !msg.contains("panicked"),
                        "{name} case {case}: a caught panic: {msg}"
                    );
                }
                Err(_) => panic!("{name} case {case}: the reader panicked"),
            }
        }
    }
}

/// A B-spline surface declared with degree 1000, and one whose degree does not match its
/// knots and control points: truck would derive another degree from the knots and silently
/// use a different surface; both are refused, naming the entity.
#[test]
fn absurd_or_inconsistent_bspline_degree() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(sample("box_bspline_top.step")).unwrap();
    let at = text.find("B_SPLINE_SURFACE_WITH_KNOTS('',3,3,").unwrap();
    let head = "B_SPLINE_SURFACE_WITH_KNOTS('',";
    let with = |degrees: &str| {
        format!(
            "{}{head}{degrees},{}",
            &text[..at],
            &text[at + head.len() + "3,3,".len()..]
        )
    };
    rejects(
        &write(dir.path(), "degree1000.step", with("1000,1000").as_bytes()),
        "degree 1000 (1 to 25 supported)",
    );
    rejects(
        &write(dir.path(), "degree2.step", with("2,3").as_bytes()),
        "needs knot multiplicities summing to",
    );
}

/// A B-spline surface with a 201 × 201 control net is refused before anything projects onto it
/// (a 1000 × 1000 one kept the reader busy for minutes).
#[test]
fn huge_control_net() {
    let dir = tempfile::tempdir().unwrap();
    let text = box_text();
    let n = 201;
    let row = format!("({})", vec!["#23"; n].join(","));
    let rows = vec![row; n].join(",");
    let mults = format!("(2,{},2)", vec!["1"; n - 2].join(","));
    let knots = format!(
        "({})",
        (0..n)
            .map(|k| format!("{k}."))
            .collect::<Vec<_>>()
            .join(",")
    );
    let record = format!(
        "#900000 = B_SPLINE_SURFACE_WITH_KNOTS('',1,1,({rows}),.UNSPECIFIED.,.F.,.F.,.F.,\
         {mults},{mults},{knots},{knots},.UNSPECIFIED.);\n"
    );
    let at = text.rfind("ENDSEC;").unwrap();
    let bad = format!("{}{record}{}", &text[..at], &text[at..]);
    rejects(
        &write(dir.path(), "huge_net.step", bad.as_bytes()),
        "#900000 B_SPLINE_SURFACE_WITH_KNOTS: control net of 201 × 201 points",
    );
}

/// Knot multiplicities chosen so that their sum wraps around `i64` to exactly the total the
/// degree needs (i64::MAX + i64::MAX + 11 ≡ 9): truck would then expand a knot vector of 2⁶⁴
/// entries. A negative multiplicity with the right sum is refused too.
#[test]
fn huge_or_negative_knot_multiplicities() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(sample("box_bspline_top.step")).unwrap();
    let mults = "(4,1,4),(4,1,4)";
    assert!(text.contains(mults));
    let huge = text.replacen(
        mults,
        "(9223372036854775807,9223372036854775807,11),(4,1,4)",
        1,
    );
    rejects(
        &write(dir.path(), "wrapping_mults.step", huge.as_bytes()),
        "needs knot multiplicities summing to 9, not 18446744073709551625",
    );
    let negative = text.replacen(mults, "(4,-1,6),(4,1,4)", 1);
    rejects(
        &write(dir.path(), "negative_mults.step", negative.as_bytes()),
        "knot multiplicity -1",
    );
}

/// A part kilometres across (millimetres written as kilometres) is refused as a scale error
/// instead of being traced with squared distances near 1e15.
#[test]
fn absurd_part_size() {
    let dir = tempfile::tempdir().unwrap();
    let text = box_text().replace(".MILLI.,.METRE.", ".KILO.,.METRE.");
    rejects(
        &write(dir.path(), "kilometres.step", text.as_bytes()),
        "mm across",
    );
}

/// Runs `matrace ARGS` under a 3 GiB address-space limit (where `prlimit` exists) and a
/// 10-minute deadline; the deadline is a bound on a hang, not a speed figure.
fn bounded(args: &[&str], cwd: &Path) -> std::process::Output {
    let exe = env!("CARGO_BIN_EXE_matrace");
    let mut cmd = match matrace::batch::find_in_path("prlimit") {
        Some(prlimit) => {
            let mut c = std::process::Command::new(prlimit);
            c.arg(format!("--as={}", 3u64 << 30)).arg("--").arg(exe);
            c
        }
        None => std::process::Command::new(exe),
    };
    let mut child = cmd
        .args(args)
        .current_dir(cwd)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(600);
    loop {
        if child.try_wait().unwrap().is_some() {
            return child.wait_with_output().unwrap();
        }
        if std::time::Instant::now() > deadline {
            child.kill().ok();
            panic!("matrace {args:?} did not finish within 10 minutes");
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
}

/// The box followed by 100 MB of points no solid uses: read within the memory bound, and the
/// box comes out as before. The same file cut inside its last megabyte is a syntax error
/// naming the line.
#[test]
fn hundred_megabyte_file() {
    use std::io::Write;
    let dir = tempfile::tempdir().unwrap();
    let text = box_text();
    let end = text.rfind("ENDSEC;").unwrap();
    let path = dir.path().join("huge.step");
    let mut f = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
    f.write_all(&text.as_bytes()[..end]).unwrap();
    let mut written = end;
    let mut id = 1_000_000u64;
    while written < 100 << 20 {
        let line = format!(
            "#{id}=CARTESIAN_POINT('',({}.5,{}.25,-{}.125));\n",
            id % 977,
            id % 331,
            id % 97
        );
        f.write_all(line.as_bytes()).unwrap();
        written += line.len();
        id += 1;
    }
    f.write_all(&text.as_bytes()[end..]).unwrap();
    drop(f);
    let out = bounded(&["inspect", path.to_str().unwrap()], dir.path());
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "status {:?}: {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("faces 6  edges 12"), "{stdout}");

    // Cut it 500 kB before the end, keeping the end marker.
    let bytes = std::fs::read(&path).unwrap();
    let mut cut = bytes[..bytes.len() - 500_000].to_vec();
    cut.extend_from_slice(b"\nENDSEC;\nEND-ISO-10303-21;\n");
    std::fs::write(&path, &cut).unwrap();
    drop(bytes);
    let out = bounded(&["inspect", path.to_str().unwrap()], dir.path());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("huge.step") && err.contains("line "), "{err}");
}
