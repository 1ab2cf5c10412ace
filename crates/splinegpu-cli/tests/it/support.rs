//! The tool's test helpers: the library's ([`crate::shared`]) and a runner for the built binary.

pub(crate) use crate::shared::*;

/// Runs the built `splinegpu` binary with `args`, extra environment `envs`, and `stdin` as its
/// standard input (a process that exits before reading it is not the caller's concern).
pub(crate) fn run_cli(args: &[&str], envs: &[(&str, &str)], stdin: &str) -> std::process::Output {
    use std::io::Write;
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_splinegpu"))
        .args(args)
        .envs(envs.iter().copied())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run splinegpu");
    let _ = child.stdin.take().unwrap().write_all(stdin.as_bytes());
    child.wait_with_output().unwrap()
}
