/*
 * pi_tracking.c: inverse compensation of a Prandtl-Ishlinskii actuator,
 * through the hysteron C API.
 *
 * The plant is a play-type Prandtl-Ishlinskii bank (`pi_bank`); the
 * compensator is its analytic inverse (`pi_inverse`, built from the same
 * fields). A reference r(t), a decaying two-tone signal, drives the loop
 * sample by sample:
 *
 *     u = inverse(r),   y = plant(u)
 *
 * and the program prints the max and RMS tracking error |y - r|, and, for
 * contrast, the error of the plant driven by the reference directly
 * (plant(r) - r).
 *
 * Usage: pi_tracking [spec.json]
 *   spec.json  a `pi_bank` spec (default: the bank of
 *              examples/specs/prandtl-ishlinskii.json, inline below)
 *
 * Build and run, from the repository root:
 *   cargo build --release -p hysteron-c
 *   cc -std=c11 -I capi/include examples/c/pi_tracking.c -L target/release \
 *      -lhysteron_c -Wl,-rpath,target/release -lm -o pi_tracking
 *   ./pi_tracking examples/specs/prandtl-ishlinskii.json
 * (the rpath is relative: run it from the repository root, or give
 * -Wl,-rpath with an absolute path).
 */

#include "common.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char DEFAULT_SPEC[] =
    "{\"type\": \"pi_bank\", \"a0\": 0.2,"
    " \"r\": [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7],"
    " \"w\": [1.0, 0.6, 0.4, 0.3, 0.2, 0.15, 0.1, 0.05],"
    " \"y0\": []}";

enum { N_SAMPLES = 4000 };

/* The spec with its `"pi_bank"` type replaced by `"pi_inverse"` (the
 * inverse takes the same fields). Caller frees. */
static char *inverse_spec(const char *bank)
{
    static const char from[] = "\"pi_bank\"", to[] = "\"pi_inverse\"";
    const char *at = strstr(bank, from);
    if (at == NULL) {
        fprintf(stderr, "pi_tracking: the spec is not a \"pi_bank\"\n");
        exit(1);
    }
    size_t head = (size_t)(at - bank), tail = strlen(at + strlen(from));
    char *out = malloc(head + strlen(to) + tail + 1);
    if (out == NULL) {
        perror("pi_tracking");
        exit(1);
    }
    memcpy(out, bank, head);
    memcpy(out + head, to, strlen(to));
    memcpy(out + head + strlen(to), at + strlen(from), tail + 1);
    return out;
}

int main(int argc, char **argv)
{
    char *bank_json = argc > 1 ? read_file(argv[1]) : NULL;
    const char *spec = bank_json != NULL ? bank_json : DEFAULT_SPEC;
    char *inverse_json = inverse_spec(spec);

    HysteronModel *plant = NULL, *inverse = NULL, *open_loop = NULL;
    check(hysteron_model_from_json(spec, &plant), "building the plant");
    check(hysteron_model_from_json(inverse_json, &inverse), "building the inverse");
    check(hysteron_model_clone(plant, &open_loop), "cloning the plant");

    /* Reference: two tones under a decaying envelope, from r(0) = 0. */
    const double pi = 3.14159265358979323846;
    double amplitude = 0.0;
    double max_c = 0.0, sq_c = 0.0; /* compensated:   plant(inverse(r)) - r */
    double max_u = 0.0, sq_u = 0.0; /* uncompensated: plant(r) - r */
    for (int i = 0; i < N_SAMPLES; i++) {
        double t = i / 1000.0;
        double r = exp(-t / 2.0) * (1.4 * sin(2.0 * pi * t) + 0.4 * sin(2.0 * pi * 3.3 * t));
        double u, y, y_open;
        check(hysteron_step(inverse, r, &u), "inverse step");
        check(hysteron_step(plant, u, &y), "plant step");
        check(hysteron_step(open_loop, r, &y_open), "open-loop plant step");

        double e = fabs(y - r), e_open = fabs(y_open - r);
        amplitude = fmax(amplitude, fabs(r));
        max_c = fmax(max_c, e);
        sq_c += e * e;
        max_u = fmax(max_u, e_open);
        sq_u += e_open * e_open;
    }

    printf("reference: %d samples, max |r| = %.6g\n", N_SAMPLES, amplitude);
    printf("compensated:   max |y - r| = %.6e   RMS = %.6e\n", max_c, sqrt(sq_c / N_SAMPLES));
    printf("uncompensated: max |y - r| = %.6e   RMS = %.6e\n", max_u, sqrt(sq_u / N_SAMPLES));

    hysteron_model_free(open_loop);
    hysteron_model_free(inverse);
    hysteron_model_free(plant);
    free(inverse_json);
    free(bank_json);
    return 0;
}
