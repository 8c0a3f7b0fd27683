/*
 * A tiny check harness shared by the C and C++ link tests in tests/c.
 *
 * Each check prints one line, "ok   <name>" or "FAIL <name>: <why>", and finish() prints
 * "N passed, M failed" and gives the exit code. The last error message is copied right after
 * the call it belongs to, before any other katachi call could replace it.
 */
#ifndef KATACHI_TEST_CHECK_H
#define KATACHI_TEST_CHECK_H

#include <stdio.h>
#include <string.h>

#include "katachi.h"

static int check_passed = 0;
static int check_failed = 0;
/* The message of the call the last CHECK_* macro made (copied). */
static char check_message[4096];

static inline void check_result(int ok, const char *name, const char *file, int line, const char *why)
{
    if (ok) {
        check_passed++;
        printf("ok   %s\n", name);
    } else {
        check_failed++;
        printf("FAIL %s (%s:%d): %s\n", name, file, line, why);
    }
    fflush(stdout);
}

static inline void check_copy_message(void)
{
    const char *m = katachi_last_error_message();
    if (m == NULL) {
        strcpy(check_message, "<katachi_last_error_message returned NULL>");
        return;
    }
    strncpy(check_message, m, sizeof check_message - 1);
    check_message[sizeof check_message - 1] = '\0';
}

/* A plain condition. */
#define CHECK(name, cond) check_result((cond) ? 1 : 0, (name), __FILE__, __LINE__, "expected " #cond)

/* A call that must succeed and leave the last message empty. */
#define CHECK_OK(name, call) check_status_impl((name), (call), KATACHI_STATUS_OK, NULL, __FILE__, __LINE__)

/* A call that must fail with `status`, its message containing `substring` (may be NULL). */
#define CHECK_ERR(name, call, status, substring) \
    check_status_impl((name), (call), (status), (substring), __FILE__, __LINE__)

/* Returns whether the check passed. */
static inline int check_status_impl(const char *name, KatachiStatus got, KatachiStatus expected,
                             const char *substring, const char *file, int line)
{
    char why[8192];
    int ok;
    check_copy_message();
    if (got != expected) {
        snprintf(why, sizeof why, "status %s, expected %s; message: \"%s\"",
                 katachi_status_name((uint32_t)got), katachi_status_name((uint32_t)expected),
                 check_message);
        ok = 0;
    } else if (expected == KATACHI_STATUS_OK && check_message[0] != '\0') {
        snprintf(why, sizeof why, "succeeded but left the message \"%s\"", check_message);
        ok = 0;
    } else if (expected != KATACHI_STATUS_OK && check_message[0] == '\0') {
        snprintf(why, sizeof why, "failed with %s but left no message",
                 katachi_status_name((uint32_t)got));
        ok = 0;
    } else if (substring != NULL && strstr(check_message, substring) == NULL) {
        snprintf(why, sizeof why, "message \"%s\" does not contain \"%s\"", check_message,
                 substring);
        ok = 0;
    } else {
        why[0] = '\0';
        ok = 1;
    }
    check_result(ok, name, file, line, why);
    return ok;
}

/* Whether the last CHECK_* call's message contains `s`. */
#define MESSAGE_HAS(s) (strstr(check_message, (s)) != NULL)

/* Prints the closing line; returns the process exit code. */
static inline int check_finish(void)
{
    printf("%d passed, %d failed\n", check_passed, check_failed);
    return check_failed == 0 ? 0 : 1;
}

#endif /* KATACHI_TEST_CHECK_H */
