/*
 * Flights in closed form from contact to contact, with the lone impacts between them: the
 * compiled step of lagrangian/simulation/flight.py for a mode whose motion is polynomial in t.
 *
 * Compiled once per machine by the system C compiler and kept on disk
 * (lagrangian/numerics/fast/c_build.py), loaded with ctypes and driven by
 * lagrangian/numerics/fast/c_flight.py.  Nothing here knows a model: the caller hands
 *
 *   - the gaps g_k(q) = (q_k, 1)^T K_k (q_k, 1) of the contacts, each in its own coordinates
 *     (QuadraticGaps.forms and augmented_index: index n is a coordinate held at 0, n + 1 the
 *     point's constant 1), and per coordinate the gaps that involve it (the incidence);
 *   - M^-1 (constant), each contact's coefficient of restitution (NaN: none) and the mode's
 *     constant acceleration a;
 *   - every gap's next contact time along the current flight (the calendar), found by Python.
 *
 * From the flight's origin (t, q, v) it repeats, as the piecewise loop does one piece and one
 * transition at a time (lagrangian/simulation/integrators/piecewise.py, unilateral.py):
 *
 *   1. the earliest contact time t_c of the calendar; past t_end: the rows at the output
 *      times up to t_end, the state at t_end, and LG_FLIGHT_END;
 *   2. the rows at the output times up to t_c, every coordinate moved along its flight
 *      q + v s + a s^2/2, v + a s (s = t_c - t, in this order of operations, as
 *      Calendar.state_at);
 *   3. a lone contact (no other within SIMULTANEOUS of t_c) with a coefficient of restitution
 *      e takes the impulse Lambda = -(1 + e) g_dot- / (a M^-1 a^T) (impacts.py's closed form),
 *      v += M^-1 a^T Lambda, recorded (time, contact, impulse, state before and after);
 *      anything else (several contacts at once, no restitution, a contact not closing, one
 *      that would rest: e = 0 or a bounce lower than the contact tolerance) returns
 *      LG_FLIGHT_CONTACT at t_c, where Python resolves it (its linear complementarity
 *      problem, the contact made persistent), as it does every max_impacts-th impact;
 *   4. the calendar: only the gaps of the coordinates whose velocity jumped find their next
 *      contact again (all of them when more than half the coordinates jumped), each the first
 *      root where its polynomial c0 + c1 s + ... + c4 s^4 along the new flight turns negative
 *      (flight.py's first_crossings: a quadratic in closed form, a cubic or quartic by
 *      bisection on the intervals where it is monotone).
 */

#include <math.h>
#include <stdint.h>
#include <string.h>

#define LG_FLIGHT_ABI 2
#define LG_FLIGHT_END 0
#define LG_FLIGHT_CONTACT 1

int64_t lg_flight_abi(void) { return LG_FLIGHT_ABI; }

/* numpy's minimum and maximum: NaN when either is */
static double nan_min(double a, double b) { return (a != a || b != b) ? NAN : (a < b ? a : b); }
static double nan_max(double a, double b) { return (a != a || b != b) ? NAN : (a > b ? a : b); }

/* flight.py's _quadratic_crossings, operation for operation */
static double quadratic_crossing(double c0, double c1, double c2) {
    if (c0 <= 0 && c1 < 0) return 0.0;
    double disc = c1 * c1 - 4 * c2 * c0;
    double root = sqrt(disc > 0.0 ? disc : 0.0);
    double half = -(c1 + (c1 >= 0 ? root : -root)) / 2;
    double r1 = half / c2, r2 = c0 / half;
    double down = c2 > 0 ? nan_min(r1, r2) : nan_max(r1, r2);
    if (c2 == 0) down = -c0 / c1;
    int real = disc >= 0 && isfinite(down);
    int closing = c2 == 0 ? c1 < 0 : 1;
    return (real && closing && down > 0) ? down : INFINITY;
}

static double horner(const double *c, int degree, double s) {
    double value = c[degree];
    for (int j = degree - 1; j >= 0; j--) value = value * s + c[j];
    return value;
}

/* The root of p (monotone on [lo, hi], p(lo) > 0 > p(hi)) by bisection to the last bit. */
static double falling_root(const double *c, int degree, double lo, double hi) {
    for (int i = 0; i < 200; i++) {
        double mid = lo + (hi - lo) / 2;
        if (mid <= lo || mid >= hi) break;
        if (horner(c, degree, mid) > 0) lo = mid; else hi = mid;
    }
    return hi;
}

/* The real roots in (0, bound) of p (ascending coefficients, c[degree] != 0), sorted:
 * between the roots of p' (found the same way) p is monotone, a sign change a root. */
static int positive_roots(const double *c, int degree, double bound, double *roots) {
    if (degree == 1) {
        double r = -c[0] / c[1];
        if (r > 0 && r < bound) { roots[0] = r; return 1; }
        return 0;
    }
    double slope[4], turns[4], edges[6];
    for (int j = 1; j <= degree; j++) slope[j - 1] = j * c[j];
    int found = positive_roots(slope, degree - 1, bound, turns), count = 0, k = 0;
    edges[k++] = 0.0;
    for (int i = 0; i < found; i++) edges[k++] = turns[i];
    edges[k++] = bound;
    for (int i = 0; i + 1 < k; i++) {
        double lo = edges[i], hi = edges[i + 1];
        double plo = horner(c, degree, lo), phi = horner(c, degree, hi);
        if (plo == 0 && i > 0) { roots[count++] = lo; continue; }
        if ((plo > 0 && phi < 0) || (plo < 0 && phi > 0)) {
            double cl[5];
            for (int j = 0; j <= degree; j++) cl[j] = plo > 0 ? c[j] : -c[j];
            roots[count++] = falling_root(cl, degree, lo, hi);
        }
    }
    return count;
}

/* flight.py's first_crossings of one gap: the first s > 0 where the polynomial turns
 * negative (0 when it is closing now at g <= 0, inf when never). */
static double first_crossing(const double *c) {
    if (c[3] == 0 && c[4] == 0) return quadratic_crossing(c[0], c[1], c[2]);
    if (c[0] <= 0 && c[1] < 0) return 0.0;
    int degree = c[4] != 0 ? 4 : 3;
    double bound = 0.0, roots[4];
    for (int j = 0; j < degree; j++) {  /* Cauchy's bound of the roots */
        double r = fabs(c[j] / c[degree]);
        if (r > bound) bound = r;
    }
    bound = 1.0 + bound;
    int found = positive_roots(c, degree, bound, roots);
    for (int i = 0; i < found; i++) {
        double s = roots[i], slope = 0.0;
        for (int j = degree; j >= 1; j--) slope = slope * s + j * c[j];
        if (slope < 0) return s;
        /* a double root (touching, slope 0): p does not turn negative there */
    }
    return INFINITY;
}

/* The gaps' model, as the caller hands it (see the top of the file). */
typedef struct {
    int64_t n, m, width;           /* coordinates, gaps, coordinates of the widest gap */
    const int64_t *index;          /* m x (width + 1): the gap's coordinates, then n + 1 */
    const double *forms;           /* m x (width + 1) x (width + 1) */
    const int64_t *incidence_start;/* n + 1 */
    const int64_t *incidence;      /* the gaps of coordinate i: [start[i], start[i + 1]) */
    const double *inverse_mass;    /* n x n */
    const double *restitution;     /* m, NaN for none */
    const double *a;               /* n */
    int64_t accelerated;           /* whether a has a nonzero entry */
    const int64_t *pattern_start;  /* m + 1 */
    const int64_t *pattern;        /* gap k's nonzero entries of K (row-major positions):
                                      [pattern_start[k], pattern_start[k + 1]) */
} lg_gaps;

/* The coefficients c0..c4 of g_k(q + v s + a s^2/2) (QuadraticGaps.along): with the
 * columns x_0 = (q, 1), x_1 = (v, 0), x_2 = (a, 0) at the gap's coordinates, f_rs = x_r . K x_s,
 * c0 = f_00, c1 = 2 f_01, c2 = f_11 + f_02, c3 = f_12, c4 = f_22 / 4.  K x_s is summed over
 * the nonzero entries of K only, row by row in the order of the dense product (the skipped
 * terms are zeros: the same sums); without acceleration the terms of x_2 are zeros too. */
static void along(const lg_gaps *g, int64_t k, const double *q, const double *v, double *c) {
    int64_t w = g->width + 1, n = g->n;
    const int64_t *index = g->index + k * w;
    const double *K = g->forms + k * w * w;
    int accelerated = g->accelerated;
    double x[3][9], kx[3][9];
    for (int64_t i = 0; i < w; i++) {
        int64_t j = index[i];
        x[0][i] = j < n ? q[j] : (j == n + 1 ? 1.0 : 0.0);
        x[1][i] = j < n ? v[j] : 0.0;
        x[2][i] = j < n ? g->a[j] : 0.0;
        kx[0][i] = kx[1][i] = kx[2][i] = 0.0;
    }
    for (int64_t p = g->pattern_start[k]; p < g->pattern_start[k + 1]; p++) {
        int64_t entry = g->pattern[p], i = entry / w, j = entry % w;
        double value = K[entry];
        kx[0][i] += value * x[0][j];
        kx[1][i] += value * x[1][j];
        if (accelerated) kx[2][i] += value * x[2][j];
    }
    double f[3][3] = {{0.0}};
    for (int r = 0; r < 3; r++)
        for (int s = r; s < 3; s++) {
            if (!accelerated && s == 2) continue;
            double sum = 0.0;
            for (int64_t i = 0; i < w; i++) sum += x[r][i] * kx[s][i];
            f[r][s] = sum;
        }
    c[0] = f[0][0];
    c[1] = 2 * f[0][1];
    c[2] = accelerated ? f[1][1] + f[0][2] : f[1][1];
    c[3] = f[1][2];
    c[4] = f[2][2] / 4;
}

/* One run of flights and lone impacts (see the top of the file).  In: state = [t, q, v],
 * the origin of the calendar's flight, times its contact times; out: the same at the end
 * (the state at t_end, or at the contact left to Python, whose gap is *hit).  Rows at the
 * output times t_out[*rows_done ...] are written to rows (2n each).  Each impact done writes
 * its time, gap, impulse and states [q, v] before and after (2 x 2n).  work: 3n doubles,
 * stamp: m integers. */
int64_t lg_fly(
    const lg_gaps *g, double *times, double *state, double t_end,
    const double *t_out, int64_t n_out, double *rows, int64_t *rows_done,
    int64_t max_impacts, double *impact_t, int64_t *impact_gap, double *impact_impulse,
    double *impact_states, int64_t *impacts_done, int64_t *hit,
    double simultaneous, double sign_tolerance, double recontact, double *work,
    int64_t *stamp) {
    int64_t n = g->n, m = g->m, w = g->width + 1, done = 0, out = *rows_done;
    double *q = state + 1, *v = state + 1 + n, t = state[0];
    double *mobility = work, *grad = work + n, *after = work + 2 * n;
    for (int64_t k = 0; k < m; k++) stamp[k] = -1;
    int code = LG_FLIGHT_END;
    for (;;) {
        /* 1. the earliest contact, and whether another is as soon */
        int64_t first = -1;
        double t_hit = INFINITY, t_next = INFINITY;
        for (int64_t k = 0; k < m; k++) {
            double time = times[k];
            if (time < t_next) {
                if (time < t_hit) { t_next = t_hit; t_hit = time; first = k; }
                else t_next = time;
            }
        }
        double t_stop = t_hit <= t_end ? t_hit : t_end;
        /* 2. the rows on the way, then every coordinate at t_stop */
        while (out < n_out && t_out[out] <= t_stop) {
            double s = t_out[out] - t, *row = rows + out * 2 * n;
            for (int64_t i = 0; i < n; i++) {
                row[i] = q[i] + v[i] * s + g->a[i] * (s * s / 2);
                row[n + i] = v[i] + g->a[i] * s;
            }
            out++;
        }
        double s = t_stop - t;
        for (int64_t i = 0; i < n; i++) {
            q[i] = q[i] + v[i] * s + g->a[i] * (s * s / 2);
            v[i] = v[i] + g->a[i] * s;
        }
        t = t_stop;
        if (!(t_hit <= t_end)) { code = LG_FLIGHT_END; *hit = -1; break; }
        *hit = first;
        code = LG_FLIGHT_CONTACT;
        if (done >= max_impacts) break;
        double window = t_hit + simultaneous * (1 + fabs(t_hit));
        double e = g->restitution[first];
        if (t_next <= window || e != e || e <= 0) break;  /* another contact as soon */
        /* 3. the lone contact's impulse: its gradient a = 2 (K (q, 1))[:w-1] */
        const int64_t *index = g->index + first * w;
        const double *K = g->forms + first * w * w;
        double local[9], rate = 0.0;
        for (int64_t i = 0; i < w; i++) {
            int64_t j = index[i];
            local[i] = j < n ? q[j] : (j == n + 1 ? 1.0 : 0.0);
        }
        for (int64_t i = 0; i + 1 < w; i++) {
            double sum = 0.0;
            for (int64_t j = 0; j < w; j++) sum += K[i * w + j] * local[j];
            grad[i] = 2 * sum;
            if (index[i] < n) rate += grad[i] * v[index[i]];
        }
        double delassus = 0.0;
        for (int64_t r = 0; r < n; r++) {
            double sum = 0.0;
            for (int64_t i = 0; i + 1 < w; i++)
                if (index[i] < n) sum += g->inverse_mass[r * n + index[i]] * grad[i];
            mobility[r] = sum;
        }
        for (int64_t i = 0; i + 1 < w; i++)
            if (index[i] < n) delassus += grad[i] * mobility[index[i]];
        double wanted = -(1.0 + e) * rate;
        double scale = fabs(rate) > 1e-300 ? fabs(rate) : 1e-300;
        if (!(delassus > 0) || !(wanted > sign_tolerance * scale)) break;
        double impulse = wanted / delassus, rate_after = rate;
        for (int64_t r = 0; r < n; r++) after[r] = v[r] + mobility[r] * impulse;
        for (int64_t i = 0; i + 1 < w; i++)
            if (index[i] < n) rate_after += grad[i] * (after[index[i]] - v[index[i]]);
        if (fabs(rate_after) <= 1e-9 * (fabs(rate) + 1e-300)) break;  /* it stays: Python */
        double c[5];
        along(g, first, q, after, c);  /* the bounce: g_dot = c1, g_ddot = 2 c2 */
        if (2 * c[2] < 0 && c[1] * c[1] / (2 * -(2 * c[2])) <= recontact) break;
        /* the impact, recorded */
        double *before_after = impact_states + done * 4 * n;
        memcpy(before_after, q, n * sizeof(double));
        memcpy(before_after + n, v, n * sizeof(double));
        memcpy(before_after + 2 * n, q, n * sizeof(double));
        memcpy(before_after + 3 * n, after, n * sizeof(double));
        impact_t[done] = t_hit;
        impact_gap[done] = first;
        impact_impulse[done] = impulse;
        /* 4. the calendar: the gaps of the coordinates whose velocity jumped */
        int64_t moved = 0;
        for (int64_t r = 0; r < n; r++) {
            /* mobility marks the coordinates whose velocity jumped (v is the one after) */
            mobility[r] = after[r] != v[r];
            moved += after[r] != v[r];
            v[r] = after[r];
        }
        int every = moved > n / 2;
        for (int64_t r = 0; r < n && !every; r++) {
            if (mobility[r] == 0) continue;
            for (int64_t p = g->incidence_start[r]; p < g->incidence_start[r + 1]; p++) {
                int64_t k = g->incidence[p];
                if (stamp[k] == done) continue;
                stamp[k] = done;
                along(g, k, q, v, c);
                times[k] = t + first_crossing(c);
            }
        }
        if (every)
            for (int64_t k = 0; k < m; k++) {
                along(g, k, q, v, c);
                times[k] = t + first_crossing(c);
            }
        done++;
    }
    state[0] = t;
    *rows_done = out;
    *impacts_done = done;
    return code;
}

/* first_crossing of each of k gaps' coefficients (k x 5), for the tests and the Python
 * path's agreement. */
void lg_first_crossings(const double *coefficients, int64_t k, double *s) {
    for (int64_t i = 0; i < k; i++) s[i] = first_crossing(coefficients + 5 * i);
}
