/*
 * bench_fmi: the cost of one fmi2DoStep of an FMU made by
 * `hysteron export-fmu`, called as an FMI host calls it (fmi2SetReal of
 * the input, fmi2DoStep, fmi2GetReal of the output), against the model's
 * own work through the C API (hysteron_step) on the same input.
 *
 *   hysteron export-fmu --model examples/specs/paper.json --output paper.fmu
 *   unzip -d paper paper.fmu
 *   cc -O2 -I capi/include examples/c/bench_fmi.c -o bench_fmi \
 *      -L target/release -lhysteron_c -Wl,-rpath,target/release -lm
 *   ./bench_fmi paper [N]
 *
 * libhysteron_c.so is the FMU's binary too, so the fmi2* functions are
 * linked directly (their prototypes: fmi2_host.h).
 * Prints `fmi2DoStep: <ns> ns per step`, `hysteron_step: <ns> ns per step`
 * and their difference, medians of 5 runs, and the sums of both outputs,
 * which must be equal (exit code 1 otherwise).
 */
#define _POSIX_C_SOURCE 199309L
#include "fmi2_host.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int by_value(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

#define RUNS 5
#define TAU 6.283185307179586

int main(int argc, char **argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: %s UNZIPPED_FMU_DIR [N]\n", argv[0]);
        return 2;
    }
    const char *dir = argv[1];
    long n = argc > 2 ? atol(argv[2]) : 2000000;
    if (n <= 0) {
        fprintf(stderr, "N must be positive\n");
        return 2;
    }
    UnzippedFmu fmu = open_fmu(dir);
    char *json = fmu.json;

    double *x = malloc((size_t)n * sizeof *x);
    for (long i = 0; i < n; i++)
        x[i] = 2.5 * sin(TAU * (double)i / 2000.0) + 0.3 * sin(TAU * (double)i / 97.3);

    fmi2CallbackFunctions callbacks = {fmu_logger, NULL, NULL, NULL, NULL};
    fmi2Component c = fmi2Instantiate("bench", 1, fmu.guid, fmu.uri, &callbacks, 0, 0);
    HysteronModel *model = NULL;
    if (!c || hysteron_model_from_json(json, &model) != HYSTERON_STATUS_OK) {
        fprintf(stderr, "cannot instantiate: %s\n", hysteron_last_error());
        return 1;
    }
    const unsigned int vr_x = 0, vr_y = 1;
    const double h = 1e-3;
    double fmi[RUNS], capi[RUNS], sum_fmi = 0.0, sum_capi = 0.0;
    for (int r = 0; r < RUNS; r++) {
        fmi2Reset(c);
        fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0);
        fmi2EnterInitializationMode(c);
        fmi2ExitInitializationMode(c);
        double t0 = now(), t = 0.0, y;
        for (long i = 0; i < n; i++) {
            if (fmi2SetReal(c, &vr_x, 1, &x[i]) || fmi2DoStep(c, t, h, 1) ||
                fmi2GetReal(c, &vr_y, 1, &y))
                return 1;
            t += h;
            sum_fmi += y;
        }
        fmi[r] = (now() - t0) / (double)n * 1e9;

        hysteron_reset(model);
        t0 = now();
        for (long i = 0; i < n; i++) {
            if (hysteron_step(model, x[i], &y) != HYSTERON_STATUS_OK) {
                fprintf(stderr, "%s\n", hysteron_last_error());
                return 1;
            }
            sum_capi += y;
        }
        capi[r] = (now() - t0) / (double)n * 1e9;
    }
    qsort(fmi, RUNS, sizeof *fmi, by_value);
    qsort(capi, RUNS, sizeof *capi, by_value);
    printf("fmi2DoStep: %.1f ns per step (fmi2SetReal + fmi2DoStep + fmi2GetReal, %ld steps, median of %d)\n",
           fmi[RUNS / 2], n, RUNS);
    printf("hysteron_step: %.1f ns per step (the same model through the C API)\n", capi[RUNS / 2]);
    printf("overhead: %.1f ns per step\n", fmi[RUNS / 2] - capi[RUNS / 2]);
    /* The same model on the same inputs: the same outputs, bit for bit. */
    printf("checksum: fmi %.17g, capi %.17g\n", sum_fmi, sum_capi);
    if (sum_fmi != sum_capi) {
        fprintf(stderr, "the FMU and the C API disagree\n");
        return 1;
    }
    fmi2FreeInstance(c);
    hysteron_model_free(model);
    free(json);
    free(x);
    return 0;
}
