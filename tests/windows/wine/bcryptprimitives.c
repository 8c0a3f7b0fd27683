/*
 * bcryptprimitives.dll for Wine 8.0 (Debian 12), which lacks it (Wine has it from 8.13).
 *
 * Rust's standard library for Windows calls ProcessPrng from bcryptprimitives.dll (since Rust
 * 1.78; every Windows 10 and 11 has it) for HashMap seeds, so katachi.dll and katachi.exe do not
 * load under Debian's Wine without it. `cargo xtask windows-test` builds this stand-in with
 * mingw-w64 and puts it into its own Wine prefix (target/wine/drive_c/windows/system32); it is
 * never shipped. ProcessPrng never fails (Microsoft's documentation): the bytes come from
 * RtlGenRandom (advapi32's SystemFunction036), Wine's system random source.
 */
#include <windows.h>

BOOLEAN WINAPI SystemFunction036(PVOID buffer, ULONG length);

BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T length)
{
    while (length > 0) {
        ULONG chunk = length > 0x40000000 ? 0x40000000 : (ULONG)length;
        if (!SystemFunction036(data, chunk)) return FALSE;
        data += chunk;
        length -= chunk;
    }
    return TRUE;
}
