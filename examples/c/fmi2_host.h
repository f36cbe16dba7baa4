/*
 * What a C program needs to drive an FMU of `hysteron export-fmu` as an
 * FMI 2.0 host does, with libhysteron_c.so (the FMU's binary) linked
 * directly: the FMI 2.0 prototypes used, a logger that prints to stderr,
 * and the GUID and resource URI of an unzipped FMU.
 */
#ifndef HYSTERON_EXAMPLES_FMI2_HOST_H
#define HYSTERON_EXAMPLES_FMI2_HOST_H

#include "common.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef void *fmi2Component;
typedef struct {
    void (*logger)(void *, const char *, int, const char *, const char *, ...);
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void (*stepFinished)(void *, int);
    void *componentEnvironment;
} fmi2CallbackFunctions;

fmi2Component fmi2Instantiate(const char *, int, const char *, const char *,
                              const fmi2CallbackFunctions *, int, int);
void fmi2FreeInstance(fmi2Component);
int fmi2SetupExperiment(fmi2Component, int, double, double, int, double);
int fmi2EnterInitializationMode(fmi2Component);
int fmi2ExitInitializationMode(fmi2Component);
int fmi2Reset(fmi2Component);
int fmi2SetReal(fmi2Component, const unsigned int *, size_t, const double *);
int fmi2GetReal(fmi2Component, const unsigned int *, size_t, double *);
int fmi2DoStep(fmi2Component, double, double, int);

/* Prints the FMU's messages to stderr. */
static inline void fmu_logger(void *env, const char *name, int status, const char *category,
                              const char *message, ...) {
    (void)env;
    (void)category;
    fprintf(stderr, "%s (status %d): %s\n", name, status, message);
}

/* The value of attribute `name` (`name="..."`) in `xml`, copied into `out`. */
static inline int attribute(const char *xml, const char *name, char *out, size_t len) {
    char key[64];
    snprintf(key, sizeof key, " %s=\"", name);
    const char *at = strstr(xml, key);
    if (!at) return 0;
    at += strlen(key);
    const char *end = strchr(at, '"');
    if (!end || (size_t)(end - at) >= len) return 0;
    memcpy(out, at, (size_t)(end - at));
    out[end - at] = '\0';
    return 1;
}

/* An unzipped FMU: its GUID, its resource URI and its spec's text. */
typedef struct {
    char guid[128];
    char uri[4200];
    char *json;
} UnzippedFmu;

/* Reads the FMU unzipped in `dir` (exits on failure). */
static inline UnzippedFmu open_fmu(const char *dir) {
    UnzippedFmu fmu;
    char path[4096];
    snprintf(path, sizeof path, "%s/modelDescription.xml", dir);
    char *xml = read_file(path);
    if (!attribute(xml, "guid", fmu.guid, sizeof fmu.guid)) {
        fprintf(stderr, "cannot read the GUID from %s\n", path);
        exit(1);
    }
    free(xml);
    snprintf(fmu.uri, sizeof fmu.uri, "file://%s/resources", dir);
    snprintf(path, sizeof path, "%s/resources/model.json", dir);
    fmu.json = read_file(path);
    return fmu;
}

#endif
