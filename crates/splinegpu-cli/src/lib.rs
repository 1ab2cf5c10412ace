//! The machinery of the `splinegpu` command line, as a library of its own: the input document
//! (docs/input-format.md), the CSV, JSON and NPZ outputs that stream chunk by chunk, and
//! `splinegpu bench` with its plain loops. The binary (`main.rs`) parses the arguments and
//! calls into these; the tests and benches call them directly.
//!
//! Everything here builds on the library crate [`splinegpu`], whose public API it uses like
//! any other caller.

pub mod bench;
pub mod document;
pub mod geometry_output;
pub mod mesh_files;
pub mod npz;
pub mod output;
pub mod plain;
pub mod query_output;
pub mod spill;
pub mod stream;
pub mod surface_output;

pub use document::{
    Document, parse_document, parse_document_from_reader, parse_input, parse_input_from_reader,
};
