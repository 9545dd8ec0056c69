//! Records the source revision so that summaries and `--version` say which
//! build produced them.
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
    let rev = git(&["rev-parse", "--short=12", "HEAD"]).unwrap_or_else(|| "unknown".to_string());
    println!("cargo:rustc-env=CONTACT2D_REVISION={rev}");
    // HEAD and the branch it points to (or packed-refs when the branch has
    // no file of its own), where git keeps them: `.git/...` in a clone,
    // elsewhere in a worktree, whose `.git` is a file. A path that does not
    // exist would rerun this script, and rebuild the crate, on every build;
    // all of `refs/heads` would rebuild it on another branch's commit.
    let branch = git(&["symbolic-ref", "-q", "HEAD"]);
    for path in ["HEAD"].into_iter().chain(branch.as_deref()) {
        let found =
            git(&["rev-parse", "--git-path", path]).unwrap_or_else(|| format!(".git/{path}"));
        let found = match std::path::Path::new(&found).exists() {
            true => found,
            false => git(&["rev-parse", "--git-path", "packed-refs"])
                .unwrap_or_else(|| ".git/packed-refs".into()),
        };
        println!("cargo:rerun-if-changed={found}");
    }
}
