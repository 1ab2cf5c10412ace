//! The memory a job may still take: the least of what the machine has available (Linux's
//! MemAvailable), what the process's control group allows beyond what it uses (cgroup v2
//! `memory.max` − `memory.current`, or v1 `memory.limit_in_bytes` − `memory.usage_in_bytes`,
//! at the process's group and every group above it: a container, a CI runner, a notebook
//! server or a Kubernetes pod sets one), and what its address-space limit (RLIMIT_AS, `ulimit
//! -v`) leaves beyond its mapped size (VmSize). A job measured against the machine alone passed
//! the guard and then aborted mid-allocation under such a limit.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// The bytes a job may still allocate now, under every limit this process runs under (see the
/// module docs); `None` where the system says nothing (not Linux).
#[must_use]
pub fn available_memory() -> Option<u64> {
    [machine_available(), cgroup_room(), address_space_room()]
        .into_iter()
        .flatten()
        .min()
}

/// MemAvailable from /proc/meminfo.
fn machine_available() -> Option<u64> {
    meminfo_field(
        &std::fs::read_to_string("/proc/meminfo").ok()?,
        "MemAvailable:",
    )
}

/// A "Name:   123 kB" field of /proc/meminfo or /proc/self/status, in bytes.
fn meminfo_field(text: &str, name: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(name))?;
    let kib: u64 = line[name.len()..].split_whitespace().next()?.parse().ok()?;
    kib.checked_mul(1024)
}

/// The least room (limit − usage) over the process's control groups and their ancestors that
/// set a limit. Which groups do is read once (a limit set later is not seen); their usage is
/// read at every call.
fn cgroup_room() -> Option<u64> {
    static LIMITED: OnceLock<Vec<(PathBuf, CgroupFiles)>> = OnceLock::new();
    let limited = LIMITED.get_or_init(|| {
        let Ok(membership) = std::fs::read_to_string("/proc/self/cgroup") else {
            return Vec::new();
        };
        cgroup_dirs(&membership, Path::new("/sys/fs/cgroup"))
            .into_iter()
            .filter(|(dir, files)| read_limit(&dir.join(files.limit)).is_some_and(|l| l < NO_LIMIT))
            .collect()
    });
    limited
        .iter()
        .filter_map(|(dir, files)| {
            let limit = read_limit(&dir.join(files.limit))?;
            let usage = read_limit(&dir.join(files.usage)).unwrap_or(0);
            Some(limit.saturating_sub(usage))
        })
        .min()
}

/// Limits at or above this are none: cgroup v1 writes "no limit" as 2^63 less a page.
const NO_LIMIT: u64 = 1 << 62;

/// The files a cgroup version keeps its memory limit and usage in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct CgroupFiles {
    limit: &'static str,
    usage: &'static str,
}

const V2: CgroupFiles = CgroupFiles {
    limit: "memory.max",
    usage: "memory.current",
};
const V1: CgroupFiles = CgroupFiles {
    limit: "memory.limit_in_bytes",
    usage: "memory.usage_in_bytes",
};

/// The group folders whose memory limits apply to a process of `membership` (the text of
/// /proc/self/cgroup) under the cgroup mount `root`: its own group's and each ancestor's, up
/// to the root. v2's line is "0::/path"; v1's memory controller's "N:memory:/path" (or a
/// list of controllers holding "memory"), mounted at `root`/memory.
fn cgroup_dirs(membership: &str, root: &Path) -> Vec<(PathBuf, CgroupFiles)> {
    let mut dirs = Vec::new();
    for line in membership.lines() {
        let mut parts = line.splitn(3, ':');
        let (Some(_), Some(controllers), Some(path)) = (parts.next(), parts.next(), parts.next())
        else {
            continue;
        };
        let (mount, files) = if controllers.is_empty() {
            (root.to_path_buf(), V2)
        } else if controllers.split(',').any(|c| c == "memory") {
            (root.join("memory"), V1)
        } else {
            continue;
        };
        let mut group = Path::new(path.trim()).to_path_buf();
        loop {
            let relative = group.strip_prefix("/").unwrap_or(&group);
            dirs.push((mount.join(relative), files));
            if !group.pop() {
                break;
            }
        }
    }
    dirs
}

/// A limit or usage file's bytes: `None` for "max" (no limit), a missing file or text that is
/// not a number.
fn read_limit(path: &Path) -> Option<u64> {
    std::fs::read_to_string(path).ok()?.trim().parse().ok()
}

/// RLIMIT_AS's soft limit less the process's mapped size, when a limit is set.
#[cfg(target_os = "linux")]
fn address_space_room() -> Option<u64> {
    let mut limit = libc::rlimit {
        rlim_cur: 0,
        rlim_max: 0,
    };
    #[allow(
        unsafe_code,
        reason = "getrlimit is a system call without a safe wrapper in std"
    )]
    // SAFETY: getrlimit writes one rlimit into the struct it is given, which lives on this
    // stack frame for the call; RLIMIT_AS is a valid resource.
    let status = unsafe { libc::getrlimit(libc::RLIMIT_AS, &raw mut limit) };
    if status != 0 || limit.rlim_cur == libc::RLIM_INFINITY {
        return None;
    }
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let mapped = meminfo_field(&status, "VmSize:")?;
    #[allow(
        clippy::useless_conversion,
        reason = "rlim_t is u64 on 64-bit Linux, u32 on some 32-bit targets"
    )]
    let limit = u64::from(limit.rlim_cur);
    Some(limit.saturating_sub(mapped))
}

/// Elsewhere no address-space limit is read.
#[cfg(not(target_os = "linux"))]
fn address_space_room() -> Option<u64> {
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_are_read_in_bytes() {
        let text = "MemTotal:       24000000 kB\nMemAvailable:   12345 kB\n";
        assert_eq!(meminfo_field(text, "MemAvailable:"), Some(12345 * 1024));
        assert_eq!(meminfo_field(text, "VmSize:"), None);
    }

    #[test]
    fn every_group_up_to_the_root_is_read_v2_and_v1() {
        let root = Path::new("/cg");
        let v2 = cgroup_dirs("0::/user.slice/session-2.scope\n", root);
        assert_eq!(
            v2,
            [
                (PathBuf::from("/cg/user.slice/session-2.scope"), V2),
                (PathBuf::from("/cg/user.slice"), V2),
                (PathBuf::from("/cg"), V2),
            ]
        );
        let v1 = cgroup_dirs("12:cpu,cpuacct:/a\n4:memory:/docker/abc\n", root);
        assert_eq!(
            v1,
            [
                (PathBuf::from("/cg/memory/docker/abc"), V1),
                (PathBuf::from("/cg/memory/docker"), V1),
                (PathBuf::from("/cg/memory"), V1),
            ]
        );
    }

    #[test]
    fn limits_read_max_as_none() {
        let dir = std::env::temp_dir().join(format!("splinegpu-limit-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("memory.max"), "max\n").unwrap();
        std::fs::write(dir.join("memory.current"), "4096\n").unwrap();
        assert_eq!(read_limit(&dir.join("memory.max")), None);
        assert_eq!(read_limit(&dir.join("memory.current")), Some(4096));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_guard_is_never_more_than_the_machine_has() {
        if let (Some(all), Some(machine)) = (available_memory(), machine_available()) {
            assert!(all <= machine);
        }
    }
}
