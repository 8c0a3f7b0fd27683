//! Property tests that say how many cases they checked. [`check`] runs a proptest strategy
//! like `proptest!` does (same configuration, the same regression files beside the test
//! source), and counts what each case did: accepted (the property ran to the end) or rejected
//! by `prop_assume!` (an input the property cannot use). A run fails when fewer than
//! `config.cases` cases were accepted, and records its counts for `cargo xtask test`'s summary.

use std::cell::Cell;

use proptest::strategy::Strategy;
use proptest::test_runner::{Config, TestCaseError, TestError, TestRunner};

use super::record::record;

/// Runs `test` on values of `strategy` until `config.cases` of them are accepted; `name`
/// names the property in failures and in the record, `source_file` is `file!()` of the
/// caller (for proptest's regression file).
pub fn check<S: Strategy>(
    name: &str,
    source_file: &'static str,
    config: Config,
    strategy: S,
    test: impl Fn(S::Value) -> Result<(), TestCaseError>,
) {
    let wanted = config.cases;
    let config = Config {
        source_file: Some(source_file),
        ..config
    };
    let accepted = Cell::new(0u32);
    let rejected = Cell::new(0u32);
    let mut runner = TestRunner::new(config);
    let result = runner.run(&strategy, |value| {
        let r = test(value);
        match &r {
            Ok(()) => accepted.set(accepted.get() + 1),
            Err(TestCaseError::Reject(_)) => rejected.set(rejected.get() + 1),
            Err(TestCaseError::Fail(_)) => {}
        }
        r
    });
    match result {
        Ok(()) => {}
        Err(TestError::Fail(why, value)) => {
            panic!("property `{name}` failed: {why}\nminimal failing input: {value:#?}")
        }
        Err(TestError::Abort(why)) => panic!(
            "property `{name}` aborted after {} accepted and {} rejected cases: {why}",
            accepted.get(),
            rejected.get()
        ),
    }
    // Shrinking re-runs cases; only a passing run's counts are recorded, and it passed only
    // after `wanted` accepted cases.
    assert!(
        accepted.get() >= wanted,
        "property `{name}`: {} accepted cases, fewer than the {wanted} asked for",
        accepted.get()
    );
    record(&[
        "property",
        name,
        &accepted.get().to_string(),
        &rejected.get().to_string(),
    ]);
}

/// `proptest!` with the same syntax (a `#![proptest_config(..)]` line, then `#[test]`
/// functions whose arguments are `pattern in strategy`), each function run through
/// [`check`], so that it counts and records its accepted and rejected cases.
macro_rules! counted_proptest {
    (
        #![proptest_config($config:expr)]
        $(
            $(#[$meta:meta])*
            fn $name:ident($($arg:pat in $strategy:expr),+ $(,)?) $body:block
        )*
    ) => {
        $(
            $(#[$meta])*
            fn $name() {
                $crate::support::property::check(
                    concat!(module_path!(), "::", stringify!($name)),
                    file!(),
                    $config,
                    ($($strategy,)+),
                    |($($arg,)+)| {
                        $body
                        #[allow(unreachable_code)]
                        Ok(())
                    },
                );
            }
        )*
    };
}
pub(crate) use counted_proptest;
