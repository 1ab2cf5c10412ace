//! Any bytes as a document: parsed from a reader and, where they are UTF-8, from memory. Both
//! must agree (a document, or an error with the same message; JSON syntax errors on being
//! such, which serde_json places a column apart from a reader and from a string), and neither
//! may panic, abort or allocate without bound (libFuzzer's -rss_limit_mb catches the last).
#![no_main]

use libfuzzer_sys::fuzz_target;
use splinegpu_cli::document::{parse_input, parse_input_from_reader};

fuzz_target!(|data: &[u8]| {
    let from_reader = parse_input_from_reader(data);
    if let Ok(text) = std::str::from_utf8(data) {
        let in_memory = parse_input(text);
        match (&from_reader, &in_memory) {
            (Ok(_), Ok(_)) => {}
            (Err(a), Err(b)) if syntax(&a.to_string()) => assert!(syntax(&b.to_string())),
            (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string()),
            _ => panic!("the reader and the text disagree: {from_reader:?} vs {in_memory:?}"),
        }
    }
});

/// Whether a refusal is a JSON syntax error (placed by line and column).
fn syntax(message: &str) -> bool {
    message.starts_with("document: invalid JSON")
}
