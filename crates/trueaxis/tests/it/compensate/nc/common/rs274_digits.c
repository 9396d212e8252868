/* Preloaded into LinuxCNC's rs274 by the NC tests: the canonical calls rs274 prints with "%.4f"
   (0.1 um in mm) are printed with "%.10f" instead, so that a test can compare corrected and
   original moves to 0.05 um. Nothing else changes: the interpreter computes in double precision
   either way. */
#define _GNU_SOURCE
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

static const char *widen(const char *fmt, char *buf, size_t size)
{
    size_t j = 0;
    for (size_t i = 0; fmt[i] != 0 && j + 8 < size; i++) {
        if (strncmp(fmt + i, "%.4f", 4) == 0) {
            memcpy(buf + j, "%.10f", 5);
            j += 5;
            i += 3;
        } else {
            buf[j++] = fmt[i];
        }
    }
    buf[j] = 0;
    return buf;
}

int fprintf(FILE *stream, const char *fmt, ...)
{
    char buf[4096];
    va_list ap;
    va_start(ap, fmt);
    int r = vfprintf(stream, widen(fmt, buf, sizeof buf), ap);
    va_end(ap);
    return r;
}

int __fprintf_chk(FILE *stream, int flag, const char *fmt, ...)
{
    (void)flag;
    char buf[4096];
    va_list ap;
    va_start(ap, fmt);
    int r = vfprintf(stream, widen(fmt, buf, sizeof buf), ap);
    va_end(ap);
    return r;
}
