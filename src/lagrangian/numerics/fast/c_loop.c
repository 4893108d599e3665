/*
 * SciPy's RK45 and DOP853, step for step, and the classical fixed-step RK4, in C: the
 * integration loop of lagrangian.simulate and lagrangian.simulate_batch.
 *
 * Compiled once per machine by the system C compiler and kept on disk
 * (lagrangian/numerics/fast/c_build.py), loaded with ctypes and driven by
 * lagrangian/numerics/fast/c_loop.py.  It is SciPy's RungeKutta solver operation for
 * operation, so it takes the same steps and agrees with scipy.integrate.solve_ivp to rounding:
 *
 *   - the right-hand side of every system is one C function
 *         void f(double *out, const double *in, void *user_data)
 *     (SymEngine's LLVM backend, lagrangian/numerics/fast/native.py) of in = [t, x, p], giving
 *     out = [matrix row by row, vector] of the state equations matrix z = vector, solved here
 *     by Gaussian elimination with partial pivoting (lagrangian/numerics/fast/linear.py) and
 *     assembled as dx/dt = [q_dot; q_ddot_S] (lagrangian/numerics/fast/compiled_rates.py);
 *   - the initial step of Hairer, Norsett & Wanner (Solving ODEs I, II.4), SciPy's error norms
 *     and step control (accept when err < 1: h <- h min(10, 0.9 err^(-1/(k+1))), at most h
 *     after a rejection; reject: h <- h max(0.2, 0.9 err^(-1/(k+1))));
 *   - RK4 (lagrangian/simulation/integrators/rk4.py): n_fixed steps of h = (t1 - t0) / n_fixed,
 *     step i landing exactly on t0 + i h (the last on t1), no error control, the cubic Hermite
 *     interpolant of x and dx/dt at both ends of a step as its dense output;
 *   - output at the requested times from each step's dense output, or every step;
 *   - the budget of lagrangian/simulation/integrators/budget.py after every accepted step: accepted steps,
 *     wall time, stiffness (h |lambda| near the edge of the stability region for most of the
 *     last steps, Hairer & Wanner, Solving ODEs II, IV.2) and a collapsed step size.
 *
 * The caller owns every buffer (struct lg_run).  lg_start begins a run, lg_advance continues
 * it until it ends, or returns LG_RUNNING after max_call accepted steps or at the clock time
 * chunk_end (so the caller can report progress and see Ctrl-C), or LG_FULL when the
 * every-step output needs more room, or LG_EVENTS_FULL when the event records do.  Status
 * codes 0-8 are those of lagrangian/numerics/status.py (LG_STOPPED: a terminal event).
 *
 * Events (lagrangian/simulation/integrators/events.py, as solve_ivp): the event functions are one more C
 * function g(t, x); after every accepted step a sign change of g_i in its direction is a
 * zero, located on the step's dense output by SciPy's brentq (xtol = rtol = 4 eps), the zeros
 * of one step recorded in the order of time, and the run ends at the zero that completes an
 * event's terminal count.
 */

#include <math.h>
#include <stdint.h>
#include <string.h>
#ifdef _WIN32
#include <windows.h>
#else
#include <time.h>
#endif

#define LG_ABI_VERSION 3

enum {
    LG_FINISHED = 0,
    LG_STOPPED = 1,
    LG_STEP_TOO_SMALL = 2,
    LG_NOT_FINITE = 3,
    LG_SINGULAR = 4,
    LG_STEP_BUDGET = 5,
    LG_WALL_TIME = 6,
    LG_STIFF = 7,
    LG_COLLAPSED = 8,
    LG_RUNNING = -1,
    LG_FULL = -2,
    LG_EVENTS_FULL = -3
};

#define SAFETY 0.9
#define MIN_FACTOR 0.2
#define MAX_FACTOR 10.0

typedef void (*lg_function)(double *out, const double *in, void *user_data);

/* One system: its C function and the buffers of one run (in = [t, x, p], p written once). */
typedef struct {
    lg_function function;
    void *user_data;
    double *inputs;        /* 1 + nx + len(p) */
    double *outputs;       /* (size + 1) * size: the matrix, then the vector (z on return) */
    const int64_t *second; /* n_second indices of the second-order coordinates */
    const int64_t *first;  /* n_first indices of the first-order coordinates */
    int64_t nx;
    int64_t size;
    int64_t n_second;
    int64_t n_first;
} lg_system;

/* A tableau of lagrangian/numerics/fast/tableaus.py; K has stages + 1 + extra rows. */
typedef struct {
    const double *A;       /* stages x stages */
    const double *B;       /* stages */
    const double *C;       /* stages */
    const double *E;       /* stages + 1: RK45's E, DOP853's E5 */
    const double *E3;      /* stages + 1 (DOP853) */
    const double *P;       /* (stages + 1) x p_cols (RK45's dense output) */
    const double *A_extra; /* extra x (stages + 1 + extra) (DOP853's extra stages) */
    const double *C_extra; /* extra */
    const double *D;       /* d_rows x (stages + 1 + extra) (DOP853's interpolation) */
    int64_t stages;
    int64_t extra;
    int64_t p_cols;
    int64_t d_rows;
    int64_t dop853;
    int64_t error_order;
    int64_t end_stage; /* j with C[j] = 1, for the stiffness estimate; -1: none */
    int64_t fixed;     /* 1: RK4's fixed steps and Hermite dense output (no E, P, D) */
} lg_tableau;

typedef struct {
    lg_system system;
    lg_tableau tableau;
    /* the run */
    double t0, t1, rtol, atol, max_step;
    const double *t_out; /* the output times; n_out = 0: every step */
    int64_t n_out;
    int64_t n_fixed; /* the fixed method's number of steps over [t0, t1] */
    /* the budget (budget.py): 0 or infinite turns a check off */
    int64_t max_steps;
    double deadline; /* lg_clock() time the wall-time budget ends */
    double stiff_edge, stiff_near, stiff_share, stiff_steps_left;
    int64_t window;
    int64_t collapse_steps;
    double collapse;
    /* buffers */
    double *out_t;   /* capacity (every step) */
    double *out_x;   /* capacity x nx, or n_out x nx */
    int64_t capacity;
    double *y, *f, *y_old, *y_new; /* nx each */
    double *K;                     /* (stages + 1 + extra) x nx */
    double *F;                     /* interpolant rows x nx */
    double *work;                  /* 3 nx */
    int64_t *recent;               /* window */
    double *times;                 /* collapse_steps */
    /* progress, read by the caller */
    int64_t rows, steps, recent_count, recent_sum, times_count;
    double t, h_abs, h_last, stiff_since, advanced;
    /* events (n_events = 0: none): g = event_function(in = [t, x, p]), n_events values */
    lg_function event_function;
    void *event_user_data;
    double *event_inputs;     /* 1 + nx + len(p), p written once */
    double *event_old;        /* n_events: g at the start of the step */
    double *event_new;        /* n_events: g at its end */
    double *event_work;       /* n_events: g inside the step */
    double *event_state;      /* nx: the interpolated state inside the step */
    const double *directions; /* n_events: > 0 rising zeros only, < 0 falling, 0 both */
    const double *limits;     /* n_events: zeros that end the run (inf: never) */
    int64_t *counts;          /* n_events: zeros so far */
    double *roots;            /* n_events: scratch */
    int64_t *order;           /* n_events: scratch */
    int64_t n_events;
    int64_t *found_index;     /* event_capacity: which event */
    double *found_t;          /* event_capacity: when */
    double *found_x;          /* event_capacity x nx: the state then */
    int64_t event_capacity, n_found;
} lg_run;

/* ------------------------------------------------------------------ helpers */

static double py_min(double a, double b) { return b < a ? b : a; } /* Python's min(a, b) */
static double py_max(double a, double b) { return b > a ? b : a; } /* Python's max(a, b) */

double lg_clock(void) {
#ifdef _WIN32
    LARGE_INTEGER count, frequency;
    QueryPerformanceCounter(&count);
    QueryPerformanceFrequency(&frequency);
    return (double)count.QuadPart / (double)frequency.QuadPart;
#else
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    return (double)now.tv_sec + 1e-9 * (double)now.tv_nsec;
#endif
}

int64_t lg_abi(void) { return LG_ABI_VERSION; }

/* sizeof of the structures, checked against the ctypes mirrors before the first call. */
int64_t lg_layout(int64_t which) {
    switch (which) {
    case 0:
        return (int64_t)sizeof(lg_system);
    case 1:
        return (int64_t)sizeof(lg_tableau);
    default:
        return (int64_t)sizeof(lg_run);
    }
}

static void put(double *target, const double *values, int64_t n) {
    memcpy(target, values, (size_t)n * sizeof(double));
}

static int all_finite(const double *values, int64_t n) {
    for (int64_t i = 0; i < n; i++)
        if (!isfinite(values[i]))
            return 0;
    return 1;
}

/* matrix z = vector by Gaussian elimination with partial pivoting, in place (vector <- z);
   0 when a pivot is exactly zero (Golub & Van Loan, Matrix Computations, 3.4). */
static int solve_linear(double *m, double *v, int64_t n) {
    for (int64_t k = 0; k < n; k++) {
        int64_t pivot = k;
        double largest = fabs(m[k * n + k]);
        for (int64_t i = k + 1; i < n; i++) {
            if (fabs(m[i * n + k]) > largest) {
                pivot = i;
                largest = fabs(m[i * n + k]);
            }
        }
        if (largest == 0.0)
            return 0;
        if (pivot != k) {
            for (int64_t j = k; j < n; j++) {
                double swap = m[k * n + j];
                m[k * n + j] = m[pivot * n + j];
                m[pivot * n + j] = swap;
            }
            double swap = v[k];
            v[k] = v[pivot];
            v[pivot] = swap;
        }
        for (int64_t i = k + 1; i < n; i++) {
            double factor = m[i * n + k] / m[k * n + k];
            for (int64_t j = k + 1; j < n; j++)
                m[i * n + j] -= factor * m[k * n + j];
            v[i] -= factor * v[k];
        }
    }
    for (int64_t i = n - 1; i >= 0; i--) {
        double total = v[i];
        for (int64_t j = i + 1; j < n; j++)
            total -= m[i * n + j] * v[j];
        v[i] = total / m[i * n + i];
    }
    return 1;
}

/* dx/dt at (t, x) into dx; 0 when the matrix is singular (its (t, x) stay in inputs). */
static int state_rates(const lg_system *s, double t, const double *x, double *dx) {
    double *in = s->inputs, *matrix = s->outputs, *z = s->outputs + s->size * s->size;
    int64_t n2 = s->n_second, n = s->n_second + s->n_first;
    in[0] = t;
    for (int64_t i = 0; i < s->nx; i++)
        in[1 + i] = x[i];
    s->function(matrix, in, s->user_data);
    if (!solve_linear(matrix, z, s->size))
        return 0;
    for (int64_t k = 0; k < n2; k++) {
        dx[s->second[k]] = x[n + k];
        dx[n + k] = z[k];
    }
    for (int64_t k = 0; k < s->n_first; k++)
        dx[s->first[k]] = z[n2 + k];
    return 1;
}

/* ------------------------------------------------------------------ one step */

/* sqrt(mean((values / (atol + rtol |y|))^2)), SciPy's norm for the initial step. */
static double scaled_rms(const double *values, const double *y, int64_t n, double rtol,
                         double atol) {
    double total = 0.0;
    for (int64_t i = 0; i < n; i++) {
        double scaled = values[i] / (atol + fabs(y[i]) * rtol);
        total += scaled * scaled;
    }
    return sqrt(total / (double)n);
}

/* SciPy's select_initial_step; -1 when the right-hand side fails. */
static double initial_step(lg_run *r) {
    const lg_system *s = &r->system;
    int64_t n = s->nx;
    double *y1 = r->work, *f1 = r->work + n;
    double interval = fabs(r->t1 - r->t);
    double d0 = scaled_rms(r->y, r->y, n, r->rtol, r->atol);
    double d1 = scaled_rms(r->f, r->y, n, r->rtol, r->atol);
    double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    h0 = py_min(h0, interval);
    for (int64_t i = 0; i < n; i++)
        y1[i] = r->y[i] + h0 * r->f[i];
    if (!state_rates(s, r->t + h0, y1, f1))
        return -1.0;
    for (int64_t i = 0; i < n; i++)
        f1[i] -= r->f[i];
    double d2 = scaled_rms(f1, r->y, n, r->rtol, r->atol) / h0;
    double h1;
    if (d1 <= 1e-15 && d2 <= 1e-15)
        h1 = py_max(1e-6, h0 * 1e-3);
    else
        h1 = pow(0.01 / py_max(d1, d2), 1.0 / (double)(r->tableau.error_order + 1));
    return py_min(py_min(py_min(100 * h0, h1), interval), r->max_step);
}

/* out = y + (sum_{j<s} a_j K_j) h, in solve_ivp's order of operations. */
static void stage_state(const double *K, const double *a, int64_t s, const double *y, double h,
                        double *out, int64_t n) {
    for (int64_t i = 0; i < n; i++) {
        double total = 0.0;
        for (int64_t j = 0; j < s; j++)
            total += K[j * n + i] * a[j];
        out[i] = y[i] + total * h;
    }
}

/* One trial step: stages K_1..K_{s-1}, y_new, and K_s = f(t + h, y_new). */
static int rk_step(lg_run *r, double t, double h) {
    const lg_tableau *tb = &r->tableau;
    const lg_system *s = &r->system;
    int64_t n = s->nx, stages = tb->stages;
    double *K = r->K, *stage = r->work;
    for (int64_t i = 1; i < stages; i++) {
        stage_state(K, tb->A + i * stages, i, r->y, h, stage, n);
        if (!state_rates(s, t + tb->C[i] * h, stage, K + i * n))
            return 0;
    }
    for (int64_t i = 0; i < n; i++) {
        double total = 0.0;
        for (int64_t j = 0; j < stages; j++)
            total += K[j * n + i] * tb->B[j];
        r->y_new[i] = r->y[i] + h * total;
    }
    return state_rates(s, t + h, r->y_new, K + stages * n);
}

/* RK45: rms(h K^T E / scale); DOP853: Hairer's estimate from E5 and E3; the scale is
   atol + rtol max(|y|, |y_new|). */
static double error_norm(lg_run *r, double h) {
    const lg_tableau *tb = &r->tableau;
    int64_t n = r->system.nx, rows = tb->stages + 1;
    double *scale = r->work + 2 * n;
    const double *K = r->K;
    for (int64_t i = 0; i < n; i++)
        scale[i] = r->atol + py_max(fabs(r->y[i]), fabs(r->y_new[i])) * r->rtol;
    if (!tb->dop853) {
        double total = 0.0;
        for (int64_t i = 0; i < n; i++) {
            double e = 0.0;
            for (int64_t j = 0; j < rows; j++)
                e += K[j * n + i] * tb->E[j];
            double scaled = e * h / scale[i];
            total += scaled * scaled;
        }
        return sqrt(total / (double)n);
    }
    double e5_squared = 0.0, e3_squared = 0.0;
    for (int64_t i = 0; i < n; i++) {
        double e5 = 0.0, e3 = 0.0;
        for (int64_t j = 0; j < rows; j++) {
            e5 += K[j * n + i] * tb->E[j];
            e3 += K[j * n + i] * tb->E3[j];
        }
        e5 /= scale[i];
        e3 /= scale[i];
        e5_squared += e5 * e5;
        e3_squared += e3 * e3;
    }
    if (e5_squared == 0.0 && e3_squared == 0.0)
        return 0.0;
    return fabs(h) * e5_squared / sqrt((e5_squared + 0.01 * e3_squared) * (double)n);
}

/* nextafter(t, inf) - t: one ulp above t, SciPy's spacing for the smallest step. */
static double spacing(double t) { return nextafter(t, INFINITY) - t; }

/* One accepted step of SciPy's RungeKutta._step_impl from (t, y) with f = f(t, y): the
   status, and *t_new, *h; K holds the stages, y_new the new state, h_abs the next step. */
static int adaptive_step(lg_run *r, double *t_new, double *h) {
    const lg_tableau *tb = &r->tableau;
    int64_t n = r->system.nx;
    double t = r->t;
    double exponent = -1.0 / (double)(tb->error_order + 1);
    double min_step = 10 * spacing(t);
    double h_abs = r->h_abs > min_step ? py_min(r->h_abs, r->max_step) : min_step;
    int rejected = 0;
    for (;;) {
        if (h_abs < min_step) {
            r->h_abs = h_abs;
            return LG_STEP_TOO_SMALL;
        }
        *t_new = py_min(t + h_abs, r->t1);
        *h = *t_new - t;
        h_abs = fabs(*h);
        put(r->K, r->f, n);
        if (!rk_step(r, t, *h)) {
            r->h_abs = h_abs;
            return LG_SINGULAR;
        }
        double err = error_norm(r, *h);
        if (err < 1) {
            double factor = err == 0 ? MAX_FACTOR : py_min(MAX_FACTOR, SAFETY * pow(err, exponent));
            if (rejected)
                factor = py_min(1.0, factor);
            r->h_abs = h_abs * factor;
            return LG_FINISHED;
        }
        double factor = SAFETY * pow(err, exponent);
        h_abs *= factor > MIN_FACTOR ? factor : MIN_FACTOR; /* a NaN error: shrink by 0.2 */
        rejected = 1;
    }
}

/* One step of the fixed-step method from (t, y) with f = f(t, y): step i = steps + 1 ends at
   t0 + i h exactly (counted, not summed, as rk4.py), the last at t1.  The status, *t_new and
   *h = *t_new - t, the span of the step's dense output (the stages use h itself). */
static int fixed_step(lg_run *r, double *t_new, double *h) {
    int64_t index = r->steps + 1;
    double h_fixed = (r->t1 - r->t0) / (double)r->n_fixed;
    *t_new = index >= r->n_fixed ? r->t1 : r->t0 + (double)index * h_fixed;
    *h = *t_new - r->t;
    put(r->K, r->f, r->system.nx);
    return rk_step(r, r->t, h_fixed) ? LG_FINISHED : LG_SINGULAR;
}

/* ------------------------------------------------------------------ dense output */

/* The interpolant of the last step (t_old, h): RK45's F = K^T P, or DOP853's F (three extra
   stages from y_old). */
static int dense_coefficients(lg_run *r, double t_old, double h) {
    const lg_tableau *tb = &r->tableau;
    int64_t n = r->system.nx, rows = tb->stages + 1, k_rows = tb->stages + 1 + tb->extra;
    double *K = r->K, *F = r->F;
    if (tb->fixed) /* the Hermite interpolant reads y_old, y, K_0 and f directly */
        return 1;
    if (!tb->dop853) {
        for (int64_t k = 0; k < tb->p_cols; k++) {
            for (int64_t i = 0; i < n; i++) {
                double total = 0.0;
                for (int64_t j = 0; j < rows; j++)
                    total += K[j * n + i] * tb->P[j * tb->p_cols + k];
                F[k * n + i] = total;
            }
        }
        return 1;
    }
    for (int64_t e = 0; e < tb->extra; e++) {
        int64_t s = rows + e;
        stage_state(K, tb->A_extra + e * k_rows, s, r->y_old, h, r->work, n);
        if (!state_rates(&r->system, t_old + tb->C_extra[e] * h, r->work, K + s * n))
            return 0;
    }
    for (int64_t i = 0; i < n; i++) {
        double delta = r->y[i] - r->y_old[i];
        F[i] = delta;
        F[n + i] = h * K[i] - delta;
        F[2 * n + i] = 2 * delta - h * (r->f[i] + K[i]);
        for (int64_t d = 0; d < tb->d_rows; d++) {
            double total = 0.0;
            for (int64_t j = 0; j < k_rows; j++)
                total += tb->D[d * k_rows + j] * K[j * n + i];
            F[(3 + d) * n + i] = h * total;
        }
    }
    return 1;
}

/* The interpolated state at t into out: RK45 x = x_old + h sum_k F_k s^(k+1); DOP853 SciPy's
   nested form x = x_old + F_0 + (1-s)(F_1 + s(F_2 + ...)), read from the last row back. */
static void dense_value(const lg_run *r, double t, double t_old, double h, double *out) {
    const lg_tableau *tb = &r->tableau;
    int64_t n = r->system.nx;
    double s = (t - t_old) / h;
    const double *F = r->F;
    if (tb->fixed) { /* cubic Hermite of x and dx/dt at both ends (f_old = K_0) */
        double h00 = (1 + 2 * s) * (1 - s) * (1 - s), h10 = s * (1 - s) * (1 - s);
        double h01 = s * s * (3 - 2 * s), h11 = s * s * (s - 1);
        for (int64_t i = 0; i < n; i++)
            out[i] = h00 * r->y_old[i] + h10 * h * r->K[i] + h01 * r->y[i] + h11 * h * r->f[i];
        return;
    }
    if (!tb->dop853) {
        for (int64_t i = 0; i < n; i++) {
            double total = 0.0, power = 1.0;
            for (int64_t k = 0; k < tb->p_cols; k++) {
                power *= s;
                total += F[k * n + i] * power;
            }
            out[i] = h * total + r->y_old[i];
        }
        return;
    }
    int64_t rows = 3 + tb->d_rows;
    for (int64_t i = 0; i < n; i++) {
        double value = 0.0;
        for (int64_t k = 0; k < rows; k++) {
            value += F[(rows - 1 - k) * n + i];
            value *= k % 2 == 0 ? s : 1 - s;
        }
        out[i] = value + r->y_old[i];
    }
}

/* ------------------------------------------------------------------ events */

/* g(t, x) into out (n_events values). */
static void event_values(lg_run *r, double t, const double *x, double *out) {
    double *in = r->event_inputs;
    in[0] = t;
    for (int64_t i = 0; i < r->system.nx; i++)
        in[1 + i] = x[i];
    r->event_function(out, in, r->event_user_data);
}

/* g_i on the dense output of the step (t_old, h) at s. */
static double event_inside(lg_run *r, int64_t i, double s, double t_old, double h) {
    dense_value(r, s, t_old, h, r->event_state);
    event_values(r, s, r->event_state, r->event_work);
    return r->event_work[i];
}

/* The zero of g_i in [xa, xb] by SciPy's brentq (scipy/optimize/Zeros/brentq.c: Brent's
   method, inverse quadratic interpolation or bisection), step for step. */
static double brent_root(lg_run *r, int64_t i, double xa, double xb, double t_old, double h) {
    const double tol = 4 * 2.220446049250313e-16;
    double xpre = xa, xcur = xb, xblk = 0.0, fblk = 0.0, spre = 0.0, scur = 0.0;
    double fpre = event_inside(r, i, xpre, t_old, h);
    double fcur = event_inside(r, i, xcur, t_old, h);
    if (fpre == 0)
        return xpre;
    if (fcur == 0)
        return xcur;
    for (int iteration = 0; iteration < 100; iteration++) {
        if (fpre != 0 && fcur != 0 && (signbit(fpre) != signbit(fcur))) {
            xblk = xpre;
            fblk = fpre;
            spre = scur = xcur - xpre;
        }
        if (fabs(fblk) < fabs(fcur)) {
            xpre = xcur;
            xcur = xblk;
            xblk = xpre;
            fpre = fcur;
            fcur = fblk;
            fblk = fpre;
        }
        double delta = (tol + tol * fabs(xcur)) / 2;
        double sbis = (xblk - xcur) / 2;
        if (fcur == 0 || fabs(sbis) < delta)
            return xcur;
        if (fabs(spre) > delta && fabs(fcur) < fabs(fpre)) {
            double stry;
            if (xpre == xblk) { /* interpolate */
                stry = -fcur * (xcur - xpre) / (fcur - fpre);
            } else { /* extrapolate */
                double dpre = (fpre - fcur) / (xpre - xcur);
                double dblk = (fblk - fcur) / (xblk - xcur);
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre));
            }
            if (2 * fabs(stry) < py_min(fabs(spre), 3 * fabs(sbis) - delta)) {
                spre = scur; /* a good short step */
                scur = stry;
            } else {
                spre = sbis;
                scur = sbis;
            }
        } else {
            spre = sbis;
            scur = sbis;
        }
        xpre = xcur;
        fpre = fcur;
        xcur += fabs(scur) > delta ? scur : (sbis > 0 ? delta : -delta);
        fcur = event_inside(r, i, xcur, t_old, h);
    }
    return xcur;
}

/* EventWatch.check after the step (t_old, h): the zeros in (t_old, t] recorded in the order
   of time; 1 when one of them ends the run (r->found_t of the last record is its time), 0
   when none does, -1 when the dense output fails.  *dense says whether the step's
   interpolant is already computed (it is computed here when a zero needs it). */
static int check_events(lg_run *r, double t_old, double h, int *dense) {
    int64_t m = r->n_events, n = r->system.nx, active = 0;
    event_values(r, r->t, r->y, r->event_new);
    for (int64_t i = 0; i < m; i++) {
        double old = r->event_old[i], new = r->event_new[i], d = r->directions[i];
        int up = old <= 0 && new >= 0, down = old >= 0 && new <= 0;
        if ((up && d > 0) || (down && d < 0) || ((up || down) && d == 0))
            r->order[active++] = i;
    }
    put(r->event_old, r->event_new, m);
    if (active == 0)
        return 0;
    if (!*dense) {
        if (!dense_coefficients(r, t_old, h))
            return -1;
        *dense = 1;
    }
    for (int64_t k = 0; k < active; k++)
        r->roots[k] = brent_root(r, r->order[k], t_old, r->t, t_old, h);
    for (int64_t k = 1; k < active; k++) { /* by time, then by index, as sorted((root, i)) */
        double root = r->roots[k];
        int64_t index = r->order[k], j = k - 1;
        while (j >= 0 && (r->roots[j] > root || (r->roots[j] == root && r->order[j] > index))) {
            r->roots[j + 1] = r->roots[j];
            r->order[j + 1] = r->order[j];
            j--;
        }
        r->roots[j + 1] = root;
        r->order[j + 1] = index;
    }
    for (int64_t k = 0; k < active; k++) {
        int64_t i = r->order[k], slot = r->n_found;
        r->found_index[slot] = i;
        r->found_t[slot] = r->roots[k];
        dense_value(r, r->roots[k], t_old, h, r->found_x + slot * n);
        r->n_found += 1;
        r->counts[i] += 1;
        if ((double)r->counts[i] >= r->limits[i])
            return 1;
    }
    return 0;
}

/* ------------------------------------------------------------------ the budget */

/* h ||f(y1) - f(y_j)|| / ||y1 - y_j|| for the step just taken (y_j the stage with c_j = 1),
   counted in the window when the step is near the edge of the stability region. */
static void watch_stiffness(lg_run *r, double h) {
    const lg_tableau *tb = &r->tableau;
    int64_t n = r->system.nx, j = tb->end_stage, stages = tb->stages;
    if (r->stiff_edge <= 0 || j < 0 || !isnan(r->stiff_since))
        return;
    double distance = 0.0, change = 0.0;
    for (int64_t i = 0; i < n; i++) {
        double total = 0.0;
        for (int64_t l = 0; l < j; l++)
            total += tb->A[j * stages + l] * r->K[l * n + i];
        double gap = r->y[i] - (r->y_old[i] + h * total);
        double rate = r->K[stages * n + i] - r->K[j * n + i];
        distance += gap * gap;
        change += rate * rate;
    }
    distance = sqrt(distance);
    if (distance == 0.0 || !isfinite(distance))
        return;
    int64_t near = fabs(h) * sqrt(change) / distance > r->stiff_near * r->stiff_edge;
    int64_t slot = r->recent_count % r->window;
    if (r->recent_count >= r->window)
        r->recent_sum -= r->recent[slot];
    r->recent[slot] = near;
    r->recent_sum += near;
    r->recent_count += 1;
    if (r->recent_count >= r->window && r->recent_sum >= r->stiff_share * (double)r->window)
        r->stiff_since = r->t;
}

/* budget.Budget.spend after the step from t_old: 0, or the status that ends the run. */
static int spend(lg_run *r, double t_old) {
    r->steps += 1;
    watch_stiffness(r, r->h_last);
    if (r->collapse_steps > 0) {
        r->times[r->times_count % r->collapse_steps] = r->t;
        r->times_count += 1;
        if (r->times_count >= r->collapse_steps) {
            double oldest = r->times[r->times_count % r->collapse_steps];
            r->advanced = fabs(r->t - oldest);
            double span = py_max(py_max(fabs(r->t1 - r->t0), fabs(r->t)), 1e-300);
            if (r->advanced <= r->collapse * span)
                return LG_COLLAPSED;
        }
    }
    if (!isnan(r->stiff_since)) {
        double step = fabs(r->t - t_old);
        if (step > 0 && fabs(r->t1 - r->t) / step > r->stiff_steps_left)
            return LG_STIFF;
    }
    if (r->max_steps > 0 && r->steps >= r->max_steps)
        return LG_STEP_BUDGET;
    if (!isinf(r->deadline) && lg_clock() > r->deadline)
        return LG_WALL_TIME;
    return 0;
}

/* ------------------------------------------------------------------ the run */

/* Begin at (t0, y): the output up to t0, f = f(t0, y), the initial step.  LG_RUNNING, or
   LG_SINGULAR when the right-hand side fails. */
int64_t lg_start(lg_run *r) {
    int64_t n = r->system.nx;
    r->t = r->t0;
    r->steps = r->recent_count = r->recent_sum = r->times_count = 0;
    r->h_last = 0.0;
    r->advanced = 0.0;
    r->stiff_since = NAN;
    r->rows = 0;
    if (r->n_out == 0) {
        r->out_t[0] = r->t0;
        put(r->out_x, r->y, n);
        r->rows = 1;
    } else {
        while (r->rows < r->n_out && r->t_out[r->rows] <= r->t0) {
            put(r->out_x + r->rows * n, r->y, n);
            r->rows += 1;
        }
    }
    r->n_found = 0;
    for (int64_t i = 0; i < r->n_events; i++)
        r->counts[i] = 0;
    if (!state_rates(&r->system, r->t, r->y, r->f))
        return LG_SINGULAR;
    if (r->n_events > 0)
        event_values(r, r->t, r->y, r->event_old);
    r->h_abs = r->tableau.fixed ? (r->t1 - r->t0) / (double)r->n_fixed : initial_step(r);
    return r->h_abs < 0 ? LG_SINGULAR : LG_RUNNING;
}

/* Step on (module comment): the end status, or LG_RUNNING after max_call accepted steps or
   past the clock time chunk_end, or LG_FULL when the every-step output is full. */
int64_t lg_advance(lg_run *r, int64_t max_call, double chunk_end) {
    const lg_tableau *tb = &r->tableau;
    int64_t n = r->system.nx, taken = 0;
    while (r->t < r->t1) {
        if (r->n_out == 0 && r->rows >= r->capacity)
            return LG_FULL;
        if (r->n_found + r->n_events > r->event_capacity)
            return LG_EVENTS_FULL;
        double t_new, h;
        int status = tb->fixed ? fixed_step(r, &t_new, &h) : adaptive_step(r, &t_new, &h);
        if (status != LG_FINISHED)
            return status;
        if (!all_finite(r->y_new, n))
            return LG_NOT_FINITE;
        double t_old = r->t;
        put(r->y_old, r->y, n);
        put(r->y, r->y_new, n);
        put(r->f, r->K + tb->stages * n, n);
        r->t = t_new;
        r->h_last = h;
        int over = spend(r, t_old), dense = 0, stopped = 0;
        if (r->n_events > 0) {
            stopped = check_events(r, t_old, h, &dense);
            if (stopped < 0)
                return LG_SINGULAR;
        }
        /* the output ends at a terminal event: its time and state */
        double t_stop = stopped ? r->found_t[r->n_found - 1] : r->t;
        const double *x_stop = stopped ? r->found_x + (r->n_found - 1) * n : r->y;
        if (r->n_out == 0) {
            r->out_t[r->rows] = t_stop;
            put(r->out_x + r->rows * n, x_stop, n);
            r->rows += 1;
        } else if (r->rows < r->n_out && r->t_out[r->rows] <= t_stop) {
            /* the interpolant only when an output time lies in the step, as solve_ivp */
            if (!dense && !dense_coefficients(r, t_old, h))
                return LG_SINGULAR;
            while (r->rows < r->n_out && r->t_out[r->rows] <= t_stop) {
                dense_value(r, r->t_out[r->rows], t_old, h, r->out_x + r->rows * n);
                r->rows += 1;
            }
        }
        if (stopped)
            return LG_STOPPED;
        if (over)
            return over;
        taken += 1;
        if (r->t < r->t1 && (taken >= max_call || lg_clock() >= chunk_end))
            return LG_RUNNING;
    }
    return LG_FINISHED;
}
