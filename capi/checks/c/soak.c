/*
 * soak.c: many lives of one model in one process, as a parametric study
 * in an FMU host runs them, with resident memory read from
 * /proc/self/statm.
 *
 *   soak UNZIPPED_FMU_DIR [CYCLES] [STEPS]
 *
 * fmi2: CYCLES times fmi2Instantiate, fmi2SetupExperiment, initialization,
 * STEPS steps (fmi2SetReal, fmi2DoStep, fmi2GetReal), fmi2Reset, STEPS
 * steps again, fmi2FreeInstance. capi: CYCLES times
 * hysteron_model_from_json, STEPS hysteron_step, hysteron_reset, STEPS
 * steps again, hysteron_model_free. Defaults: 10000 cycles of 1000 steps.
 *
 * Prints per face one line
 *   `<face>: <cycles> cycles of <steps> steps, <us> us per cycle, resident
 *    <kB> kB after 100 cycles, <kB> kB at the end, growth <kB> kB`
 * and exits 1 if any call fails or if any run's outputs (the sum of the
 * bits) differ from the first run's: every life of the model is the same.
 * capi/checks/test_c_api.py runs it and bounds the growth.
 */
#define _POSIX_C_SOURCE 199309L
#include "../../../examples/c/fmi2_host.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Resident memory in kB (0 if /proc is not there). */
static long resident_kb(void) {
    long pages_total = 0, pages_resident = 0;
    FILE *f = fopen("/proc/self/statm", "r");
    if (!f) return 0;
    if (fscanf(f, "%ld %ld", &pages_total, &pages_resident) != 2) pages_resident = 0;
    fclose(f);
    return pages_resident * (sysconf(_SC_PAGESIZE) / 1024);
}

/* One face's life cycle: make, run, reset, run, free; the output sum of
 * each run into sums[0..2). Returns 0 on success. */
typedef int (*Life)(const UnzippedFmu *, const double *, long, double *);

static int fmi2_life(const UnzippedFmu *fmu, const double *x, long steps, double *sums) {
    fmi2CallbackFunctions callbacks = {fmu_logger, NULL, NULL, NULL, NULL};
    fmi2Component c = fmi2Instantiate("soak", 1, fmu->guid, fmu->uri, &callbacks, 0, 0);
    if (!c) return 1;
    const unsigned int vr_x = 0, vr_y = 1;
    for (int run = 0; run < 2; run++) {
        if (run == 1 && fmi2Reset(c)) return 1;
        if (fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0) || fmi2EnterInitializationMode(c) ||
            fmi2ExitInitializationMode(c))
            return 1;
        double t = 0.0, y, sum = 0.0;
        for (long i = 0; i < steps; i++) {
            if (fmi2SetReal(c, &vr_x, 1, &x[i]) || fmi2DoStep(c, t, 1e-3, 1) ||
                fmi2GetReal(c, &vr_y, 1, &y))
                return 1;
            t += 1e-3;
            sum += y;
        }
        sums[run] = sum;
    }
    fmi2FreeInstance(c);
    return 0;
}

static int capi_life(const UnzippedFmu *fmu, const double *x, long steps, double *sums) {
    HysteronModel *model = NULL;
    if (hysteron_model_from_json(fmu->json, &model) != HYSTERON_STATUS_OK) return 1;
    for (int run = 0; run < 2; run++) {
        if (run == 1 && hysteron_reset(model) != HYSTERON_STATUS_OK) return 1;
        double y, sum = 0.0;
        for (long i = 0; i < steps; i++) {
            if (hysteron_step(model, x[i], &y) != HYSTERON_STATUS_OK) return 1;
            sum += y;
        }
        sums[run] = sum;
    }
    hysteron_model_free(model);
    return 0;
}

static int soak(const char *face, Life life, const UnzippedFmu *fmu, const double *x,
                long cycles, long steps) {
    double first[2] = {0.0, 0.0}, sums[2];
    long after_100 = 0;
    double t0 = now();
    for (long k = 0; k < cycles; k++) {
        if (life(fmu, x, steps, sums)) {
            fprintf(stderr, "%s: cycle %ld failed: %s\n", face, k, hysteron_last_error());
            return 1;
        }
        if (k == 0) {
            first[0] = sums[0];
            first[1] = sums[1];
        }
        if (sums[0] != first[0] || sums[1] != first[0]) {
            fprintf(stderr, "%s: cycle %ld gave %.17g and %.17g, cycle 0 %.17g\n", face, k,
                    sums[0], sums[1], first[0]);
            return 1;
        }
        if (k == 99) after_100 = resident_kb();
    }
    double per_cycle = (now() - t0) / (double)cycles * 1e6;
    long end = resident_kb();
    if (cycles < 100) after_100 = end;
    printf("%s: %ld cycles of %ld steps, %.1f us per cycle, resident %ld kB after 100 cycles, "
           "%ld kB at the end, growth %ld kB\n",
           face, cycles, steps, per_cycle, after_100, end, end - after_100);
    return 0;
}

int main(int argc, char **argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: %s UNZIPPED_FMU_DIR [CYCLES] [STEPS]\n", argv[0]);
        return 2;
    }
    long cycles = argc > 2 ? atol(argv[2]) : 10000;
    long steps = argc > 3 ? atol(argv[3]) : 1000;
    if (cycles <= 0 || steps <= 0) {
        fprintf(stderr, "CYCLES and STEPS must be positive\n");
        return 2;
    }
    UnzippedFmu fmu = open_fmu(argv[1]);
    double *x = malloc((size_t)steps * sizeof *x);
    if (!x) return 1;
    for (long i = 0; i < steps; i++)
        x[i] = 1.4 * sin(6.283185307179586 * (double)i / 400.0);
    int failed = soak("fmi2", fmi2_life, &fmu, x, cycles, steps) ||
                 soak("capi", capi_life, &fmu, x, cycles, steps);
    free(x);
    free(fmu.json);
    return failed;
}
