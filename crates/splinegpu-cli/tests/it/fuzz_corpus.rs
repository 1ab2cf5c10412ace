//! The parser's fuzz corpus (fuzz/corpus/document/, seeds of every document kind and of the
//! hostile inputs the project has met) replayed as the fuzz target replays it
//! (fuzz/fuzz_targets/document.rs): every file parsed from a reader and, where it is UTF-8,
//! from memory, the two agreeing (JSON syntax errors on being such: serde_json places them a
//! column apart from a reader and from a string), none panicking. CI runs this; libFuzzer runs
//! on nightly.

use splinegpu_cli::document::{parse_input, parse_input_from_reader};

#[test]
fn every_corpus_document_parses_or_is_refused_the_same_way_from_a_reader_and_from_memory() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fuzz/corpus/document");
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert!(
        files.len() >= 30,
        "the seed corpus is there: {}",
        files.len()
    );
    let (mut documents, mut refused) = (0, 0);
    for path in &files {
        let data = std::fs::read(path).unwrap();
        let from_reader = parse_input_from_reader(&data[..]);
        if let Ok(text) = std::str::from_utf8(&data) {
            match (&from_reader, parse_input(text)) {
                (Ok(_), Ok(_)) => {}
                (Err(a), Err(b)) if syntax(&a.to_string()) => {
                    assert!(syntax(&b.to_string()), "{}: {a} / {b}", path.display());
                }
                (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "{}", path.display()),
                (a, b) => panic!("{}: the reader gives {a:?}, the text {b:?}", path.display()),
            }
        }
        match from_reader {
            Ok(_) => documents += 1,
            Err(e) => {
                // A refusal names what is wrong, on one line.
                let message = e.to_string();
                assert!(!message.is_empty() && !message.contains('\n'), "{message}");
                refused += 1;
            }
        }
    }
    // The valid seeds (one of each document kind, and a batch of 2,000 curves) parse.
    assert!(documents >= 7, "{documents} documents, {refused} refused");
}

/// Whether a refusal is a JSON syntax error (placed by line and column).
fn syntax(message: &str) -> bool {
    message.starts_with("document: invalid JSON")
}
