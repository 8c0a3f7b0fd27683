/*
 * A fresh temporary directory for a C test program, on POSIX (mkdtemp under $TMPDIR or /tmp)
 * and on Windows (a new folder under GetTempPath's, where `cargo xtask windows-test` runs the
 * programs under Wine). Define _POSIX_C_SOURCE 200809L before any include for mkdtemp.
 */
#ifndef KATACHI_TEST_TEMPDIR_H
#define KATACHI_TEST_TEMPDIR_H

#include <stdio.h>
#include <stdlib.h>

#ifdef _WIN32
#include <direct.h>
#include <windows.h>
#else
#include <unistd.h>
#endif

/* Makes a new, empty directory named katachi-ctest-… and writes its path into dir (size
 * bytes). Returns 0, or -1 (dir then holds what was tried). */
static int temp_dir_make(char *dir, size_t size)
{
#ifdef _WIN32
    char base[MAX_PATH + 1];
    DWORD n = GetTempPathA(sizeof base, base);
    unsigned i;
    if (n == 0 || n > MAX_PATH) {
        snprintf(dir, size, "%s", "GetTempPathA");
        return -1;
    }
    for (i = 0; i < 1000; i++) {
        snprintf(dir, size, "%skatachi-ctest-%lu-%u", base, (unsigned long)GetCurrentProcessId(), i);
        if (_mkdir(dir) == 0) return 0;
    }
    return -1;
#else
    const char *tmp = getenv("TMPDIR");
    snprintf(dir, size, "%s/katachi-ctest-XXXXXX", tmp != NULL && tmp[0] ? tmp : "/tmp");
    return mkdtemp(dir) == NULL ? -1 : 0;
#endif
}

/* Removes an empty directory; 0 on success. */
static int temp_dir_remove(const char *dir)
{
#ifdef _WIN32
    return _rmdir(dir);
#else
    return rmdir(dir);
#endif
}

#endif
