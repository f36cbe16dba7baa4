/*
 * Helpers shared by the C examples: a status check that exits with the
 * library's message, and a whole-file read.
 */
#ifndef HYSTERON_EXAMPLES_COMMON_H
#define HYSTERON_EXAMPLES_COMMON_H

#include "hysteron.h"

#include <stdio.h>
#include <stdlib.h>

/* Exits with the library's message if a call failed. */
static inline void check(HysteronStatus status, const char *what)
{
    if (status != HYSTERON_STATUS_OK) {
        fprintf(stderr, "%s failed (status %d): %s\n", what, (int)status,
                hysteron_last_error());
        exit(1);
    }
}

/* The whole file as a NUL-terminated string (exits on failure). */
static inline char *read_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        perror(path);
        exit(1);
    }
    long size = fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
    char *text = size >= 0 ? malloc((size_t)size + 1) : NULL;
    if (text == NULL || fseek(f, 0, SEEK_SET) != 0
        || fread(text, 1, (size_t)size, f) != (size_t)size) {
        fprintf(stderr, "cannot read %s\n", path);
        exit(1);
    }
    fclose(f);
    text[size] = '\0';
    return text;
}

#endif
