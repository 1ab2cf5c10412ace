//! The tool's test helpers: the library's ([`crate::shared`]) and a runner for the built binary.

pub(crate) use crate::shared::*;

/// The largest file a test's run of the binary may write: `ulimit -f` in 512-byte blocks (1
/// GiB; a shell counting 1 KiB blocks allows 2), so that a regression that streams a job it
/// should refuse ends in SIGXFSZ instead of filling the machine's disk.
const FILE_SIZE_BLOCKS: u64 = 1 << 21;

/// A command running the built `splinegpu` binary through `sh`, under the file-size limit
/// and the shell's `limits` (`ulimit -v ...`, empty for none).
fn limited(limits: &str) -> std::process::Command {
    let mut command = std::process::Command::new("sh");
    command
        .args([
            "-c",
            &format!("ulimit -f {FILE_SIZE_BLOCKS} {limits} && exec \"$0\" \"$@\""),
        ])
        .arg(env!("CARGO_BIN_EXE_splinegpu"));
    command
}

/// Runs the built `splinegpu` binary with `args`, extra environment `envs`, and `stdin` as its
/// standard input (a process that exits before reading it is not the caller's concern), its
/// files no larger than [`FILE_SIZE_BLOCKS`].
pub(crate) fn run_cli(args: &[&str], envs: &[(&str, &str)], stdin: &str) -> std::process::Output {
    use std::io::Write;
    use std::process::Stdio;
    let mut child = limited("")
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
    limited(&format!("&& ulimit -v {kib}"))
        .arg("tessellate")
        .arg(input)
        .arg("-o")
        .arg(output)
        .args(["--backend", "cpu"])
        .output()
        .unwrap()
}

/// `splinegpu tessellate input --format format --backend cpu` under an address-space limit of
/// `kib` KiB, its standard output read here as it comes and not kept: the exit status, the
/// bytes and lines written, the last bytes (up to 64) and standard error.
pub(crate) fn tessellate_to_pipe_under_limit(
    kib: u64,
    input: &std::path::Path,
    format: &str,
) -> (Option<i32>, u64, u64, Vec<u8>, String) {
    use std::io::Read;
    use std::process::Stdio;
    let mut child = limited(&format!("&& ulimit -v {kib}"))
        .arg("tessellate")
        .arg(input)
        .args(["--format", format, "--backend", "cpu"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdout = child.stdout.take().unwrap();
    let (mut bytes, mut lines, mut tail) = (0u64, 0u64, Vec::new());
    let mut block = vec![0u8; 1 << 20];
    loop {
        let got = stdout.read(&mut block).unwrap();
        if got == 0 {
            break;
        }
        bytes += got as u64;
        lines += block[..got].iter().filter(|&&b| b == b'\n').count() as u64;
        tail.extend_from_slice(&block[..got]);
        tail.drain(..tail.len().saturating_sub(64));
    }
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    (out.status.code(), bytes, lines, tail, stderr)
}
