//! `cargo xtask deps`.

pub fn run(_args: &[&str]) -> Result<(), String> {
    Err("not yet written".into())
}
