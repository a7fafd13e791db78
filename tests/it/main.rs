//! Integration tests (one binary, see HOUSE-STYLE.md).

mod architecture;
mod bad_input;
mod batch;
mod cli;
mod common;
mod crosscheck;
mod golden;
mod iges;
mod realworld;
mod regenerate;
mod samples;
mod step_out;
mod svg;
