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

/// `splinegpu tessellate input -o output --backend cpu` under an address-space limit of
/// `kib` KiB (`ulimit -v`, in the child's shell only).
pub(crate) fn tessellate_under_limit(
    kib: u64,
    input: &std::path::Path,
    output: &std::path::Path,
) -> std::process::Output {
    std::process::Command::new("sh")
        .args(["-c", &format!("ulimit -v {kib} && exec \"$0\" \"$@\"")])
        .arg(env!("CARGO_BIN_EXE_splinegpu"))
        .arg("tessellate")
        .arg(input)
        .arg("-o")
        .arg(output)
        .args(["--backend", "cpu"])
        .output()
        .unwrap()
}
