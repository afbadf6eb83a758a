// Empty: cargo reads a package's build-dependencies only when it has a build
// script, and this package's build-dependencies unify the features of the
// proc-macro crates (syn and its kin).
fn main() {}
