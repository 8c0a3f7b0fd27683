//! `cargo xtask header`.

pub fn run(_args: &[&str]) -> Result<(), String> {
    Err("not yet written".into())
}

pub fn check() -> Result<(), String> {
    run(&["--check"])
}
