//! The JSON report (`matrace.report/1`).
