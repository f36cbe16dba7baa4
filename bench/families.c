/* The C -O3 reference of two of hysteron's ODE-integrated leaves, and of
 * the closed-form Bouc-Wen spring (n = 1) alone and in an ensemble, written
 * for this project: the same step as operators/src/bwbn.rs (with
 * energy_flow.rs) and operators/src/jiles_atherton.rs, on the same adaptive
 * Dormand-Prince 5(4) as operators/src/ode.rs (the same tableau, error
 * norm, step controller, side-by-side switching and tolerances), on the
 * input and parameters of the `bwbn` and `jiles_atherton` kernels of
 * `hysteron bench`. Prints one row per kernel in the format of the shared
 * C reference (kernel, Msamples/s, ns/sample median, checksum, run times).
 *
 * Build and run: bash bench/run_families.sh [N] [REPS] [KERNEL]
 * (KERNEL: only the rows whose label contains it, e.g. "Bouc-Wen").
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <float.h>

#define MAX_SUBSTEPS 100000
#define EPS DBL_EPSILON

typedef struct Law Law;
struct Law {
    int n;                                                 /* state size */
    void (*flow)(const Law *, const double *, int, double *);
    int (*side)(const Law *, const double *);
    double (*sw)(const Law *, const double *);
    void (*scale)(const Law *, const double *, double *);
    double snap, dir;
    const void *p;
};

/* out = y + h (sum_j c_j k_j) */
static inline void lin(int n, const double *y, int m, const double *c, double *const *k, double h, double *out) {
    for (int i = 0; i < n; i++) {
        double sum = 0.0;
        for (int j = 0; j < m; j++) sum = sum + c[j] * k[j][i];
        out[i] = y[i] + h * sum;
    }
}

/* integrates the law over the travel s from y (in place); 0 on success */
static int dopri5(const Law *L, double *y, double s, double rtol) {
    const int n = L->n;
    double travel = s;
    if (travel <= 0.0) return 0;
    double t = 0.0, h = travel;
    int on = L->side(L, y);
    double k1[4], k2[4], k3[4], k4[4], k5[4], k6[4], k7[4], tmp[4], y5[4], err[4], w[4], zero[4] = {0};
    L->flow(L, y, on, k1);
    for (int it = 0; it < MAX_SUBSTEPS; it++) {
        double remaining = travel - t;
        if (remaining <= travel * 4.0 * EPS) return 0;
        int last = h >= remaining;
        if (last) h = remaining;
        { double c[] = {1.0 / 5.0}; double *k[] = {k1}; lin(n, y, 1, c, k, h, tmp); L->flow(L, tmp, on, k2); }
        { double c[] = {3.0 / 40.0, 9.0 / 40.0}; double *k[] = {k1, k2}; lin(n, y, 2, c, k, h, tmp); L->flow(L, tmp, on, k3); }
        { double c[] = {44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0}; double *k[] = {k1, k2, k3}; lin(n, y, 3, c, k, h, tmp); L->flow(L, tmp, on, k4); }
        { double c[] = {19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0}; double *k[] = {k1, k2, k3, k4};
          lin(n, y, 4, c, k, h, tmp); L->flow(L, tmp, on, k5); }
        { double c[] = {9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0}; double *k[] = {k1, k2, k3, k4, k5};
          lin(n, y, 5, c, k, h, tmp); L->flow(L, tmp, on, k6); }
        { double c[] = {35.0 / 384.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0}; double *k[] = {k1, k3, k4, k5, k6};
          lin(n, y, 5, c, k, h, y5); }
        L->flow(L, y5, on, k7);
        { double c[] = {71.0 / 57600.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0};
          double *k[] = {k1, k3, k4, k5, k6, k7}; lin(n, zero, 6, c, k, h, err); }
        int finite = 1;
        for (int i = 0; i < n; i++) finite &= isfinite(y5[i]) && isfinite(err[i]);
        if (!finite && h <= travel * 4.0 * EPS) return 1;
        L->scale(L, y, w);
        double norm = 0.0;
        if (finite) {
            for (int i = 0; i < n; i++) { double e = fabs(err[i]) / fmax(w[i], DBL_MIN); if (e > norm) norm = e; }
        } else {
            norm = INFINITY;
        }
        double before = L->sw(L, y), after = L->sw(L, y5);
        if (norm <= rtol && fabs(before) > L->snap && (before < 0.0) != (after < 0.0) && after != 0.0) {
            double shorter = h * (before / (before - after)) * (1.0 - 1e-9);
            if (shorter > travel * 4.0 * EPS) { h = shorter; continue; }
        }
        if (norm <= rtol || (finite && h <= travel * 4.0 * EPS)) {
            memcpy(y, y5, sizeof(double) * n);
            t = last ? travel : t + h;
            if (last) return 0;
            int next = L->side(L, y);
            if (next == on) memcpy(k1, k7, sizeof k1); else L->flow(L, y, next, k1);
            on = next;
        }
        double factor = norm == 0.0 ? 5.0 : fmin(fmax(0.9 * pow(rtol / norm, 0.2), 0.2), 5.0);
        h *= factor;
    }
    return 2;
}

/* ---- BWBN on (z, e): energy_flow.rs and bwbn.rs ---- */
typedef struct { double alpha, k0, n, gamma, beta, a0, q, zeta_s, p, psi0, delta_psi, lam; } Bwbn;

static inline double power_on_side(int positive, double z, double n) {
    double size = positive ? z : -z;
    if (n == 1.0) return size;
    return size > 0.0 ? pow(size, n) : 0.0;
}

static inline double bwbn_rate(const Bwbn *b, double dir, int positive, double z, double e) {
    double psi = ((dir > 0.0) == positive) ? b->gamma + b->beta : b->gamma - b->beta;
    double zeta1 = b->zeta_s * (1.0 - exp(-b->p * e));
    double zeta2 = (b->psi0 + b->delta_psi * e) * (b->lam + zeta1);
    double bound = 1.0 / (b->beta + b->gamma);
    double z_u = b->n == 1.0 ? bound : pow(bound, 1.0 / b->n);
    double off = z * dir - b->q * z_u;
    double h = 1.0 - zeta1 * exp(-(off * off) / (zeta2 * zeta2));
    return h * (b->a0 - power_on_side(positive, z, b->n) * psi);
}

static inline int bwbn_side_at(const Bwbn *b, double dir, double z, double e, double snap) {
    if (fabs(z) > snap) return z > 0.0;
    return dir * bwbn_rate(b, dir, 1, z, e) > 0.0;
}

static double bwbn_zs;

static void bwbn_flow(const Law *L, const double *y, int positive, double *out) {
    const Bwbn *b = L->p;
    double hysteretic = (1.0 - b->alpha) * b->k0;
    out[0] = L->dir * bwbn_rate(b, L->dir, positive, y[0], y[1]);
    out[1] = L->dir * hysteretic * y[0];
}
static int bwbn_side(const Law *L, const double *y) { return bwbn_side_at(L->p, L->dir, y[0], y[1], L->snap); }
static double bwbn_switch(const Law *L, const double *y) { (void)L; return y[0]; }
static void bwbn_scale(const Law *L, const double *y, double *w) {
    const Bwbn *b = L->p;
    double energy_scale = fabs((1.0 - b->alpha) * b->k0);
    double z = fmax(fabs(y[0]), bwbn_zs);
    w[0] = z;
    w[1] = fmax(fabs(y[1]), energy_scale * z * bwbn_zs);
}

/* one sample: state (x, z, e) -> output and tangent */
static int bwbn_step(const Bwbn *b, double *x0, double *z, double *e, double x, double *out, double *tangent) {
    double hysteretic = (1.0 - b->alpha) * b->k0;
    double travel = x - *x0;
    double dir = travel < 0.0 ? -1.0 : 1.0;
    double zs = bwbn_zs, snap = 1e-8 * zs;
    if (travel != 0.0) {
        Law L = {2, bwbn_flow, bwbn_side, bwbn_switch, bwbn_scale, snap, dir, b};
        double y[2] = {*z, *e};
        if (dopri5(&L, y, fabs(travel), 1e-11)) return 1;
        *z = y[0]; *e = y[1];
    }
    double dz = bwbn_rate(b, dir, bwbn_side_at(b, dir, *z, *e, 0.0), *z, *e);
    *x0 = x;
    *out = b->alpha * b->k0 * x + hysteretic * *z;
    *tangent = b->alpha * b->k0 + hysteretic * dz;
    return 0;
}

/* ---- Jiles-Atherton on (H, M, M_irr): jiles_atherton.rs ---- */
typedef struct { double ms, a, k, c, alpha; } Ja;

static inline void langevin(double u, double *l, double *dl) {
    if (fabs(u) < 0.1) {
        double u2 = u * u;
        *l = u * (1.0 / 3.0 + u2 * (-1.0 / 45.0 + u2 * (2.0 / 945.0 + u2 * (-1.0 / 4725.0 + u2 * (2.0 / 93555.0)))));
        *dl = 1.0 / 3.0 + u2 * (-1.0 / 15.0 + u2 * (2.0 / 189.0 + u2 * (-1.0 / 675.0 + u2 * (2.0 / 10395.0))));
    } else {
        double s = sinh(u);
        *l = 1.0 / tanh(u) - 1.0 / u;
        *dl = 1.0 / (u * u) - 1.0 / (s * s);
    }
}

static inline void ja_anhysteretic(const Ja *p, double he, double *m_an, double *chi) {
    double l, dl;
    langevin(he / p->a, &l, &dl);
    *m_an = p->ms * l;
    *chi = p->ms / p->a * dl;
}

static inline double ja_lag(const Ja *p, double dir, const double *y) {
    double m_an, chi;
    ja_anhysteretic(p, y[0] + p->alpha * y[1], &m_an, &chi);
    return dir * (m_an - y[2]);
}

/* dM/dH and dM_irr/dH; 0 where 1 - alpha dM/dH_e <= 0 */
static inline int ja_slopes(const Ja *p, double dir, int moving, const double *y, double *dm, double *dm_irr) {
    double m_an, chi;
    ja_anhysteretic(p, y[0] + p->alpha * y[1], &m_an, &chi);
    double irr = moving ? dir * (m_an - y[2]) / p->k : 0.0;
    double dme = p->c * chi + (1.0 - p->c) * irr;
    double den = 1.0 - p->alpha * dme;
    if (!(den > 0.0)) return 0;
    *dm = dme / den;
    *dm_irr = irr / den;
    return 1;
}

static inline int ja_moving(const Ja *p, double dir, const double *y, double snap) {
    double lag = ja_lag(p, dir, y);
    return lag > 0.0 || fabs(lag) <= snap;
}

static double ja_h_scale;

static void ja_flow(const Law *L, const double *y, int moving, double *out) {
    double dm, dm_irr;
    if (ja_slopes(L->p, L->dir, moving, y, &dm, &dm_irr)) {
        out[0] = L->dir; out[1] = L->dir * dm; out[2] = L->dir * dm_irr;
    } else {
        out[0] = out[1] = out[2] = NAN;
    }
}
static int ja_side(const Law *L, const double *y) { return ja_moving(L->p, L->dir, y, L->snap); }
static double ja_switch(const Law *L, const double *y) { return ja_lag(L->p, L->dir, y); }
static void ja_scale(const Law *L, const double *y, double *w) {
    const Ja *p = L->p;
    (void)y;
    w[0] = ja_h_scale; w[1] = p->ms; w[2] = p->ms;
}

static int ja_step(const Ja *p, double *s, double x, double *out, double *tangent) {
    double travel = x - s[0];
    double dir = travel < 0.0 ? -1.0 : 1.0;
    double rtol = fmax(1e-11, 64.0 * EPS), snap = fmax(1e-9, 16.0 * EPS) * p->ms;
    if (travel != 0.0) {
        ja_h_scale = fmax(p->a, fabs(x));
        Law L = {3, ja_flow, ja_side, ja_switch, ja_scale, snap, dir, p};
        if (dopri5(&L, s, fabs(travel), rtol)) return 1;
    }
    double end[3] = {x, s[1], s[2]}, dm, dm_irr;
    if (!ja_slopes(p, dir, ja_moving(p, dir, end, 0.0), end, &dm, &dm_irr)) return 1;
    s[0] = x;
    *out = s[1];
    *tangent = dm;
    return 0;
}

/* ---- Bouc-Wen n = 1 (operators/src/bouc_wen, hysteretic_state.rs) ----
 * H = w S z + (1 - w) S h, dh/dz = alpha - |h| (beta sgn(dz h) + gamma),
 * every sample in closed form from its branch start (the last reversal):
 * the same branch terms as `StateEquation::branch` and the same pieces as
 * `Branch::at`. Constant stiffness S, z0 = h0 = 0 (the `bouc_wen n=1`
 * kernel: w = 0.1, alpha = 1, beta = 0.7, gamma = 0.3, S = 1). */
typedef struct { double w, alpha, beta, gamma, s; } Bw;
typedef struct { double g_a, f_a, c_a, fc_a, inf_a, s0, f_0, c_0, fc_0; int near; } BwBranch;

static double bw_side(const Bw *p, double g, double f) {
    return (g > 0.0 || (g == 0.0 && f > 0.0)) ? p->beta + p->gamma : p->beta - p->gamma;
}

static BwBranch bw_branch(const Bw *p, double g) {
    BwBranch b;
    double c = g < 0.0 ? p->gamma - p->beta : p->beta + p->gamma;
    b.g_a = g;
    b.f_a = p->alpha - fabs(g) * c;
    b.c_a = bw_side(p, g, b.f_a);
    b.s0 = INFINITY;
    if ((g > 0.0 && b.f_a < 0.0) || (g < 0.0 && b.f_a > 0.0)) {
        double s = b.c_a == 0.0 ? -g / b.f_a : -log1p(g * b.c_a / b.f_a) / b.c_a;
        if (isfinite(s)) b.s0 = s;
    }
    b.f_0 = p->alpha;
    b.c_0 = bw_side(p, 0.0, p->alpha);
    b.near = b.c_a != b.c_0 && fabs(b.c_a) * 16.0 < fabs(b.c_0);
    b.fc_a = b.f_a / b.c_a;
    b.inf_a = g + b.f_a / b.c_a;
    b.fc_0 = p->alpha / b.c_0;
    return b;
}

static double bw_at(const BwBranch *b, double s) {
    if (b->s0 < s) {
        double t = s - b->s0;
        return b->c_0 == 0.0 ? b->f_0 * t : b->fc_0 - b->fc_0 * exp(-b->c_0 * t);
    }
    if (b->c_a == 0.0) return b->g_a + b->f_a * s;
    if (b->near) return b->g_a - b->fc_a * expm1(-b->c_a * s);
    return b->inf_a - b->fc_a * exp(-b->c_a * s);
}

/* One spring over x[0..n) into y, from z = h = 0 at rest. */
static void bw_run(const Bw *p, const double *x, double *y, size_t n, size_t stride) {
    double z = 0.0, h = 0.0, sign = 1.0, z_a = 0.0;
    int moving = 0;
    BwBranch b = bw_branch(p, 0.0);
    for (size_t i = 0; i < n; i++) {
        double dz = x[i] - z;
        if (dz != 0.0 || moving) {
            double d = dz > 0.0 ? 1.0 : dz < 0.0 ? -1.0 : sign;
            if (!moving || d != sign) {
                sign = d;
                moving = 1;
                z_a = z;
                b = bw_branch(p, sign * h);
            }
            z = x[i];
            h = sign * bw_at(&b, sign * (z - z_a));
        }
        y[i * stride] = p->w * p->s * z + (1.0 - p->w) * p->s * h;
    }
}

static volatile double BW_VALUES[5] = {0.1, 1.0, 0.7, 0.3, 1.0};
#define BW_ENSEMBLE 64

static Bw bw_params(double beta_scale) {
    return (Bw){BW_VALUES[0], BW_VALUES[1], BW_VALUES[2] * beta_scale, BW_VALUES[3], BW_VALUES[4]};
}

static double run_bw(const double *x, double *y, size_t n) {
    Bw p = bw_params(1.0);
    bw_run(&p, x, y, n, 1);
    double cs = 0.0;
    for (size_t i = 0; i < n; i++) cs += y[i];
    return cs;
}

/* The ensemble of `hysteron bench`'s `ensemble bouc_wen n=1`: 64 springs,
 * instance j with beta scaled by 0.5 + j/64, over the first n/64 samples,
 * one row of outputs per instance. Sample by sample, the 64 instances in
 * the inner loop (state and branch terms instance by instance, the
 * direction common: every instance starts at z0 = 0), so that the
 * compiler may vectorise across instances. */
static double run_bw_ensemble(const double *x, double *y, size_t n) {
    size_t t = n / BW_ENSEMBLE;
    Bw p[BW_ENSEMBLE];
    BwBranch b[BW_ENSEMBLE];
    double h[BW_ENSEMBLE];
    for (int j = 0; j < BW_ENSEMBLE; j++) {
        p[j] = bw_params(0.5 + (double)j / BW_ENSEMBLE);
        h[j] = 0.0;
    }
    double z = 0.0, sign = 1.0, z_a = 0.0;
    int moving = 0;
    for (size_t i = 0; i < t; i++) {
        double dz = x[i] - z;
        if (dz != 0.0 || moving) {
            double d = dz > 0.0 ? 1.0 : dz < 0.0 ? -1.0 : sign;
            if (!moving || d != sign) {
                sign = d;
                moving = 1;
                z_a = z;
                for (int j = 0; j < BW_ENSEMBLE; j++) b[j] = bw_branch(&p[j], sign * h[j]);
            }
            z = x[i];
            double s = sign * (z - z_a);
            for (int j = 0; j < BW_ENSEMBLE; j++) h[j] = sign * bw_at(&b[j], s);
        }
        for (int j = 0; j < BW_ENSEMBLE; j++)
            y[j * t + i] = p[j].w * p[j].s * z + (1.0 - p[j].w) * p[j].s * h[j];
    }
    double cs = 0.0;
    for (size_t i = 0; i < t * BW_ENSEMBLE; i++) cs += y[i];
    return cs;
}

/* ---- The Bouc-Wen benchmark system (examples/specs/boucwen-benchmark.json) ----
 * oversample(20, feedback(mass_spring_damper, bouc_wen)): m y'' + c y' + k y = u - H[y],
 * Newmark average acceleration (operators/src/mass_spring_damper.rs) at
 * dt = 1/15000, 20 sub-steps per sample on the input interpolated
 * linearly (composition/src/oversample.rs); the spring above with w = 0,
 * alpha = 5e4, beta = 800, gamma = -1100, S = 1. Each sub-step solves
 * R(y) = y - MSD(u - H(y)) = 0 (composition/src/feedback.rs) by Newton steps
 * from the cubic prediction 4 (y + y2) - 6 y1 - y3, stopping where
 * |r/d| <= 16 eps |y| + DBL_MIN or r = 0: the path the library's solver
 * takes at nearly every sub-step (where it would bracket or stall, this
 * loop takes plain Newton steps on: the checksums agree to about 1e-10). */
typedef struct { double m, c, k, dt, q, q2, k_eff; Bw bw; } Sys;
typedef struct { double y, v, a; } Msd;
typedef struct {
    Msd msd;
    double z, h, sign, z_a;
    int moving;
    BwBranch b;
    double out, before[3];
} SysState;

static Sys sys_params(double beta_scale) {
    Sys p = {2.0, 10.0, 5e4, 1.0 / 15000.0, 0, 0, 0, {0.0, 5e4, 800.0 * beta_scale, -1100.0, 1.0}};
    p.q = 2.0 / p.dt;
    p.q2 = p.q * p.q;
    p.k_eff = p.k + p.q * p.c + p.q2 * p.m;
    return p;
}

/* One evaluation of R at y: the spring's trial (a reversal starts a branch at
 * the committed state), the oscillator's; the trial states in *t. */
static void sys_eval(const Sys *p, const SysState *s, double u, double y, double *r, double *d, SysState *t) {
    *t = *s;
    double dz = y - s->z;
    double sign = dz > 0.0 ? 1.0 : dz < 0.0 ? -1.0 : (s->moving ? s->sign : 0.0);
    double h;
    if (s->moving && sign == s->sign) {
        h = sign * bw_at(&s->b, sign * (y - s->z_a));
        t->z = y;
    } else if (sign == 0.0) {
        h = s->h;
        sign = 1.0;
    } else {
        t->b = bw_branch(&p->bw, sign * s->h);
        t->z_a = s->z;
        t->moving = 1;
        h = sign * bw_at(&t->b, sign * (y - s->z));
        t->z = y;
    }
    t->h = h;
    t->sign = sign;
    const Bw *b = &p->bw;
    double force = b->w * b->s * y + (1.0 - b->w) * b->s * h;
    double g = sign * h, cg = g < 0.0 ? b->gamma - b->beta : b->beta + b->gamma;
    double tb = b->w * b->s + (1.0 - b->w) * (b->s * (b->alpha - fabs(g) * cg));
    double f = u - force, yv = s->msd.y, v = s->msd.v, a = s->msd.a, two_v = v + v;
    double y1 = (f + p->m * (p->q2 * yv + p->q * two_v + a) + p->c * (p->q * yv + v)) / p->k_eff;
    double a1 = p->q2 * (y1 - yv) - p->q * two_v - a;
    t->msd = (Msd){y1, v + p->dt * 0.5 * (a + a1), a1};
    *r = y - y1;
    *d = 1.0 + tb / p->k_eff;
}

static void sys_substep(const Sys *p, SysState *s, double u) {
    double y = 4.0 * (s->out + s->before[1]) - 6.0 * s->before[0] - s->before[2], r, d;
    SysState t;
    sys_eval(p, s, u, y, &r, &d, &t);
    for (int it = 0; it < 100 && r != 0.0; it++) {
        double step = r / d;
        if (fabs(step) <= 16.0 * EPS * fabs(y) + DBL_MIN) break;
        y -= step;
        sys_eval(p, s, u, y, &r, &d, &t);
    }
    t.before[2] = s->before[1];
    t.before[1] = s->before[0];
    t.before[0] = s->out;
    t.out = y;
    *s = t;
}

/* One sample: 20 sub-steps from the committed input *x0 to x. */
static double sys_sample(const Sys *p, SysState *s, double x0, double x) {
    for (int i = 1; i <= 20; i++) sys_substep(p, s, i == 20 ? x : x0 + (x - x0) * (i / 20.0));
    return s->out;
}

static volatile double SYS_FORCE = 20.0;

/* The `bouc_wen system` kernel: one system over the force 20 x of the first
 * n/64 samples (ns per sample of those). */
static double run_sys(const double *x, double *y, size_t n) {
    size_t t = n / BW_ENSEMBLE;
    Sys p = sys_params(1.0);
    SysState s;
    memset(&s, 0, sizeof s);
    double x0 = 0.0;
    for (size_t i = 0; i < t; i++) {
        double u = SYS_FORCE * x[i];
        y[i] = sys_sample(&p, &s, x0, u);
        x0 = u;
    }
    double cs = 0.0;
    for (size_t i = 0; i < t; i++) cs += y[i];
    return cs;
}

/* The `ensemble bouc_wen system` kernel: 64 systems, instance j with beta
 * scaled by 0.5 + j/64, over the same samples, sample by sample with the
 * instances in the inner loop, one row of outputs per instance. */
static double run_sys_ensemble(const double *x, double *y, size_t n) {
    size_t t = n / BW_ENSEMBLE;
    static Sys p[BW_ENSEMBLE];
    static SysState s[BW_ENSEMBLE];
    for (int j = 0; j < BW_ENSEMBLE; j++) {
        p[j] = sys_params(0.5 + (double)j / BW_ENSEMBLE);
        memset(&s[j], 0, sizeof s[j]);
    }
    double x0 = 0.0;
    for (size_t i = 0; i < t; i++) {
        double u = SYS_FORCE * x[i];
        for (int j = 0; j < BW_ENSEMBLE; j++) y[j * t + i] = sys_sample(&p[j], &s[j], x0, u);
        x0 = u;
    }
    double cs = 0.0;
    for (size_t i = 0; i < t * BW_ENSEMBLE; i++) cs += y[i];
    return cs;
}

/* ---- timing ---- */
static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int cmp(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The parameters, read at run time (as hysteron reads them), so that the
 * compiler cannot fold them into the code. */
static volatile double BWBN_VALUES[12] = {0.1, 10.0, 1.0, 0.5, 0.5, 1.0, 0.25, 0.9, 1.0, 0.2, 0.005, 0.5};
static volatile double JA_VALUES[5] = {1.0, 0.3, 0.5, 0.2, 0.1};
static Bwbn BWBN;
static Ja JA;

static double run_bwbn(const double *x, double *y, size_t n) {
    double x0 = 0.0, z = 0.0, e = 0.0, t;
    for (size_t i = 0; i < n; i++)
        if (bwbn_step(&BWBN, &x0, &z, &e, x[i], &y[i], &t)) { fprintf(stderr, "bwbn failed at %zu\n", i); exit(1); }
    double cs = 0.0;
    for (size_t i = 0; i < n; i++) cs += y[i];
    return cs;
}

static double run_ja(const double *x, double *y, size_t n) {
    double s[3] = {0.0, 0.0, 0.0}, t;
    for (size_t i = 0; i < n; i++)
        if (ja_step(&JA, s, x[i], &y[i], &t)) { fprintf(stderr, "jiles_atherton failed at %zu\n", i); exit(1); }
    double cs = 0.0;
    for (size_t i = 0; i < n; i++) cs += y[i];
    return cs;
}

int main(int argc, char **argv) {
    size_t n = argc > 1 ? strtoull(argv[1], NULL, 10) : 10000000;
    int reps = argc > 2 ? atoi(argv[2]) : 5;
    const char *only = argc > 3 ? argv[3] : "";
    if (n == 0 || reps < 1 || reps > 1000) { fprintf(stderr, "usage: families [N] [REPS] [KERNEL]\n"); return 2; }
    double *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y), ts[1000];
    if (!x || !y) return 1;
    for (size_t i = 0; i < n; i++) x[i] = 2.5 * sin(2 * M_PI * i / 2000.0) + 0.3 * sin(2 * M_PI * i / 97.3);
    BWBN = (Bwbn){BWBN_VALUES[0], BWBN_VALUES[1], BWBN_VALUES[2], BWBN_VALUES[3], BWBN_VALUES[4], BWBN_VALUES[5],
                  BWBN_VALUES[6], BWBN_VALUES[7], BWBN_VALUES[8], BWBN_VALUES[9], BWBN_VALUES[10], BWBN_VALUES[11]};
    JA = (Ja){JA_VALUES[0], JA_VALUES[1], JA_VALUES[2], JA_VALUES[3], JA_VALUES[4]};
    bwbn_zs = pow(BWBN.a0 / (BWBN.beta + BWBN.gamma), 1.0 / BWBN.n);
#ifdef __FAST_MATH__
    const char *mode = "-O3 -ffast-math";
#else
    const char *mode = "-O3";
#endif
    printf("families.c  gcc %s  [%s]  N=%zu  reps=%d\n", __VERSION__, mode, n, reps);
    printf("%-30s %11s %10s %22s  runs (s)\n", "kernel", "Msamples/s", "ns/sample", "checksum");
    /* (`part`: the kernel runs over the first n/64 samples, and its time is per
     * sample of those) */
    struct { const char *label; double (*run)(const double *, double *, size_t); int part; } k[] = {
        {"BWBN (DP5)", run_bwbn, 0}, {"Jiles-Atherton (DP5)", run_ja, 0},
        {"Bouc-Wen n=1", run_bw, 0}, {"Bouc-Wen n=1 ensemble x64", run_bw_ensemble, 0},
        {"Bouc-Wen system", run_sys, 1}, {"Bouc-Wen system ensemble x64", run_sys_ensemble, 0}};
    for (int j = 0; j < 6; j++) {
        size_t count = k[j].part ? n / BW_ENSEMBLE : n;
        if (!strstr(k[j].label, only)) continue;
        double cs = k[j].run(x, y, n); /* untimed */
        for (int rep = 0; rep < reps; rep++) {
            double t0 = now();
            cs = k[j].run(x, y, n);
            ts[rep] = now() - t0;
        }
        double sorted[1000];
        memcpy(sorted, ts, reps * sizeof(double));
        qsort(sorted, reps, sizeof(double), cmp);
        double med = reps % 2 ? sorted[reps / 2] : 0.5 * (sorted[reps / 2 - 1] + sorted[reps / 2]);
        printf("%-30s %11.1f %10.3f %22.10e  ", k[j].label, count / med / 1e6, med / count * 1e9, cs);
        for (int rep = 0; rep < reps; rep++) printf("%.4f ", ts[rep]);
        printf("\n");
    }
    free(x);
    free(y);
    return 0;
}
