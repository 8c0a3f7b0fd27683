//! Version macros and the runtime version functions.
//!
//! The macros say which header a program was compiled against; the functions say which
//! library it runs with. A program can compare `KATACHI_ABI_VERSION` with
//! `katachi_abi_version()` at start-up and refuse to run on a mismatch.

use std::ffi::{c_char, CStr};

use super::boundary::guard_value;

/// The major version of the katachi release this header belongs to.
pub const KATACHI_VERSION_MAJOR: u32 = 0;
/// The minor version of the katachi release this header belongs to.
pub const KATACHI_VERSION_MINOR: u32 = 1;
/// The patch version of the katachi release this header belongs to.
pub const KATACHI_VERSION_PATCH: u32 = 0;
/// The version of the C ABI this header describes. It grows by one whenever a change would
/// break a program compiled against an older header (a function's signature, a struct's
/// layout beyond its `struct_size`, a status's meaning). Adding functions does not change it.
pub const KATACHI_ABI_VERSION: u32 = 2;

/// The ABI version of the library at run time; equals `KATACHI_ABI_VERSION` of the header the
/// library was built with. Never fails.
#[no_mangle]
pub extern "C" fn katachi_abi_version() -> u32 {
    guard_value("katachi_abi_version", KATACHI_ABI_VERSION, || {
        KATACHI_ABI_VERSION
    })
}

/// `CARGO_PKG_VERSION` as a C string.
const VERSION: &CStr =
    match CStr::from_bytes_with_nul(concat!(env!("CARGO_PKG_VERSION"), "\0").as_bytes()) {
        Ok(s) => s,
        Err(_) => panic!("the package version has no NUL"),
    };

/// The library's version as a static NUL-terminated string, `"MAJOR.MINOR.PATCH"`
/// (e.g. `"0.1.0"`), matching `KATACHI_VERSION_MAJOR`, `_MINOR` and `_PATCH`. Never NULL;
/// do not free it.
#[no_mangle]
pub extern "C" fn katachi_version_string() -> *const c_char {
    guard_value("katachi_version_string", VERSION.as_ptr(), || {
        VERSION.as_ptr()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn macros_match_the_package_version() {
        let parse = |s: &str| s.parse::<u32>().unwrap();
        assert_eq!(
            KATACHI_VERSION_MAJOR,
            parse(env!("CARGO_PKG_VERSION_MAJOR"))
        );
        assert_eq!(
            KATACHI_VERSION_MINOR,
            parse(env!("CARGO_PKG_VERSION_MINOR"))
        );
        assert_eq!(
            KATACHI_VERSION_PATCH,
            parse(env!("CARGO_PKG_VERSION_PATCH"))
        );
        let s = unsafe { std::ffi::CStr::from_ptr(katachi_version_string()) };
        assert_eq!(
            s.to_str().unwrap(),
            format!("{KATACHI_VERSION_MAJOR}.{KATACHI_VERSION_MINOR}.{KATACHI_VERSION_PATCH}")
        );
        assert_eq!(katachi_abi_version(), KATACHI_ABI_VERSION);
    }
}
