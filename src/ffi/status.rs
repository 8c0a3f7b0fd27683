//! `KatachiStatus`, the result of every call, and the thread's last error message.

use std::ffi::c_char;

use super::boundary::{guard_value, last_error_ptr};

/// The result of a katachi call. `KATACHI_STATUS_OK` (0) is success; every other value is a
/// failure, and `katachi_last_error_message()` then says what was wrong and where.
///
/// In C this is a `uint32_t` (the enum's constants name its values), because the size of a C
/// enum is the compiler's choice.
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum KatachiStatus {
    /// Success.
    Ok = 0,
    /// A required pointer argument was NULL (the message names the parameter).
    NullPointer = 1,
    /// A scalar argument was out of range (a vertex index, a `struct_size`, a count that does
    /// not match the mesh), a path was not UTF-8, or a pointer was misaligned.
    InvalidArgument = 2,
    /// A caller's buffer was too short; the message says how many elements are needed.
    /// Nothing was written.
    BufferTooSmall = 3,
    /// The mesh data or values were invalid: an index out of range in the corner array,
    /// a NaN or infinite coordinate, loop counts that do not add up, a degenerate loop, a
    /// negative sharpness, a vertex pair that is not an edge.
    BadInput = 4,
    /// The mesh is valid element by element, but its connectivity is not what the operation
    /// needs (non-manifold edges, inconsistent orientation).
    BadTopology = 5,
    /// A file could not be read or written, is malformed, or has an unknown extension.
    IoError = 6,
    /// A bug in katachi (an internal invariant failed or katachi panicked). Please report it
    /// with the message.
    InternalError = 7,
    /// The caller cancelled the call through its progress function; nothing was returned.
    Cancelled = 8,
}

/// Every status, in numeric order (not `pub`, so cbindgen leaves it out of the header).
const ALL: [KatachiStatus; 9] = [
    KatachiStatus::Ok,
    KatachiStatus::NullPointer,
    KatachiStatus::InvalidArgument,
    KatachiStatus::BufferTooSmall,
    KatachiStatus::BadInput,
    KatachiStatus::BadTopology,
    KatachiStatus::IoError,
    KatachiStatus::InternalError,
    KatachiStatus::Cancelled,
];

impl KatachiStatus {
    /// The status whose value is `value`, if any.
    pub fn from_u32(value: u32) -> Option<KatachiStatus> {
        ALL.get(value as usize).copied()
    }

    /// The C name of this status, e.g. `"KATACHI_STATUS_OK"`.
    pub fn name(self) -> &'static str {
        self.c_name().to_str().expect("status names are ASCII")
    }

    fn c_name(self) -> &'static std::ffi::CStr {
        match self {
            KatachiStatus::Ok => c"KATACHI_STATUS_OK",
            KatachiStatus::NullPointer => c"KATACHI_STATUS_NULL_POINTER",
            KatachiStatus::InvalidArgument => c"KATACHI_STATUS_INVALID_ARGUMENT",
            KatachiStatus::BufferTooSmall => c"KATACHI_STATUS_BUFFER_TOO_SMALL",
            KatachiStatus::BadInput => c"KATACHI_STATUS_BAD_INPUT",
            KatachiStatus::BadTopology => c"KATACHI_STATUS_BAD_TOPOLOGY",
            KatachiStatus::IoError => c"KATACHI_STATUS_IO_ERROR",
            KatachiStatus::InternalError => c"KATACHI_STATUS_INTERNAL_ERROR",
            KatachiStatus::Cancelled => c"KATACHI_STATUS_CANCELLED",
        }
    }
}

/// The message of the last failed katachi call on the calling thread, as a NUL-terminated
/// UTF-8 string: what was wrong and where, prefixed with the function's name
/// ("katachi_mesh_create: positions is NULL but vertex_count is 8").
///
/// Every function that returns a `KatachiStatus` clears the message when it starts and sets it
/// when it fails; the functions that cannot fail (`katachi_status_name`, the version and
/// `_default` functions, `katachi_mesh_free`, this one) leave it alone. So this returns `""`
/// (never NULL) when the last status-returning call on this thread succeeded or there was none.
///
/// Ownership and lifetime: the string belongs to katachi; do not free it. It stays valid until
/// the next status-returning katachi call on the same thread (copy it to keep it). Each thread
/// has its own message; calls on other threads never change it.
#[no_mangle]
pub extern "C" fn katachi_last_error_message() -> *const c_char {
    guard_value("katachi_last_error_message", c"".as_ptr(), last_error_ptr)
}

/// The name of a status value as a static NUL-terminated string, e.g.
/// `katachi_status_name(KATACHI_STATUS_BAD_INPUT)` is `"KATACHI_STATUS_BAD_INPUT"`;
/// a value that is no status gives `"KATACHI_STATUS_UNKNOWN"`. Never NULL; do not free it.
#[no_mangle]
pub extern "C" fn katachi_status_name(status: u32) -> *const c_char {
    guard_value(
        "katachi_status_name",
        c"KATACHI_STATUS_UNKNOWN".as_ptr(),
        || {
            KatachiStatus::from_u32(status)
                .map_or(c"KATACHI_STATUS_UNKNOWN", |s| s.c_name())
                .as_ptr()
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_their_index() {
        for (i, s) in ALL.iter().enumerate() {
            assert_eq!(*s as u32, i as u32);
            assert_eq!(KatachiStatus::from_u32(i as u32), Some(*s));
        }
    }

    #[test]
    fn names() {
        let name = |s: u32| {
            unsafe { std::ffi::CStr::from_ptr(katachi_status_name(s)) }
                .to_str()
                .unwrap()
                .to_owned()
        };
        assert_eq!(name(0), "KATACHI_STATUS_OK");
        assert_eq!(name(7), "KATACHI_STATUS_INTERNAL_ERROR");
        assert_eq!(name(8), "KATACHI_STATUS_CANCELLED");
        assert_eq!(name(9), "KATACHI_STATUS_UNKNOWN");
        assert_eq!(name(u32::MAX), "KATACHI_STATUS_UNKNOWN");
        assert_eq!(
            KatachiStatus::BadTopology.name(),
            "KATACHI_STATUS_BAD_TOPOLOGY"
        );
    }
}
