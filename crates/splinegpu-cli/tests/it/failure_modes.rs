//! The CLI's failure modes, each a test: special files as OUTPUT (a device node, a FIFO,
//! symbolic links), output that cannot be written, a reader that closes early, signals, jobs
//! too large to hold, and a large input document.
//!
//! These tests cannot harm the machine they run on even if the code under test regresses:
//! every file they name lies in their own temporary folder (a device node they need is made
//! there with `mknod`, when running as root), and /dev/full is reached only as an already-open
//! standard output.

use std::fs;
use std::io::{BufRead, BufReader, Read, Write};
use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_splinegpu");

/// A document of `curves` Catmull-Rom curves of 3-D points, `k` samples per segment.
fn document(curves: usize, k: u64) -> String {
    let curve = r#"{"kind": "catmull-rom", "points": [[0, 0, 0], [1, 2, 0], [3, 1, 1], [4, 4, 2], [5, 0, 1]]}"#;
    let curves = vec![curve; curves].join(",\n");
    format!(r#"{{"sampling": {{"per_segment": {k}}}, "curves": [{curves}]}}"#)
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    fs::write(&path, text).unwrap();
    path
}

/// `splinegpu tessellate INPUT -o OUTPUT` with the given backend (none: auto).
fn tessellate_to(input: &Path, output: &Path, backend: Option<&str>, stdout: Stdio) -> Child {
    let mut args = vec![
        "tessellate",
        input.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
    ];
    if let Some(backend) = backend {
        args.extend(["--backend", backend]);
    }
    spawn(&args, stdout)
}

fn spawn(args: &[&str], stdout: Stdio) -> Child {
    Command::new(BIN)
        .args(args)
        .stdin(Stdio::null())
        .stdout(stdout)
        .stderr(Stdio::piped())
        .spawn()
        .expect("run splinegpu")
}

fn stderr_of(child: &mut Child) -> String {
    let mut text = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut text)
        .unwrap();
    text
}

/// The names in `dir`, sorted.
fn names_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn temporary_files_in(dir: &Path) -> Vec<String> {
    names_in(dir)
        .into_iter()
        .filter(|n| n.starts_with(".splinegpu-"))
        .collect()
}

fn is_root() -> bool {
    let out = Command::new("id").arg("-u").output().unwrap();
    String::from_utf8_lossy(&out.stdout).trim() == "0"
}

/// The CSV the CPU backend writes for `input` to a regular file, as the reference output.
fn regular_output(dir: &Path, input: &Path) -> Vec<u8> {
    let out = dir.join("regular.csv");
    let status = Command::new(BIN)
        .args(["tessellate", input.to_str().unwrap(), "-o"])
        .arg(&out)
        .args(["--backend", "cpu"])
        .status()
        .unwrap();
    assert!(status.success());
    let bytes = fs::read(&out).unwrap();
    fs::remove_file(&out).unwrap();
    bytes
}

#[test]
fn a_reader_that_closes_early_ends_the_run_quietly() {
    let dir = tempfile::tempdir().unwrap();
    // About 40 MB of CSV: far more than a pipe holds.
    let input = write(dir.path(), "big.json", &document(2000, 2000));
    let mut child = spawn(
        &["tessellate", input.to_str().unwrap(), "--backend", "cpu"],
        Stdio::piped(),
    );
    // `| head -1`: read one line, then close the pipe.
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    assert!(first.starts_with("curve,sample,t,x0"), "{first}");
    let stderr = stderr_of(&mut child);
    let status = child.wait().unwrap();
    assert!(status.success(), "{status:?}: {stderr}");
    assert_eq!(stderr, "", "nothing on stderr");
}

#[test]
fn standard_output_on_a_full_device_exits_1_with_one_message() {
    // /dev/full is opened here for writing only, and given to the child as its stdout, as a
    // shell's `> /dev/full` does; nothing is created, removed or renamed.
    let Ok(full) = fs::OpenOptions::new().write(true).open("/dev/full") else {
        eprintln!("skipping: no /dev/full");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "doc.json", &document(3, 10));
    let mut child = spawn(
        &["tessellate", input.to_str().unwrap(), "--backend", "cpu"],
        Stdio::from(full),
    );
    let stderr = stderr_of(&mut child);
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.contains("cannot write output"), "{stderr}");
}

#[test]
fn a_device_node_as_output_is_written_in_place_never_replaced() {
    if !is_root() {
        eprintln!("skipping: mknod needs root");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    // A node with /dev/full's numbers (char 1 7), made in our own folder.
    let node = dir.path().join("full");
    let made = Command::new("mknod")
        .arg(&node)
        .args(["c", "1", "7"])
        .status();
    if !made.is_ok_and(|s| s.success()) {
        eprintln!("skipping: mknod failed here");
        return;
    }
    let input = write(dir.path(), "doc.json", &document(3, 10));
    let mut child = tessellate_to(&input, &node, Some("cpu"), Stdio::null());
    let stderr = stderr_of(&mut child);
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        fs::symlink_metadata(&node)
            .unwrap()
            .file_type()
            .is_char_device(),
        "the device node is still a device node"
    );
    assert_eq!(temporary_files_in(dir.path()), Vec::<String>::new());
}

#[test]
fn a_fifo_as_output_is_written_in_place_and_its_reader_gets_everything() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "doc.json", &document(20, 50));
    let expected = regular_output(dir.path(), &input);
    let fifo = dir.path().join("pipe");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || fs::read(fifo).unwrap())
    };
    let mut child = tessellate_to(&input, &fifo, Some("cpu"), Stdio::null());
    let stderr = stderr_of(&mut child);
    assert!(child.wait().unwrap().success(), "{stderr}");
    assert_eq!(reader.join().unwrap(), expected);
    assert!(fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo());
    assert_eq!(temporary_files_in(dir.path()), Vec::<String>::new());
}

#[test]
fn a_link_to_a_pipe_as_output_is_written_through() {
    // `-o /dev/stdout` with stdout a pipe: /dev/stdout -> /proc/self/fd/1 -> pipe:[N], a link
    // whose target is no path. The test's own link in its folder stands in for /dev/stdout.
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "doc.json", &document(3, 5));
    let expected = regular_output(dir.path(), &input);
    let link = dir.path().join("stdout");
    std::os::unix::fs::symlink("/proc/self/fd/1", &link).unwrap();
    let mut child = tessellate_to(&input, &link, Some("cpu"), Stdio::piped());
    let mut got = Vec::new();
    child.stdout.take().unwrap().read_to_end(&mut got).unwrap();
    let stderr = stderr_of(&mut child);
    assert!(child.wait().unwrap().success(), "{stderr}");
    assert_eq!(got, expected);
    assert_eq!(names_in(dir.path()), ["doc.json", "stdout"]);
}

#[test]
fn a_symbolic_link_as_output_is_followed_to_its_file() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "doc.json", &document(4, 8));
    let expected = regular_output(dir.path(), &input);
    let sub = dir.path().join("sub");
    fs::create_dir(&sub).unwrap();
    // An existing target through a relative link, a missing one through a dangling link, and a
    // chain of two links.
    let target = write(&sub, "target.csv", "OLD");
    std::os::unix::fs::symlink("sub/target.csv", dir.path().join("link.csv")).unwrap();
    std::os::unix::fs::symlink(sub.join("new.csv"), dir.path().join("dangling.csv")).unwrap();
    std::os::unix::fs::symlink("link.csv", dir.path().join("chain.csv")).unwrap();
    for (link, file) in [
        ("link.csv", target.clone()),
        ("dangling.csv", sub.join("new.csv")),
        ("chain.csv", target.clone()),
    ] {
        let out = dir.path().join(link);
        let status = Command::new(BIN)
            .args(["tessellate", input.to_str().unwrap(), "-o"])
            .arg(&out)
            .args(["--backend", "cpu"])
            .status()
            .unwrap();
        assert!(status.success());
        assert!(
            fs::symlink_metadata(&out).unwrap().file_type().is_symlink(),
            "{link} is still a link"
        );
        assert_eq!(fs::read(&file).unwrap(), expected, "{link}");
        fs::write(&target, "OLD").unwrap();
    }
    assert_eq!(temporary_files_in(&sub), Vec::<String>::new());
}

#[test]
fn an_unwritable_directory_exits_1_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "doc.json", &document(2, 4));
    // Root writes into any directory whatever its mode, so there the "directory" is a file.
    let out = if is_root() {
        let file = write(dir.path(), "not-a-directory", "");
        file.join("out.csv")
    } else {
        let locked = dir.path().join("locked");
        fs::create_dir(&locked).unwrap();
        let mut perms = fs::metadata(&locked).unwrap().permissions();
        std::os::unix::fs::PermissionsExt::set_mode(&mut perms, 0o555);
        fs::set_permissions(&locked, perms).unwrap();
        locked.join("out.csv")
    };
    let before = names_in(dir.path());
    let mut child = tessellate_to(&input, &out, Some("cpu"), Stdio::null());
    let stderr = stderr_of(&mut child);
    assert_eq!(child.wait().unwrap().code(), Some(1), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert_eq!(names_in(dir.path()), before);
}

/// Waits (at most a minute) until a temporary output file appears in `dir`.
fn wait_for_temporary_file(dir: &Path, child: &mut Child) {
    let start = Instant::now();
    while temporary_files_in(dir).is_empty() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "splinegpu ended before writing"
        );
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no temporary file"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Peak resident memory of a running process, in bytes (VmHWM from /proc/PID/status).
fn peak_rss(pid: u32) -> Option<u64> {
    let status = fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

fn signal(child: &Child, name: &str) {
    let status = Command::new("kill")
        .args(["-s", name, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
}

fn signalled(status: ExitStatus, number: i32) -> bool {
    use std::os::unix::process::ExitStatusExt;
    status.code() == Some(128 + number) || status.signal() == Some(number)
}

#[test]
fn signals_remove_the_temporary_file() {
    for (name, number) in [("INT", 2), ("TERM", 15), ("HUP", 1)] {
        let dir = tempfile::tempdir().unwrap();
        // Two billion samples: it is still writing when the signal comes.
        let input = write(dir.path(), "doc.json", &document(1, 500_000_000));
        let out = dir.path().join("out.csv");
        let mut child = tessellate_to(&input, &out, Some("cpu"), Stdio::null());
        wait_for_temporary_file(dir.path(), &mut child);
        signal(&child, name);
        let status = child.wait().unwrap();
        assert!(signalled(status, number), "SIG{name}: {status:?}");
        assert_eq!(names_in(dir.path()), ["doc.json"], "SIG{name}");
    }
}

#[test]
fn billions_of_samples_in_one_segment_stream_in_bounded_memory() {
    let dir = tempfile::tempdir().unwrap();
    // per_segment 4e9 on a curve of 2 segments: 8e9 samples, 64 GB of t alone.
    let doc = r#"{"sampling": {"per_segment": 4000000000}, "curves": [
        {"kind": "catmull-rom", "ends": "repeat", "points": [[0, 0], [1, 2], [3, 1]]}]}"#;
    let input = write(dir.path(), "doc.json", doc);
    for format in ["npz", "csv", "json"] {
        let out = dir.path().join(format!("out.{format}"));
        let mut child = tessellate_to(&input, &out, None, Stdio::null());
        wait_for_temporary_file(dir.path(), &mut child);
        // Let it write 64 MB, then look at its peak memory.
        let start = Instant::now();
        loop {
            let written: u64 = temporary_files_in(dir.path())
                .iter()
                .filter_map(|n| fs::metadata(dir.path().join(n)).ok())
                .map(|m| m.len())
                .sum();
            if written > 64 << 20 || start.elapsed() > Duration::from_secs(60) {
                break;
            }
            assert!(child.try_wait().unwrap().is_none(), "{format}: ended early");
            std::thread::sleep(Duration::from_millis(20));
        }
        let peak = peak_rss(child.id()).unwrap();
        signal(&child, "TERM");
        let status = child.wait().unwrap();
        assert!(signalled(status, 15), "{format}: {status:?}");
        eprintln!("{format}: peak resident memory {} MB", peak >> 20);
        assert!(peak < 400 << 20, "{format}: peak {} MB", peak >> 20);
        assert_eq!(names_in(dir.path()), ["doc.json"], "{format}");
    }
}

/// A w1-like document of about `bytes` bytes: Catmull-Rom curves of 34 3-D points with
/// coordinates written to 16 significant digits, as a program dumping f64 data writes them.
fn large_document(bytes: usize) -> String {
    let mut text = String::with_capacity(bytes + 4096);
    text.push_str(r#"{"sampling": {"per_segment": 1}, "curves": ["#);
    let mut x = 0x2545_F491_4F6C_DD1Du64;
    let mut first = true;
    while text.len() < bytes {
        text.push_str(if first { "\n" } else { ",\n" });
        first = false;
        text.push_str(r#"{"kind": "catmull-rom", "points": ["#);
        for p in 0..34 {
            text.push_str(if p > 0 { ", [" } else { "[" });
            for k in 0..3 {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                let v = (x >> 11) as f64 / (1u64 << 53) as f64 * 200.0 - 100.0;
                text.push_str(&format!("{}{v:.15e}", if k > 0 { ", " } else { "" }));
            }
            text.push(']');
        }
        text.push_str("]}");
    }
    text.push_str("]}\n");
    text
}

#[test]
fn a_256_mb_document_is_accepted_with_peak_memory_under_2_5_times_its_size() {
    let dir = tempfile::tempdir().unwrap();
    let text = large_document(256 << 20);
    let input = write(dir.path(), "big.json", &text);
    let size = text.len() as u64;
    drop(text);
    let out = dir.path().join("out.npz");
    let mut child = tessellate_to(&input, &out, Some("cpu"), Stdio::null());
    // VmHWM only grows; the last reading before the process ends is its peak (the output is
    // streamed after the whole document is held, so the peak comes well before the end).
    let mut peak = 0;
    while child.try_wait().unwrap().is_none() {
        if let Some(p) = peak_rss(child.id()) {
            peak = peak.max(p);
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let stderr = stderr_of(&mut child);
    assert!(child.wait().unwrap().success(), "{stderr}");
    eprintln!(
        "{} MB document: peak resident memory {} MB ({:.2}x)",
        size >> 20,
        peak >> 20,
        peak as f64 / size as f64
    );
    assert!(peak > 0);
    assert!(
        (peak as f64) < 2.5 * size as f64,
        "peak {} MB for a {} MB document",
        peak >> 20,
        size >> 20
    );
}

#[test]
fn stdin_documents_stream_too() {
    let mut child = Command::new(BIN)
        .args(["tessellate", "-", "--backend", "cpu", "--format", "json"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(document(2, 3).as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success());
    let parsed: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(parsed["curves"].as_array().unwrap().len(), 2);
    assert_eq!(
        parsed["curves"][1]["t"].as_array().unwrap().len(),
        2 * 3 + 1
    );
}

/// A surface document whose .glb is far more than a pipe holds (a 4 x 4 net at
/// per_segment [300, 300]: 90,601 vertices, about 1.8 MB).
fn big_surface_document() -> String {
    let net: Vec<Vec<[f64; 3]>> = (0..4)
        .map(|i| {
            (0..4)
                .map(|j| [f64::from(i), f64::from(j), f64::from((i + j) % 3)])
                .collect()
        })
        .collect();
    format!(
        r#"{{"sampling": {{"per_segment": [300, 300]}}, "surfaces": [{{"kind": "bspline", "points": {}}}]}}"#,
        serde_json::to_string(&net).unwrap()
    )
}

#[test]
fn a_glb_reader_that_closes_early_ends_the_run_quietly() {
    // Exit 1 "Broken pipe" before: the .glb writer's error hid the pipe's.
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "surface.json", &big_surface_document());
    let mut child = spawn(
        &[
            "tessellate",
            input.to_str().unwrap(),
            "--format",
            "glb",
            "--backend",
            "cpu",
        ],
        Stdio::piped(),
    );
    let mut magic = [0u8; 4];
    child.stdout.take().unwrap().read_exact(&mut magic).unwrap();
    assert_eq!(&magic, b"glTF");
    let stderr = stderr_of(&mut child);
    let status = child.wait().unwrap();
    assert!(status.success(), "{status:?}: {stderr}");
    assert_eq!(stderr, "", "nothing on stderr");
}

#[test]
fn a_dash_as_output_is_standard_output() {
    // A file named "-" was written before.
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "doc.json", &document(2, 4));
    let out = Command::new(BIN)
        .current_dir(dir.path())
        .args(["tessellate", "doc.json", "-o", "-", "--backend", "cpu"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.stdout.starts_with(b"curve,sample,t,x0"));
    assert_eq!(out.stdout, regular_output(dir.path(), &input));
    assert!(!dir.path().join("-").exists());
}

#[test]
fn a_replaced_output_keeps_its_mode() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "doc.json", &document(2, 4));
    let output = write(dir.path(), "out.csv", "old");
    fs::set_permissions(&output, fs::Permissions::from_mode(0o640)).unwrap();
    let mut child = tessellate_to(&input, &output, Some("cpu"), Stdio::null());
    let stderr = stderr_of(&mut child);
    assert!(child.wait().unwrap().success(), "{stderr}");
    let mode = fs::metadata(&output).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, 0o640, "the mode was {mode:o}");
    assert_ne!(fs::read(&output).unwrap(), b"old");
}

#[test]
fn an_output_the_user_may_not_write_is_refused_and_kept() {
    // As `cp` and `sort -o` refuse it; before, the rename replaced it (a writable folder lets
    // anyone rename over a file they may not write). Run as an unprivileged user (nobody,
    // through setpriv) when the tests run as root, where every file is writable.
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    fs::set_permissions(dir.path(), fs::Permissions::from_mode(0o777)).unwrap();
    let input = write(dir.path(), "doc.json", &document(2, 4));
    let output = write(dir.path(), "theirs.csv", "not yours");
    fs::set_permissions(&output, fs::Permissions::from_mode(0o444)).unwrap();
    let args = [
        "tessellate",
        input.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
        "--backend",
        "cpu",
    ];
    let out = if is_root() {
        let Ok(out) = Command::new("setpriv")
            .args(["--reuid=65534", "--regid=65534", "--clear-groups", BIN])
            .args(args)
            .output()
        else {
            eprintln!("skipping: no setpriv to drop root");
            return;
        };
        out
    } else {
        Command::new(BIN).args(args).output().unwrap()
    };
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("theirs.csv") && stderr.contains("ermission denied"),
        "{stderr}"
    );
    assert_eq!(fs::read(&output).unwrap(), b"not yours");
    assert!(temporary_files_in(dir.path()).is_empty());
}
