/*
 * bench_step.c: the cost of one sample of the paper model through the
 * hysteron C API.
 *
 * Builds the model of a JSON spec (the paper model by default), then times
 * N calls of hysteron_step on the input
 *
 *     x_i = 2.5 sin(2 pi i / 2000) + 0.3 sin(2 pi i / 97.3)
 *
 * and one hysteron_process over the same N samples, each R = 5 times from
 * the initial state (hysteron_reset between runs), and prints the median
 * time per sample. The outputs are summed and printed so that no loop can
 * be optimized away (the two sums are equal: step and process compute the
 * same samples).
 *
 * Usage: bench_step [spec.json [N]]
 *   spec.json  default examples/specs/paper.json (run from the repository root)
 *   N          number of samples, default 10000000
 *
 * Build and run, from the repository root:
 *   cargo build --release -p hysteron-c
 *   cc -std=c11 -O2 -I capi/include examples/c/bench_step.c -L target/release \
 *      -lhysteron_c -Wl,-rpath,target/release -lm -o bench_step
 *   ./bench_step examples/specs/paper.json
 * (the rpath is relative: run it from the repository root).
 */

#define _POSIX_C_SOURCE 199309L /* clock_gettime */

#include "common.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

enum { RUNS = 5 };

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, by_value);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int main(int argc, char **argv)
{
    const char *path = argc > 1 ? argv[1] : "examples/specs/paper.json";
    long n_arg = argc > 2 ? strtol(argv[2], NULL, 10) : 10000000L;
    if (n_arg <= 0) {
        fprintf(stderr, "bench_step: N must be a positive integer\n");
        return 1;
    }
    size_t n = (size_t)n_arg;

    char *json = read_file(path);
    HysteronModel *model = NULL;
    check(hysteron_model_from_json(json, &model), "building the model");

    double *xs = malloc(n * sizeof *xs), *ys = malloc(n * sizeof *ys);
    if (xs == NULL || ys == NULL) {
        fprintf(stderr, "bench_step: out of memory for %zu samples\n", n);
        return 1;
    }
    const double two_pi = 6.28318530717958647692;
    for (size_t i = 0; i < n; i++) {
        xs[i] = 2.5 * sin(two_pi * (double)i / 2000.0) + 0.3 * sin(two_pi * (double)i / 97.3);
    }

    double step_ns[RUNS], process_ns[RUNS], step_sum = 0.0, process_sum = 0.0;
    for (int run = 0; run < RUNS; run++) {
        check(hysteron_reset(model), "reset");
        double sum = 0.0, y = 0.0;
        double t0 = now_ns();
        for (size_t i = 0; i < n; i++) {
            check(hysteron_step(model, xs[i], &y), "step");
            sum += y;
        }
        step_ns[run] = (now_ns() - t0) / (double)n;
        step_sum = sum;

        check(hysteron_reset(model), "reset");
        t0 = now_ns();
        check(hysteron_process(model, xs, ys, n), "process");
        process_ns[run] = (now_ns() - t0) / (double)n;
        sum = 0.0;
        for (size_t i = 0; i < n; i++) {
            sum += ys[i];
        }
        process_sum = sum;
    }

    printf("step: %.2f ns per call (paper model, %zu calls, median of %d)\n",
           median(step_ns, RUNS), n, RUNS);
    printf("process: %.2f ns per sample (paper model, %zu samples, median of %d)\n",
           median(process_ns, RUNS), n, RUNS);
    printf("checksum: step %.17g, process %.17g\n", step_sum, process_sum);

    hysteron_model_free(model);
    free(ys);
    free(xs);
    free(json);
    return 0;
}
