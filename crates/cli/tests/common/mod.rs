//! Helpers shared by the `strata` binary's tests: run it in a folder, write a scene there.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Run `strata ARGS` in `dir` and wait for it.
pub fn strata(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_strata"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the strata binary runs")
}

/// Write `text` to `dir/name`.
pub fn scene_file(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// Run `strata ARGS` in `dir`, check that its first line on stderr starts with `first` (the
/// device line), wait for its first line that starts with `after` (`progress:`: samples have
/// landed; `measured:`: a study's first level is done), send it SIGINT (Ctrl-C), and return its
/// exit status and the rest of its stderr.
pub fn interrupted_after(
    dir: &Path,
    args: &[&str],
    first: &str,
    after: &str,
) -> (std::process::ExitStatus, String) {
    use std::io::{BufRead, BufReader, Read};
    let mut child = Command::new(env!("CARGO_BIN_EXE_strata"))
        .args(args)
        .current_dir(dir)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut stderr = BufReader::new(child.stderr.take().unwrap());
    let mut seen = String::new();
    stderr.read_line(&mut seen).unwrap();
    assert!(seen.starts_with(first), "{seen}");
    loop {
        let mut line = String::new();
        let read = stderr.read_line(&mut line).unwrap();
        assert!(
            read > 0,
            "no line starting `{after}` before the end:\n{seen}"
        );
        seen.push_str(&line);
        if line.starts_with(after) {
            break;
        }
    }
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let mut rest = String::new();
    stderr.read_to_string(&mut rest).unwrap();
    (child.wait().unwrap(), rest)
}
