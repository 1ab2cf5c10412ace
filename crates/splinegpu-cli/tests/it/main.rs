//! The tool's integration tests, in one binary: the command line as users script it (exit
//! codes, messages, outputs that appear only whole), the streaming writers against the
//! library's evaluators, and property tests of the document reader.

mod cli;
mod document_properties;
mod failure_modes;
mod fuzz_corpus;
mod geometry;
mod queries;
mod stream;
mod support;
mod surfaces;

// The library's test helpers (the shared GPU context, the random source, the comparisons).
#[path = "../../../splinegpu/tests/it/support.rs"]
mod shared;
