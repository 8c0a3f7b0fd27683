//! The frame every exported function stands in: the panic boundary, the thread-local last
//! error message, and checked conversions from C pointers.
//!
//! Each `extern "C"` function is a one-line call to [`guard`] (or [`guard_value`] for the
//! few that return something other than a status) around a closure that returns
//! [`FfiResult`]. The guard clears the thread's last message, runs the closure inside
//! `catch_unwind`, turns an `Err` into its status plus a message prefixed with the function's
//! name, and turns a panic into `KATACHI_STATUS_INTERNAL_ERROR` with the panic's text. No
//! panic hook is installed: a library must not change process-wide state (DESIGN.md).
//!
//! The message lives in a `thread_local!`, never in a global buffer, so two threads calling
//! katachi at once each read their own message.

use std::any::Any;
use std::cell::RefCell;
use std::ffi::{c_char, CStr, CString};
use std::fmt::Display;
use std::panic::{catch_unwind, AssertUnwindSafe};

use super::status::KatachiStatus;
use crate::error::{Error, ErrorKind};

thread_local! {
    /// The last failed call's message on this thread; `None` after a call that succeeded.
    static LAST_ERROR: RefCell<Option<CString>> = const { RefCell::new(None) };
}

/// A failed FFI call: the status to return and the message to leave for
/// `katachi_last_error_message` (without the function-name prefix, which [`guard`] adds).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FfiError {
    pub(crate) status: KatachiStatus,
    pub(crate) message: String,
}

/// The result of an exported function's body.
pub(crate) type FfiResult<T = ()> = Result<T, FfiError>;

impl FfiError {
    pub(crate) fn new(status: KatachiStatus, message: impl Into<String>) -> Self {
        FfiError {
            status,
            message: message.into(),
        }
    }

    /// `KATACHI_STATUS_INVALID_ARGUMENT` with `message`.
    pub(crate) fn invalid(message: impl Into<String>) -> Self {
        Self::new(KatachiStatus::InvalidArgument, message)
    }

    /// `KATACHI_STATUS_NULL_POINTER`: "`param` is NULL".
    pub(crate) fn null(param: &str) -> Self {
        Self::new(KatachiStatus::NullPointer, format!("{param} is NULL"))
    }
}

/// Maps the kernel's error families onto statuses. [`Error::InvalidArgument`] and
/// [`Error::InvalidOption`] (arguments that are not mesh data) get their own status;
/// everything else follows [`Error::kind`].
impl From<Error> for FfiError {
    fn from(e: Error) -> Self {
        let status = match (&e, e.kind()) {
            (Error::InvalidArgument(_) | Error::InvalidOption { .. }, _) => {
                KatachiStatus::InvalidArgument
            }
            (_, ErrorKind::BadInput) => KatachiStatus::BadInput,
            (_, ErrorKind::BadTopology) => KatachiStatus::BadTopology,
            (_, ErrorKind::Io) => KatachiStatus::IoError,
            (_, ErrorKind::Cancelled) => KatachiStatus::Cancelled,
            (_, ErrorKind::Internal) => KatachiStatus::InternalError,
        };
        FfiError::new(status, e.to_string())
    }
}

/// Leaves `message` for `katachi_last_error_message` on this thread, as one line of plain
/// text: control characters from the input (a file name's escape codes or line breaks, and
/// NUL bytes, which a C string cannot hold) as Rust escapes (`\u{1b}`, `\n`, `\0`), so a
/// host that prints the message prints no terminal codes.
pub(crate) fn set_last_error(message: &str) {
    let text = crate::error::escape_control_characters(message);
    let c = CString::new(text.into_owned()).unwrap_or_default();
    // `try_with`: during thread teardown the slot may be gone; then there is no one to tell.
    let _ = LAST_ERROR.try_with(|slot| *slot.borrow_mut() = Some(c));
}

/// Forgets this thread's last message.
pub(crate) fn clear_last_error() {
    let _ = LAST_ERROR.try_with(|slot| *slot.borrow_mut() = None);
}

/// This thread's last message as a C string: valid until the next katachi call on this
/// thread replaces or clears it; `""` (a static string) when there is none.
pub(crate) fn last_error_ptr() -> *const c_char {
    LAST_ERROR
        .try_with(|slot| match slot.borrow().as_ref() {
            // The CString's heap buffer stays put until the slot is next assigned.
            Some(c) => c.as_ptr(),
            None => c"".as_ptr(),
        })
        .unwrap_or(c"".as_ptr())
}

/// This thread's last message as a Rust string (for tests).
#[cfg(test)]
pub(crate) fn last_error() -> String {
    // SAFETY: `last_error_ptr` returns a valid NUL-terminated string that lives until the
    // next katachi call on this thread; it is copied out before any such call.
    unsafe { CStr::from_ptr(last_error_ptr()) }
        .to_string_lossy()
        .into_owned()
}

/// The text of a panic payload (`panic!("...")` gives a `&str` or a `String`).
pub(crate) fn panic_message(payload: &(dyn Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_owned()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "a panic with a non-text payload".to_owned()
    }
}

fn internal_message(function: &str, payload: &(dyn Any + Send)) -> String {
    format!(
        "{function}: internal error: katachi panicked: {} (this is a bug in katachi; please report it)",
        panic_message(payload)
    )
}

/// The panic boundary for functions that return a status: clears the last message, runs
/// `body`, and maps its error or panic to a status and a message prefixed with `function`.
pub(crate) fn guard(function: &str, body: impl FnOnce() -> FfiResult) -> KatachiStatus {
    clear_last_error();
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => KatachiStatus::Ok,
        Ok(Err(e)) => {
            set_last_error(&format!("{function}: {}", e.message));
            e.status
        }
        Err(payload) => {
            set_last_error(&internal_message(function, payload.as_ref()));
            // Dropping the payload could itself panic; forget it instead of risking that.
            std::mem::forget(payload);
            KatachiStatus::InternalError
        }
    }
}

/// The panic boundary for the few functions that cannot fail and so return a value rather
/// than a status (names, versions, defaults, `katachi_mesh_free`). They leave the last
/// message alone, so `katachi_status_name(s)` can be printed beside it; if `body` panics
/// (a bug), the result is `fallback` and the message says so.
pub(crate) fn guard_value<T>(function: &str, fallback: T, body: impl FnOnce() -> T) -> T {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(v) => v,
        Err(payload) => {
            set_last_error(&internal_message(function, payload.as_ref()));
            std::mem::forget(payload);
            fallback
        }
    }
}

/// Checks `p` is not NULL and is aligned for `T`.
pub(crate) fn check_ptr<T>(p: *const T, param: &str) -> FfiResult {
    if p.is_null() {
        Err(FfiError::null(param))
    } else if !p.is_aligned() {
        Err(FfiError::invalid(format!(
            "{param} ({p:p}) is not aligned to {} bytes",
            std::mem::align_of::<T>()
        )))
    } else {
        Ok(())
    }
}

/// A shared reference from a caller's pointer, or an error naming `param`.
///
/// # Safety
/// A non-NULL `p` must point to a valid `T` that outlives `'a` and is not written meanwhile.
pub(crate) unsafe fn deref<'a, T>(p: *const T, param: &str) -> FfiResult<&'a T> {
    check_ptr(p, param)?;
    // SAFETY: non-NULL and aligned (checked); validity is the caller's promise.
    Ok(unsafe { &*p })
}

/// An exclusive reference from a caller's pointer, or an error naming `param`.
///
/// # Safety
/// A non-NULL `p` must point to a valid `T` that outlives `'a` and that nothing else accesses meanwhile.
pub(crate) unsafe fn deref_mut<'a, T>(p: *mut T, param: &str) -> FfiResult<&'a mut T> {
    check_ptr(p, param)?;
    // SAFETY: non-NULL and aligned (checked); validity and exclusivity are the caller's promise.
    Ok(unsafe { &mut *p })
}

fn check_array<T>(p: *const T, len: usize, param: &str, why: &dyn Display) -> FfiResult {
    if p.is_null() {
        return Err(FfiError::new(
            KatachiStatus::NullPointer,
            format!("{param} is NULL but {why}"),
        ));
    }
    check_ptr(p, param)?;
    if len
        .checked_mul(std::mem::size_of::<T>())
        .is_none_or(|b| b > isize::MAX as usize)
    {
        return Err(FfiError::invalid(format!(
            "{param}: {len} elements is more than any buffer can hold"
        )));
    }
    Ok(())
}

/// A slice of `len` elements from a caller's array. With `len == 0`, `p` may be NULL; otherwise
/// a NULL `p` fails with "`param` is NULL but `why`" (e.g. "positions is NULL but vertex_count is 8").
///
/// # Safety
/// A non-NULL `p` must point to `len` valid, initialised `T`s that outlive `'a`.
pub(crate) unsafe fn slice<'a, T>(
    p: *const T,
    len: usize,
    param: &str,
    why: &dyn Display,
) -> FfiResult<&'a [T]> {
    if len == 0 {
        return Ok(&[]);
    }
    check_array(p, len, param, why)?;
    // SAFETY: non-NULL, aligned, size in range (checked); validity is the caller's promise.
    Ok(unsafe { std::slice::from_raw_parts(p, len) })
}

/// A mutable slice of `len` elements from a caller's buffer; like [`slice`].
///
/// # Safety
/// A non-NULL `p` must point to `len` writable `T`s that outlive `'a` and that nothing else accesses.
pub(crate) unsafe fn slice_mut<'a, T>(
    p: *mut T,
    len: usize,
    param: &str,
    why: &dyn Display,
) -> FfiResult<&'a mut [T]> {
    if len == 0 {
        return Ok(&mut []);
    }
    check_array(p, len, param, why)?;
    // SAFETY: as for `slice`, plus exclusivity, which is the caller's promise.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, len) })
}

/// Checks a caller's buffer of `capacity` elements can take `needed`, and returns the first
/// `needed` elements. A short buffer gives `KATACHI_STATUS_BUFFER_TOO_SMALL` saying how many are
/// needed (so `(NULL, 0)` asks the size); a NULL buffer with a nonzero need gives
/// `KATACHI_STATUS_NULL_POINTER`.
///
/// # Safety
/// A non-NULL `p` must point to `capacity` writable `T`s that outlive `'a`.
pub(crate) unsafe fn out_buffer<'a, T>(
    p: *mut T,
    capacity: usize,
    needed: usize,
    param: &str,
    what: &dyn Display,
) -> FfiResult<&'a mut [T]> {
    if capacity < needed {
        return Err(FfiError::new(
            KatachiStatus::BufferTooSmall,
            format!("{param} has room for {capacity} values, but {needed} are needed ({what})"),
        ));
    }
    // SAFETY: forwarded to the caller; only the first `needed` of `capacity` elements are used.
    unsafe {
        slice_mut(
            p,
            needed,
            param,
            &format_args!("{needed} values are needed ({what})"),
        )
    }
}

/// A UTF-8 string from a caller's NUL-terminated C string.
///
/// # Safety
/// A non-NULL `p` must point to a NUL-terminated string that outlives `'a`.
pub(crate) unsafe fn c_str<'a>(p: *const c_char, param: &str) -> FfiResult<&'a str> {
    if p.is_null() {
        return Err(FfiError::null(param));
    }
    // SAFETY: non-NULL (checked); NUL termination and lifetime are the caller's promise.
    let bytes = unsafe { CStr::from_ptr(p) };
    bytes.to_str().map_err(|e| {
        FfiError::invalid(format!(
            "{param} is not valid UTF-8 (invalid byte at offset {}: {:?})",
            e.valid_up_to(),
            bytes.to_string_lossy()
        ))
    })
}

/// Writes an info struct that starts with `uint32_t struct_size`, honouring the caller's size:
/// rejects a `struct_size` below `min_size` (the size of the struct's first version), and
/// writes at most `struct_size` bytes, so a caller built against an older, shorter struct
/// keeps working. `struct_size` itself is left as the caller set it.
///
/// # Safety
/// A non-NULL `p` must point to `struct_size` writable bytes (the caller's promise), of which
/// the first four hold `struct_size`.
pub(crate) unsafe fn write_sized<T: Copy>(
    p: *mut T,
    value: T,
    min_size: usize,
    param: &str,
    type_name: &str,
) -> FfiResult {
    check_ptr(p, param)?;
    // SAFETY: non-NULL and aligned; every such struct starts with a `u32` struct_size.
    let struct_size = unsafe { p.cast::<u32>().read() } as usize;
    if struct_size < min_size {
        return Err(FfiError::invalid(format!(
            "{param}->struct_size is {struct_size}, but {type_name} needs at least {min_size} \
             (set it to sizeof({type_name}), or start from {}())",
            default_fn_name(type_name)
        )));
    }
    let n = struct_size.min(std::mem::size_of::<T>());
    // SAFETY: `value` is a `T` (n ≤ size_of::<T>() bytes readable), the caller's buffer has
    // `struct_size ≥ n` writable bytes; the first 4 bytes (struct_size) are skipped so the
    // caller's value stays. Byte copies may carry padding, which memcpy allows.
    unsafe {
        let src = (&value as *const T).cast::<u8>();
        let dst = p.cast::<u8>();
        std::ptr::copy_nonoverlapping(src.add(4), dst.add(4), n - 4);
    }
    Ok(())
}

/// `KatachiMeshInfo` → `katachi_mesh_info_default`.
fn default_fn_name(type_name: &str) -> String {
    let mut s = String::new();
    for (i, ch) in type_name.chars().enumerate() {
        if ch.is_uppercase() {
            if i > 0 {
                s.push('_');
            }
            s.extend(ch.to_lowercase());
        } else {
            s.push(ch);
        }
    }
    s + "_default"
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ok_clears_the_last_message() {
        set_last_error("old");
        assert_eq!(last_error(), "old");
        assert_eq!(guard("f", || Ok(())), KatachiStatus::Ok);
        assert_eq!(last_error(), "");
    }

    #[test]
    fn errors_are_prefixed_with_the_function() {
        let s = guard("katachi_x", || Err(FfiError::invalid("count is 0")));
        assert_eq!(s, KatachiStatus::InvalidArgument);
        assert_eq!(last_error(), "katachi_x: count is 0");
    }

    #[test]
    fn a_panic_becomes_internal_error_with_its_message() {
        let s = guard("katachi_boom", || panic!("exploded at step {}", 3));
        assert_eq!(s, KatachiStatus::InternalError);
        let m = last_error();
        assert!(m.starts_with("katachi_boom: internal error"), "{m}");
        assert!(m.contains("exploded at step 3"), "{m}");
        assert!(m.contains("bug in katachi"), "{m}");
        // A static-str payload too, and a non-text payload.
        assert_eq!(
            guard("g", || std::panic::panic_any(17u8)),
            KatachiStatus::InternalError
        );
        assert!(last_error().contains("non-text payload"));
        // The thread is fine afterwards.
        assert_eq!(guard("h", || Ok(())), KatachiStatus::Ok);
    }

    #[test]
    fn a_todo_stub_becomes_internal_error() {
        let s = guard("katachi_mesh_read", || -> FfiResult { todo!("io::read") });
        assert_eq!(s, KatachiStatus::InternalError);
        assert!(last_error().contains("not yet implemented: io::read"));
    }

    #[test]
    fn guard_value_returns_the_fallback_on_panic() {
        let v = guard_value("katachi_v", 7u32, || panic!("no"));
        assert_eq!(v, 7);
        assert!(last_error().contains("katachi_v: internal error"));
        // Infallible functions leave the message alone.
        assert_eq!(guard_value("katachi_v", 7u32, || 9), 9);
        assert!(last_error().contains("katachi_v: internal error"));
    }

    #[test]
    fn messages_are_per_thread() {
        set_last_error("main thread");
        std::thread::spawn(|| {
            assert_eq!(last_error(), "");
            set_last_error("other thread");
            assert_eq!(last_error(), "other thread");
        })
        .join()
        .unwrap();
        assert_eq!(last_error(), "main thread");
    }

    #[test]
    fn interior_nul_and_control_characters_are_escaped() {
        set_last_error("a\0b");
        assert_eq!(last_error(), "a\\0b");
        set_last_error("x.off\x1b[2J\ny é");
        assert_eq!(last_error(), "x.off\\u{1b}[2J\\ny é");
    }

    #[test]
    fn kernel_errors_map_by_kind() {
        let e: FfiError = Error::InvalidArgument("x".into()).into();
        assert_eq!(e.status, KatachiStatus::InvalidArgument);
        let e: FfiError = Error::NoSuchEdge { a: 1, b: 2 }.into();
        assert_eq!(e.status, KatachiStatus::BadInput);
        let e: FfiError = Error::NonManifoldEdge {
            a: 1,
            b: 2,
            uses: 3,
        }
        .into();
        assert_eq!(e.status, KatachiStatus::BadTopology);
        let e: FfiError = Error::UnknownFormat {
            path: "x.stl".into(),
        }
        .into();
        assert_eq!(e.status, KatachiStatus::IoError);
        let e: FfiError = Error::Internal("x".into()).into();
        assert_eq!(e.status, KatachiStatus::InternalError);
    }

    #[test]
    fn pointer_checks_name_the_parameter() {
        let e = unsafe { slice::<f64>(std::ptr::null(), 24, "positions", &"vertex_count is 8") }
            .unwrap_err();
        assert_eq!(e.status, KatachiStatus::NullPointer);
        assert_eq!(e.message, "positions is NULL but vertex_count is 8");
        assert!(unsafe { slice::<f64>(std::ptr::null(), 0, "p", &"") }
            .unwrap()
            .is_empty());
        let buf = [0u64; 2];
        let odd = (buf.as_ptr() as *const u8).wrapping_add(1) as *const u32;
        let e = unsafe { deref(odd, "counts") }.unwrap_err();
        assert_eq!(e.status, KatachiStatus::InvalidArgument);
        assert!(e.message.contains("counts"));
    }

    #[test]
    fn short_buffers_say_what_is_needed() {
        let mut buf = [0.0f64; 4];
        let e = unsafe { out_buffer(buf.as_mut_ptr(), 4, 24, "positions", &"3 × 8 vertices") }
            .unwrap_err();
        assert_eq!(e.status, KatachiStatus::BufferTooSmall);
        assert!(e.message.contains("24 are needed"), "{}", e.message);
        let e = unsafe { out_buffer::<f64>(std::ptr::null_mut(), 30, 24, "positions", &"") }
            .unwrap_err();
        assert_eq!(e.status, KatachiStatus::NullPointer);
    }

    #[test]
    fn invalid_utf8_is_an_invalid_argument() {
        let bad = c"ab\xffcd.obj";
        let e = unsafe { c_str(bad.as_ptr(), "path") }.unwrap_err();
        assert_eq!(e.status, KatachiStatus::InvalidArgument);
        assert!(e.message.contains("not valid UTF-8"), "{}", e.message);
        assert!(e.message.contains("offset 2"), "{}", e.message);
    }

    #[test]
    fn sized_structs_reject_small_sizes_and_keep_struct_size() {
        #[derive(Clone, Copy, Debug, PartialEq)]
        #[repr(C)]
        struct Info {
            struct_size: u32,
            a: u32,
            b: u64,
        }
        let v = Info {
            struct_size: 999,
            a: 1,
            b: 2,
        };
        let mut out = Info {
            struct_size: 8,
            a: 0,
            b: 0,
        };
        let e = unsafe { write_sized(&mut out, v, 16, "info", "KatachiMeshInfo") }.unwrap_err();
        assert!(
            e.message.contains("katachi_mesh_info_default"),
            "{}",
            e.message
        );
        assert_eq!(out.a, 0);
        out.struct_size = 16;
        unsafe { write_sized(&mut out, v, 16, "info", "KatachiMeshInfo") }.unwrap();
        assert_eq!(
            out,
            Info {
                struct_size: 16,
                a: 1,
                b: 2
            }
        );
    }
}
