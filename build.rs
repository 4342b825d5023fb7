//! Records the git commit the binaries are built from, for `--version`
//! (`SCASM_BUILD_COMMIT`: `git rev-parse --short=12 HEAD`, or `unknown` outside
//! a git checkout). Re-run when HEAD or the branch it names moves; whether the
//! tree had uncommitted changes is recorded at run time, in each run's config.toml.

use std::path::Path;
use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    Command::new("git")
        .args(args)
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
}

fn main() {
    let commit = git(&["rev-parse", "--short=12", "HEAD"]).unwrap_or_else(|| "unknown".into());
    println!("cargo:rustc-env=SCASM_BUILD_COMMIT={commit}");
    println!("cargo:rerun-if-changed=build.rs");
    if let Some(dir) = git(&["rev-parse", "--git-dir"]) {
        let mut watch = vec![format!("{dir}/HEAD"), format!("{dir}/packed-refs")];
        watch.extend(git(&["symbolic-ref", "-q", "HEAD"]).map(|r| format!("{dir}/{r}")));
        // Only files that exist: a missing one would re-run this every build.
        for f in watch.iter().filter(|f| Path::new(f).exists()) {
            println!("cargo:rerun-if-changed={f}");
        }
    }
}
