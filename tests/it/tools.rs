//! The external tools some tests need, and what a test does when one is missing.
//!
//! `scripts/test.sh` installs them (Debian's FreeCAD and OpenSCAD, the OpenCASCADE venv
//! `.venv-ocp`); the third-party corpus is the folder `../shared/realworld` beside the
//! project. Without a tool a test that needs it is skipped, loudly: it writes a line naming
//! the test and the tool straight to the terminal (past the test harness's capture, so plain
//! `cargo test` shows it). Under CI (the `CI` variable set and not `false`) a missing tool is a
//! failure instead: CI installs everything, so a missing tool there is a broken setup.

use crate::common::root;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// Something a test needs besides the Rust toolchain.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tool {
    /// FreeCAD 0.20's Python modules for Debian's `/usr/bin/python3`.
    FreeCad,
    /// `/usr/bin/openscad`.
    OpenScad,
    /// The venv `.venv-ocp` with OpenCASCADE's Python bindings (`import OCP`).
    Occt,
    /// The third-party parts in `../shared/realworld`.
    Corpus,
    /// FreeCAD's IDF library of SMD component bodies, `/usr/share/freecad/Mod/Idf/Idflibs`
    /// (Debian's `freecad-common`, which FreeCAD's Python modules depend on).
    IdfLibrary,
}

impl Tool {
    /// What the tool is and how to get it, for the skip line.
    pub fn describe(self) -> &'static str {
        match self {
            Tool::FreeCad => {
                "FreeCAD (/usr/lib/freecad-python3/lib/FreeCAD.so; scripts/setup_tools.sh installs it)"
            }
            Tool::OpenScad => "OpenSCAD (/usr/bin/openscad; scripts/setup_tools.sh installs it)",
            Tool::Occt => "OpenCASCADE (.venv-ocp with OCP; scripts/setup_tools.sh creates it)",
            Tool::Corpus => "the third-party corpus (../shared/realworld beside the project)",
            Tool::IdfLibrary => {
                "FreeCAD's IDF library (/usr/share/freecad/Mod/Idf/Idflibs, Debian's \
                 freecad-common; scripts/setup_tools.sh installs it with FreeCAD)"
            }
        }
    }

    /// True when the tool is there (checked once per test run).
    pub fn present(self) -> bool {
        static OCCT: OnceLock<bool> = OnceLock::new();
        match self {
            Tool::FreeCad => {
                Path::new("/usr/lib/freecad-python3/lib/FreeCAD.so").exists()
                    && Path::new("/usr/bin/python3").exists()
            }
            Tool::OpenScad => Path::new("/usr/bin/openscad").exists(),
            Tool::Occt => *OCCT.get_or_init(|| {
                std::process::Command::new(occt_python())
                    .args(["-c", "import OCP"])
                    .output()
                    .is_ok_and(|o| o.status.success())
            }),
            Tool::Corpus => root().join("../shared/realworld").is_dir(),
            Tool::IdfLibrary => Path::new(IDF_LIBRARY).is_dir(),
        }
    }
}

/// Where Debian's `freecad-common` puts FreeCAD's IDF library.
pub const IDF_LIBRARY: &str = "/usr/share/freecad/Mod/Idf/Idflibs";

/// The OpenCASCADE venv's Python.
pub fn occt_python() -> PathBuf {
    root().join(".venv-ocp/bin/python")
}

/// True when the tests run under CI.
pub fn under_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| !v.is_empty() && v != "false" && v != "0")
}

/// What a test does about the tools it needs.
#[derive(Debug, PartialEq, Eq)]
pub enum Decision {
    Run,
    /// Skipped, with the line to write.
    Skip(String),
    /// Failed, with the message.
    Fail(String),
}

/// The decision for `test` needing `tools`, of which `missing` are not there.
pub fn decide(test: &str, missing: &[Tool], ci: bool) -> Decision {
    if missing.is_empty() {
        return Decision::Run;
    }
    let what: Vec<&str> = missing.iter().map(|t| t.describe()).collect();
    let what = what.join(", ");
    if ci {
        Decision::Fail(format!(
            "{test}: needs {what}, which CI must provide (.ci/run runs scripts/test.sh)"
        ))
    } else {
        Decision::Skip(format!("SKIPPED {test}: needs {what}"))
    }
}

/// True when every tool of `tools` is there. Otherwise, under CI the test fails; elsewhere
/// the skip is written to the terminal and the test returns early.
pub fn require(test: &str, tools: &[Tool]) -> bool {
    let missing: Vec<Tool> = tools.iter().copied().filter(|t| !t.present()).collect();
    match decide(test, &missing, under_ci()) {
        Decision::Run => true,
        Decision::Skip(line) => {
            say(&line);
            false
        }
        Decision::Fail(message) => panic!("{message}"),
    }
}

/// Writes a line to the terminal, past the test harness's output capture (which takes only
/// what `print!` and `eprint!` write).
pub fn say(line: &str) {
    let _ = writeln!(std::io::stderr(), "{line}");
}

#[test]
fn a_missing_tool_skips_loudly_and_fails_under_ci() {
    assert_eq!(decide("t", &[], false), Decision::Run);
    assert_eq!(decide("t", &[], true), Decision::Run);
    match decide("t", &[Tool::FreeCad, Tool::Occt], false) {
        Decision::Skip(line) => {
            assert!(line.starts_with("SKIPPED t: needs FreeCAD"), "{line}");
            assert!(line.contains("OpenCASCADE"), "{line}");
        }
        other => panic!("{other:?}"),
    }
    match decide("t", &[Tool::OpenScad], true) {
        Decision::Fail(message) => assert!(message.contains("OpenSCAD"), "{message}"),
        other => panic!("{other:?}"),
    }
}
