//! Integration tests, compiled into one binary (`cargo test --test it`); `docs/testing.md`
//! says what each needs and how tests that need a missing tool are skipped.

mod analytic;
mod architecture;
mod bad_input;
mod batch;
mod cli;
mod common;
mod crosscheck;
mod golden;
mod idf_library;
mod iges;
mod reader;
mod realworld;
mod regenerate;
mod samples;
mod step_out;
mod svg;
mod tools;
mod trace_regressions;
mod verify;
