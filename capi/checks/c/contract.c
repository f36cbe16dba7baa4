/*
 * contract.c: the contract of the hysteron C API (capi/include/hysteron.h),
 * checked from C on the paper model.
 *
 * Prints one line per check, `ok <n> - <what>` or `not ok <n> - <what>`
 * (with the status and message that were wrong), then a summary line, and
 * exits non-zero if any check failed. capi/checks/test_c_api.py compiles
 * it, runs it with examples/specs/paper.json as argv[1], and counts the
 * `ok` lines.
 *
 * Checked: step and process agree bit for bit; trial does not commit;
 * commit keeps the last trial; reset and clone; the parameter API
 * (count, name, get, set) against models built from JSON; and every
 * error path: its status, a message naming the problem, and that nothing
 * changed (or, for process, that the samples before the bad one are
 * committed).
 */

#include "hysteron.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The paper model (examples/specs/paper.json) with f_c as a format
 * argument; check 2 compares it with the file. */
static const char PAPER_TEMPLATE[] =
    "{\"type\": \"series\","
    " \"left\": {\"type\": \"mms\", \"f_c\": %.17g, \"k\": 30.0, \"y0\": 0.0},"
    " \"right\": {\"type\": \"bouc_wen\", \"w\": 0.6, \"alpha\": 1.0, \"beta\": 2.5,"
    " \"gamma\": 1.5, \"n\": 1.0, \"h0\": 0.0, \"z0\": 0.0,"
    " \"stiffness\": {\"z\": [0.0, 0.3, 0.6, 0.9, 1.2, 1.5],"
    " \"s\": [10.0, 11.5, 13.5, 16.0, 19.5, 22.5]}},"
    " \"limits\": {\"type\": \"gap\", \"b\": 0.3, \"r0\": 0.0}}";

enum { N = 2000, K = 700 /* a point in the middle of the record */ };

static int checks, failures;

/* Records one check. */
static void report(bool pass, const char *what)
{
    checks++;
    if (pass) {
        printf("ok %d - %s\n", checks, what);
    } else {
        failures++;
        printf("not ok %d - %s (last error: \"%s\")\n", checks, what, hysteron_last_error());
    }
}

/* A check that a call failed with `want` and a message containing
 * `needle`. */
static void expect_error(HysteronStatus got, HysteronStatus want, const char *needle,
                         const char *what)
{
    const char *message = hysteron_last_error();
    bool pass = got == want && message != NULL && strstr(message, needle) != NULL;
    if (!pass) {
        printf("#   status %d (want %d), message should contain \"%s\"\n", (int)got,
               (int)want, needle);
    }
    report(pass, what);
}

/* Set-up that must succeed: stops the program otherwise. */
static void must(HysteronStatus status, const char *what)
{
    if (status != HYSTERON_STATUS_OK) {
        printf("not ok - set-up: %s failed (status %d): %s\n", what, (int)status,
               hysteron_last_error());
        exit(2);
    }
}

static HysteronModel *paper(double f_c)
{
    char json[sizeof PAPER_TEMPLATE + 32];
    snprintf(json, sizeof json, PAPER_TEMPLATE, f_c);
    HysteronModel *m = NULL;
    must(hysteron_model_from_json(json, &m), "building the paper model");
    return m;
}

static HysteronModel *from_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        perror(path);
        exit(2);
    }
    static char json[1 << 16];
    size_t len = fread(json, 1, sizeof json - 1, f);
    fclose(f);
    json[len] = '\0';
    HysteronModel *m = NULL;
    must(hysteron_model_from_json(json, &m), path);
    return m;
}

/* `n` outputs of `m` for `xs` by hysteron_process (must succeed). */
static void run(HysteronModel *m, const double *xs, double *ys, size_t n)
{
    must(hysteron_process(m, xs, ys, n), "process");
}

static bool same_bits(const double *a, const double *b, size_t n)
{
    return memcmp(a, b, n * sizeof *a) == 0;
}

/* Whether `m`, run from its current state on xs[from..N], reproduces
 * ref[from..N] bit for bit. */
static bool continues(HysteronModel *m, const double *xs, const double *ref, size_t from)
{
    static double ys[N];
    run(m, xs + from, ys + from, N - from);
    return same_bits(ys + from, ref + from, N - from);
}

/* The paper model (f_c = 1.5) after the first K samples of `xs`. */
static HysteronModel *paper_after_k(const double *xs)
{
    static double ys[K];
    HysteronModel *m = paper(1.5);
    run(m, xs, ys, K);
    return m;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: contract examples/specs/paper.json\n");
        return 2;
    }
    report(strcmp(hysteron_last_error(), "") == 0,
           "hysteron_last_error is empty before any call failed");

    /* The input: reversals of varying amplitude through the gap. */
    static double xs[N], ref[N], ys[N];
    const double two_pi = 6.28318530717958647692;
    for (int i = 0; i < N; i++) {
        xs[i] = 2.5 * sin(two_pi * i / 500.0) + 0.3 * sin(two_pi * i / 37.3);
    }

    /* --- step, process, trial, commit ------------------------------- */
    HysteronModel *m = paper(1.5);
    for (int i = 0; i < N; i++) {
        must(hysteron_step(m, xs[i], &ref[i]), "step");
    }
    hysteron_model_free(m);

    m = from_file(argv[1]);
    run(m, xs, ys, N);
    report(same_bits(ys, ref, N), "the inline paper spec is examples/specs/paper.json");
    hysteron_model_free(m);

    m = paper(1.5);
    run(m, xs, ys, N);
    report(same_bits(ys, ref, N), "step and process give bit-identical outputs");
    hysteron_model_free(m);

    m = paper(1.5);
    run(m, xs, ys, K);
    for (int i = K; i < N; i++) {
        must(hysteron_step(m, xs[i], &ys[i]), "step");
    }
    report(same_bits(ys, ref, N), "process then step continue the same trajectory");
    hysteron_model_free(m);

    m = paper_after_k(xs);
    double y_trial = NAN, tangent = NAN, y_trial2 = NAN;
    must(hysteron_trial(m, xs[K], &y_trial, &tangent), "trial");
    must(hysteron_trial(m, xs[K], &y_trial2, NULL), "trial");
    report(memcmp(&y_trial, &ref[K], sizeof y_trial) == 0
               && memcmp(&y_trial2, &ref[K], sizeof y_trial) == 0 && isfinite(tangent),
           "trial gives the step's output (repeatably) and a finite tangent");
    hysteron_model_free(m);

    m = paper_after_k(xs);
    must(hysteron_trial(m, 2.4, NULL, NULL), "trial");
    must(hysteron_trial(m, -1.9, NULL, NULL), "trial");
    report(continues(m, xs, ref, K), "trials that are not committed leave no trace");
    hysteron_model_free(m);

    /* Two trials at different inputs, then commit: the state is that of
     * the last one (a step there), not of the first. */
    m = paper_after_k(xs);
    HysteronModel *r = paper_after_k(xs);
    must(hysteron_trial(m, 2.4, NULL, NULL), "trial");
    must(hysteron_trial(m, xs[K], NULL, NULL), "trial");
    must(hysteron_commit(m), "commit");
    report(continues(m, xs, ref, K + 1), "commit keeps the last of two trials");
    must(hysteron_step(r, 2.4, NULL), "step");
    report(!continues(r, xs, ref, K + 1),
           "control: committing the first trial instead would leave a trace");
    hysteron_model_free(r);
    hysteron_model_free(m);

    m = paper(1.5);
    must(hysteron_commit(m), "commit");
    run(m, xs, ys, K);
    must(hysteron_commit(m), "commit");
    must(hysteron_commit(m), "commit");
    report(continues(m, xs, ref, K), "commit without a pending trial does nothing");
    hysteron_model_free(m);

    m = paper_after_k(xs);
    must(hysteron_trial(m, 2.4, NULL, NULL), "trial");
    expect_error(hysteron_trial(m, NAN, NULL, NULL), HYSTERON_STATUS_INPUT, "NaN",
                 "trial(NaN) is HYSTERON_STATUS_INPUT");
    must(hysteron_commit(m), "commit");
    report(continues(m, xs, ref, K), "a failed trial drops the pending one: commit does nothing");
    hysteron_model_free(m);

    /* --- reset and clone -------------------------------------------- */
    m = paper_after_k(xs);
    must(hysteron_trial(m, 2.4, NULL, NULL), "trial");
    must(hysteron_reset(m), "reset");
    must(hysteron_commit(m), "commit");
    report(continues(m, xs, ref, 0), "reset returns to the initial outputs (and drops a trial)");
    must(hysteron_reset(m), "reset");
    report(continues(m, xs, ref, 0), "reset again: the same outputs");
    hysteron_model_free(m);

    m = paper_after_k(xs);
    HysteronModel *c = NULL;
    must(hysteron_model_clone(m, &c), "clone");
    hysteron_model_free(m);
    report(c != NULL && continues(c, xs, ref, K),
           "a clone starts in the original's state and outlives it");
    hysteron_model_free(c);

    m = paper_after_k(xs);
    must(hysteron_model_clone(m, &c), "clone");
    for (int i = 0; i < K; i++) {
        must(hysteron_step(c, -xs[i], NULL), "step");
    }
    must(hysteron_set_param(c, "left.mms.f_c", 2.0), "set_param");
    report(continues(m, xs, ref, K), "a clone is independent: advancing it leaves the original");
    hysteron_model_free(c);
    hysteron_model_free(m);

    /* --- parameters ------------------------------------------------- */
    m = paper(1.5);
    size_t count = 0;
    must(hysteron_param_count(m, &count), "param_count");
    bool names_ok = count > 0, found = false;
    for (size_t i = 0; i < count; i++) {
        const char *name = NULL;
        double v = NAN;
        names_ok = names_ok && hysteron_param_name(m, i, &name) == HYSTERON_STATUS_OK
                   && name != NULL && hysteron_get_param(m, name, &v) == HYSTERON_STATUS_OK
                   && isfinite(v);
        found = found || (name != NULL && strcmp(name, "left.mms.f_c") == 0);
    }
    printf("#   the paper model has %zu parameters\n", count);
    report(names_ok && found,
           "every parameter name reads back by get_param; left.mms.f_c is one of them");

    double f_c = NAN, f_c_suffix = NAN;
    must(hysteron_get_param(m, "left.mms.f_c", &f_c), "get_param");
    must(hysteron_get_param(m, "f_c", &f_c_suffix), "get_param");
    report(f_c == 1.5 && f_c_suffix == 1.5, "get_param by path and by unique suffix: f_c = 1.5");

    run(m, xs, ys, K); /* set_param restarts from the initial state */
    must(hysteron_set_param(m, "left.mms.f_c", 2.0), "set_param");
    must(hysteron_get_param(m, "left.mms.f_c", &f_c), "get_param");
    report(f_c == 2.0, "set_param then get_param: f_c = 2");
    HysteronModel *built = paper(2.0);
    static double ref2[N];
    run(built, xs, ref2, N);
    run(m, xs, ys, N);
    report(same_bits(ys, ref2, N) && !same_bits(ref2, ref, N),
           "after set_param the outputs are those of the spec with f_c = 2, from the start");
    hysteron_model_free(built);
    hysteron_model_free(m);

    /* --- error paths: building -------------------------------------- */
    static double sentinel;
    HysteronModel *out = (HysteronModel *)(void *)&sentinel;
    expect_error(hysteron_model_from_json(NULL, &out), HYSTERON_STATUS_NULL_ARGUMENT, "json",
                 "from_json(NULL json) is NULL_ARGUMENT naming json");
    report(out == NULL, "... and sets *out to NULL");
    expect_error(hysteron_model_from_json("{\"type\": \"play\", \"r\": 0.5}", NULL),
                 HYSTERON_STATUS_NULL_ARGUMENT, "out",
                 "from_json(json, NULL out) is NULL_ARGUMENT naming out");
    out = (HysteronModel *)(void *)&sentinel;
    expect_error(hysteron_model_from_json("{\"type\": \"play\", ", &out), HYSTERON_STATUS_SPEC,
                 "EOF", "malformed JSON is SPEC (message: EOF while parsing)");
    report(out == NULL, "... and sets *out to NULL");
    expect_error(hysteron_model_from_json("{\"type\": \"nothing\"}", &out),
                 HYSTERON_STATUS_SPEC, "nothing", "an unknown type is SPEC naming it");
    expect_error(hysteron_model_from_json("{\"type\": \"play\", \"r\": \"x\"}", &out),
                 HYSTERON_STATUS_SPEC, "expected f64", "a field of the wrong type is SPEC");
    expect_error(hysteron_model_from_json("{\"type\":\"play\",\"r\":-1}", &out),
                 HYSTERON_STATUS_PARAMETER, "play.r",
                 "{\"type\":\"play\",\"r\":-1} is PARAMETER naming r");
    expect_error(hysteron_model_from_json("{\"type\": \"pl\xff\"}", &out),
                 HYSTERON_STATUS_INVALID_UTF8, "UTF-8", "JSON that is not UTF-8 is INVALID_UTF8");

    /* --- error paths: running --------------------------------------- */
    m = paper_after_k(xs);
    expect_error(hysteron_step(m, NAN, NULL), HYSTERON_STATUS_INPUT, "input sample NaN",
                 "step(NaN) is INPUT naming the sample");
    expect_error(hysteron_step(m, -INFINITY, NULL), HYSTERON_STATUS_INPUT, "input sample -inf",
                 "step(-inf) is INPUT naming the sample");
    report(continues(m, xs, ref, K), "... and the state is unchanged");
    hysteron_model_free(m);

    m = paper(1.5);
    double bad[10];
    memcpy(bad, xs, sizeof bad);
    bad[5] = NAN;
    expect_error(hysteron_process(m, bad, ys, 10), HYSTERON_STATUS_INPUT, "sample 5",
                 "NaN at index 5 of a process buffer is INPUT naming sample 5");
    report(same_bits(ys, ref, 5) && continues(m, xs, ref, 5),
           "... the samples before it are committed, not the rest");
    hysteron_model_free(m);

    m = paper(1.5);
    expect_error(hysteron_process(m, NULL, ys, 3), HYSTERON_STATUS_NULL_ARGUMENT, "xs",
                 "process with NULL xs is NULL_ARGUMENT");
    report(hysteron_process(m, NULL, NULL, 0) == HYSTERON_STATUS_OK,
           "process of 0 samples accepts NULL buffers");

    /* --- error paths: parameters ------------------------------------ */
    run(m, xs, ys, K);
    expect_error(hysteron_get_param(m, "no_such_param", NULL), HYSTERON_STATUS_PARAMETER,
                 "no_such_param", "get_param of an unknown name is PARAMETER naming it");
    expect_error(hysteron_set_param(m, "no_such_param", 1.0), HYSTERON_STATUS_PARAMETER,
                 "no_such_param", "set_param of an unknown name is PARAMETER naming it");
    expect_error(hysteron_set_param(m, "right.bouc_wen.z0", 0.1), HYSTERON_STATUS_PARAMETER,
                 "right.bouc_wen.z0", "setting the tied right.bouc_wen.z0 alone is PARAMETER");
    expect_error(hysteron_set_param(m, "left.mms.f_c", -1.0), HYSTERON_STATUS_PARAMETER,
                 "f_c", "set_param(f_c = -1) is PARAMETER naming f_c");
    expect_error(hysteron_set_param(m, "left.mms.f_c", NAN), HYSTERON_STATUS_PARAMETER, "f_c",
                 "set_param(f_c = NaN) is PARAMETER naming f_c");
    double z0 = NAN;
    must(hysteron_get_param(m, "right.bouc_wen.z0", &z0), "get_param");
    must(hysteron_get_param(m, "left.mms.f_c", &f_c), "get_param");
    report(z0 == 0.0 && f_c == 1.5 && continues(m, xs, ref, K),
           "... refused set_param calls change nothing (values, state)");
    const char *name = NULL;
    expect_error(hysteron_param_name(m, count, &name), HYSTERON_STATUS_OUT_OF_RANGE,
                 "index 24", "param_name(count) is OUT_OF_RANGE naming the index");
    expect_error(hysteron_get_param(m, NULL, &f_c), HYSTERON_STATUS_NULL_ARGUMENT, "name",
                 "get_param(NULL name) is NULL_ARGUMENT");
    expect_error(hysteron_set_param(m, NULL, 1.0), HYSTERON_STATUS_NULL_ARGUMENT, "name",
                 "set_param(NULL name) is NULL_ARGUMENT");

    /* --- sample period ---------------------------------------------- */
    /* A dt outside its domain is reported like a parameter (the library
     * checks it as the parameter `dt`), also by rate-independent models. */
    expect_error(hysteron_set_sample_period(m, 0.0), HYSTERON_STATUS_PARAMETER, "dt",
                 "set_sample_period(0) is PARAMETER naming dt");
    expect_error(hysteron_set_sample_period(m, -1e-3), HYSTERON_STATUS_PARAMETER, "dt",
                 "set_sample_period(-1e-3) is PARAMETER naming dt");
    /* The header lists a non-finite sample period under
     * HYSTERON_STATUS_INPUT, the library returns PARAMETER: either is
     * accepted here, as a refusal naming dt. */
    HysteronStatus nan_dt = hysteron_set_sample_period(m, NAN);
    report((nan_dt == HYSTERON_STATUS_INPUT || nan_dt == HYSTERON_STATUS_PARAMETER)
               && strstr(hysteron_last_error(), "dt") != NULL,
           "set_sample_period(NaN) is refused naming dt");
    must(hysteron_reset(m), "reset");
    must(hysteron_set_sample_period(m, 1e-3), "set_sample_period");
    report(continues(m, xs, ref, 0), "the rate-independent paper model ignores a valid dt");
    double period = -1.0;
    must(hysteron_sample_period(m, &period), "sample_period");
    report(period == 0.0, "a rate-independent model's sample period is 0");
    hysteron_model_free(m);

    /* A spec may leave a rate-dependent node's period to the host: every
     * run is refused, naming the node, until the host gives it. */
    HysteronModel *damper = NULL;
    must(hysteron_model_from_json("{\"type\": \"viscous_damper\", \"c\": 2}", &damper),
         "a viscous damper without dt");
    double force = 0.0;
    expect_error(hysteron_step(damper, 0.1, &force), HYSTERON_STATUS_SPEC, "viscous_damper.dt",
                 "step without a period is SPEC naming the node");
    expect_error(hysteron_process(damper, xs, ys, N), HYSTERON_STATUS_SPEC, "viscous_damper.dt",
                 "process without a period is SPEC naming the node");
    expect_error(hysteron_sample_period(damper, &period), HYSTERON_STATUS_SPEC,
                 "sample period is not given", "sample_period without one is SPEC");
    must(hysteron_set_sample_period(damper, 0.5), "the host gives the period");
    must(hysteron_sample_period(damper, &period), "sample_period");
    report(period == 0.5, "the period given is the period reported");
    must(hysteron_step(damper, 0.1, &force), "step at the given period");
    report(force == 2.0 * 0.1 / 0.5, "F = c dx/dt at the given period");
    hysteron_model_free(damper);

    /* --- NULL model --------------------------------------------------- */
    HysteronModel *none = NULL;
    const char *nm = NULL;
    double v = 0.0;
    size_t n = 0;
    expect_error(hysteron_model_clone(none, &c), HYSTERON_STATUS_NULL_ARGUMENT, "model",
                 "clone(NULL) is NULL_ARGUMENT");
    expect_error(hysteron_step(none, 0.0, &v), HYSTERON_STATUS_NULL_ARGUMENT, "model",
                 "step(NULL) is NULL_ARGUMENT");
    expect_error(hysteron_trial(none, 0.0, &v, &v), HYSTERON_STATUS_NULL_ARGUMENT, "model",
                 "trial(NULL) is NULL_ARGUMENT");
    expect_error(hysteron_commit(none), HYSTERON_STATUS_NULL_ARGUMENT, "model",
                 "commit(NULL) is NULL_ARGUMENT");
    expect_error(hysteron_reset(none), HYSTERON_STATUS_NULL_ARGUMENT, "model",
                 "reset(NULL) is NULL_ARGUMENT");
    expect_error(hysteron_process(none, xs, ys, N), HYSTERON_STATUS_NULL_ARGUMENT, "model",
                 "process(NULL) is NULL_ARGUMENT");
    expect_error(hysteron_set_sample_period(none, 1e-3), HYSTERON_STATUS_NULL_ARGUMENT,
                 "model", "set_sample_period(NULL) is NULL_ARGUMENT");
    expect_error(hysteron_param_count(none, &n), HYSTERON_STATUS_NULL_ARGUMENT, "model",
                 "param_count(NULL) is NULL_ARGUMENT");
    expect_error(hysteron_param_name(none, 0, &nm), HYSTERON_STATUS_NULL_ARGUMENT, "model",
                 "param_name(NULL) is NULL_ARGUMENT");
    expect_error(hysteron_get_param(none, "f_c", &v), HYSTERON_STATUS_NULL_ARGUMENT, "model",
                 "get_param(NULL) is NULL_ARGUMENT");
    expect_error(hysteron_set_param(none, "f_c", 1.0), HYSTERON_STATUS_NULL_ARGUMENT, "model",
                 "set_param(NULL) is NULL_ARGUMENT");
    m = paper(1.5);
    expect_error(hysteron_model_clone(m, NULL), HYSTERON_STATUS_NULL_ARGUMENT, "out",
                 "clone(model, NULL out) is NULL_ARGUMENT naming out");
    hysteron_model_free(m);
    hysteron_model_free(NULL);
    report(true, "hysteron_model_free(NULL) is a no-op");

    /* --- the message ---------------------------------------------------- */
    (void)hysteron_reset(none);
    const char *before = hysteron_last_error();
    m = paper(1.5);
    must(hysteron_step(m, 0.1, NULL), "step");
    report(strcmp(before, "model: NULL") == 0 && strcmp(hysteron_last_error(), before) == 0,
           "a successful call keeps the last error message");
    hysteron_model_free(m);

    printf("# %d checks, %d failed\n", checks, failures);
    return failures == 0 ? 0 : 1;
}
