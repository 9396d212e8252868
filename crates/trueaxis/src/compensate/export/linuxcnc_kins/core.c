/* trueaxis kinematics core, after the generated model data. Pure C on the math library: the exact
 * chain of trueaxis (docs/design.md, "Frames and chain"): A_k(q) = L_k S_k(q) J_k(q), products from
 * the base outward; L_k the location errors, S_k the motion errors (tables over the axis travel,
 * linear interpolation), J_k the nominal motion. Units: mm and rad inside; joints and world in mm and
 * deg. World: the tool point relative to the workpiece (x y z, mm, in the frame of the controller's
 * linear axes, the datum of the model) and the rotary axes' programmed (nominal) positions (deg). */

typedef struct { double r[3][3]; double t[3]; } ta_pose;

static void ta_identity(ta_pose *p) {
    int i, j;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) p->r[i][j] = (i == j) ? 1.0 : 0.0;
        p->t[i] = 0.0;
    }
}

/* a = a b */
static void ta_then(ta_pose *a, const ta_pose *b) {
    ta_pose c;
    int i, j, k;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            c.r[i][j] = 0.0;
            for (k = 0; k < 3; k++) c.r[i][j] += a->r[i][k] * b->r[k][j];
        }
        c.t[i] = a->t[i];
        for (k = 0; k < 3; k++) c.t[i] += a->r[i][k] * b->t[k];
    }
    *a = c;
}

/* rotation by the angle |w| about w / |w| (Rodrigues) */
static void ta_rotation(const double w[3], double r[3][3]) {
    double th = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]), s, c, k[3];
    int i, j;
    if (th < 1e-300) {
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++) r[i][j] = (i == j) ? 1.0 : 0.0;
        return;
    }
    s = sin(th);
    c = 1.0 - cos(th);
    for (i = 0; i < 3; i++) k[i] = w[i] / th;
    r[0][0] = 1.0 - c * (k[1] * k[1] + k[2] * k[2]);
    r[0][1] = -s * k[2] + c * k[0] * k[1];
    r[0][2] = s * k[1] + c * k[0] * k[2];
    r[1][0] = s * k[2] + c * k[0] * k[1];
    r[1][1] = 1.0 - c * (k[0] * k[0] + k[2] * k[2]);
    r[1][2] = -s * k[0] + c * k[1] * k[2];
    r[2][0] = -s * k[1] + c * k[0] * k[2];
    r[2][1] = s * k[0] + c * k[1] * k[2];
    r[2][2] = 1.0 - c * (k[0] * k[0] + k[1] * k[1]);
}

/* the small transform Trans(c) [exp(eps), e] Trans(-c), v = (ex ey ez epsx epsy epsz) */
static void ta_small(const double v[6], const double c[3], ta_pose *p) {
    int i, k;
    ta_rotation(v + 3, p->r);
    for (i = 0; i < 3; i++) {
        p->t[i] = c[i] + v[i];
        for (k = 0; k < 3; k++) p->t[i] -= p->r[i][k] * c[k];
    }
}

/* the six motion errors of axis k at its position q (mm or deg): its tables, interpolated */
static void ta_motion_errors(int k, double q, double v[6]) {
    int c, i, last = ta_points[k] - 1;
    double x, s;
    for (c = 0; c < 6; c++) v[c] = 0.0;
    if (last < 1) return;
    x = (q - ta_first[k]) / ta_step[k];
    if (ta_period[k]) {
        x = fmod(x, (double)last);
        if (x < 0.0) x += (double)last;
    }
    if (x < 0.0) x = 0.0;
    if (x > (double)last) x = (double)last;
    i = (int)x;
    if (i > last - 1) i = last - 1;
    s = x - (double)i;
    for (c = 0; c < 6; c++) {
        const double *t = ta_values + ta_start[k] + c * ta_points[k];
        v[c] = t[i] + s * (t[i + 1] - t[i]);
    }
}

/* the end pose of a chain at the joints q (mm, deg); actual: with the errors */
static void ta_chain(const int *chain, int len, const double *q, int actual, ta_pose *out) {
    ta_pose step;
    int n, i, j;
    ta_identity(out);
    for (n = 0; n < len; n++) {
        int k = chain[n];
        double qi = q[k] * ta_scale[k];
        if (actual) {
            double v[6], c[3];
            ta_small(ta_location[k], ta_location_centre[k], &step);
            ta_then(out, &step);
            ta_motion_errors(k, q[k], v);
            for (i = 0; i < 3; i++) c[i] = ta_kind[k] ? ta_point[k][i] : ta_point[k][i] + qi * ta_dir[k][i];
            ta_small(v, c, &step);
            ta_then(out, &step);
        }
        if (ta_kind[k]) {
            double w[3];
            for (i = 0; i < 3; i++) w[i] = ta_dir[k][i] * qi;
            ta_rotation(w, step.r);
            for (i = 0; i < 3; i++) {
                step.t[i] = ta_point[k][i];
                for (j = 0; j < 3; j++) step.t[i] -= step.r[i][j] * ta_point[k][j];
            }
        } else {
            ta_identity(&step);
            for (i = 0; i < 3; i++) step.t[i] = ta_dir[k][i] * qi;
        }
        ta_then(out, &step);
    }
}

/* the tool point relative to the workpiece (r, mm) and the tool axis (u), in the workpiece frame;
 * the actual model in the datum of the controller's frame */
static void ta_relative(const double *q, int actual, double r[3], double u[3]) {
    ta_pose tool, work;
    double p[3], d[3], rr[3], uu[3];
    const double *tool_point = actual ? ta_tool_point_actual : ta_tool_point;
    int i, k;
    ta_chain(ta_tool_chain, ta_tool_len, q, actual, &tool);
    ta_chain(ta_work_chain, ta_work_len, q, actual, &work);
    for (i = 0; i < 3; i++) {
        p[i] = tool.t[i] - work.t[i];
        for (k = 0; k < 3; k++) p[i] += tool.r[i][k] * tool_point[k];
        d[i] = tool.r[i][2];
    }
    for (i = 0; i < 3; i++) {
        rr[i] = 0.0;
        uu[i] = 0.0;
        for (k = 0; k < 3; k++) {
            rr[i] += work.r[k][i] * p[k];
            uu[i] += work.r[k][i] * d[k];
        }
    }
    for (i = 0; i < 3; i++) {
        r[i] = actual ? ta_datum_t[i] : 0.0;
        u[i] = 0.0;
        for (k = 0; k < 3; k++) {
            double m = actual ? ta_datum_r[i][k] : ((i == k) ? 1.0 : 0.0);
            r[i] += m * rr[k];
            u[i] += m * uu[k];
        }
    }
}

/* solves a x = b (n x n, Gaussian elimination with partial pivoting); 0 when singular */
static int ta_solve(int n, double a[TA_N][TA_N], double b[TA_N], double x[TA_N]) {
    int i, j, k, p;
    for (k = 0; k < n; k++) {
        p = k;
        for (i = k + 1; i < n; i++)
            if (fabs(a[i][k]) > fabs(a[p][k])) p = i;
        if (fabs(a[p][k]) < 1e-300) return 0;
        if (p != k) {
            double t;
            for (j = 0; j < n; j++) {
                t = a[k][j];
                a[k][j] = a[p][j];
                a[p][j] = t;
            }
            t = b[k];
            b[k] = b[p];
            b[p] = t;
        }
        for (i = k + 1; i < n; i++) {
            double f = a[i][k] / a[k][k];
            for (j = k; j < n; j++) a[i][j] -= f * a[k][j];
            b[i] -= f * b[k];
        }
    }
    for (i = n - 1; i >= 0; i--) {
        x[i] = b[i];
        for (j = i + 1; j < n; j++) x[i] -= a[i][j] * x[j];
        x[i] /= a[i][i];
    }
    return 1;
}

/* two unit directions across the unit vector u */
static void ta_across(const double u[3], double e1[3], double e2[3]) {
    double h[3] = { 1.0, 0.0, 0.0 }, d, n;
    int i;
    if (fabs(u[0]) >= 0.9) {
        h[0] = 0.0;
        h[1] = 1.0;
    }
    d = h[0] * u[0] + h[1] * u[1] + h[2] * u[2];
    for (i = 0; i < 3; i++) e1[i] = h[i] - d * u[i];
    n = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    for (i = 0; i < 3; i++) e1[i] /= n;
    e2[0] = u[1] * e1[2] - u[2] * e1[1];
    e2[1] = u[2] * e1[0] - u[0] * e1[2];
    e2[2] = u[0] * e1[1] - u[1] * e1[0];
}

/* the tasks at the joints q. actual = 1 (inverse kinematics): the actual tool point minus `target`
 * (mm) and the actual tool axis across the wanted one (e1, e2; x 1000 mm). actual = 0 (the world
 * rotary positions of a tool axis): the nominal tool axis across the actual one, no position task. */
static void ta_tasks(const double *q, int actual, const double target[3], const double e1[3], const double e2[3], double f[5]) {
    double r[3], u[3];
    int i;
    ta_relative(q, actual, r, u);
    for (i = 0; i < 3; i++) f[i] = actual ? r[i] - target[i] : 0.0;
    f[3] = 1000.0 * (u[0] * e1[0] + u[1] * e1[1] + u[2] * e1[2]);
    f[4] = 1000.0 * (u[0] * e2[0] + u[1] * e2[1] + u[2] * e2[2]);
}

/* Gauss-Newton (normal equations, damped by 1e-9 of a joint unit squared) on the joints `free`
 * that puts the tasks to zero; joints scaled so that 1 rad of a rotary joint counts as 1000 mm, a
 * central-difference Jacobian. Returns the iterations, -1 when it does not converge. */
static int ta_newton(double *q, const int *free, int actual, const double target[3], const double e1[3], const double e2[3]) {
    int it, i, j, k;
    for (it = 1; it <= 30; it++) {
        double f[5], g[5], h5[5], jac[5][TA_N], a[TA_N][TA_N], b[TA_N], dx[TA_N], w[TA_N], big = 0.0;
        ta_tasks(q, actual, target, e1, e2, f);
        for (k = 0; k < TA_N; k++) {
            double keep = q[k], h = 1e-4; /* mm or deg */
            w[k] = ta_kind[k] ? 1000.0 * ta_scale[k] : 1.0; /* mm per joint unit */
            if (!free[k]) {
                for (i = 0; i < 5; i++) jac[i][k] = 0.0;
                continue;
            }
            q[k] = keep + h;
            ta_tasks(q, actual, target, e1, e2, g);
            q[k] = keep - h;
            ta_tasks(q, actual, target, e1, e2, h5);
            q[k] = keep;
            for (i = 0; i < 5; i++) jac[i][k] = (g[i] - h5[i]) / (2.0 * h) / w[k];
        }
        for (j = 0; j < TA_N; j++) {
            for (k = 0; k < TA_N; k++) {
                a[j][k] = 0.0;
                for (i = 0; i < 5; i++) a[j][k] += jac[i][j] * jac[i][k];
            }
            a[j][j] += free[j] ? 1e-9 : 1.0;
            b[j] = 0.0;
            for (i = 0; i < 5; i++) b[j] -= jac[i][j] * f[i];
        }
        if (!ta_solve(TA_N, a, b, dx)) return -1;
        for (k = 0; k < TA_N; k++) {
            q[k] += dx[k] / w[k];
            if (fabs(dx[k]) > big) big = fabs(dx[k]);
        }
        if (big < 1e-9) return it;
    }
    return -1;
}

/* joints q of the world pose: x y z (world, mm), the rotary axes' programmed positions (rotary, deg,
 * joint order; other entries unused). Returns the iterations, -1 when it does not converge. */
static int ta_inverse(const double world[3], const double *rotary, double *q) {
    double r0[3], u0[3], e1[3], e2[3], a[TA_N][TA_N], b[TA_N], x[TA_N];
    int free[TA_N], lin[TA_N], n_lin = 0, i, k;
    /* the nominal joints: the rotary axes as programmed, the linear axes solving the (affine)
     * nominal position */
    for (k = 0; k < TA_N; k++) {
        q[k] = ta_kind[k] ? rotary[k] : 0.0;
        if (!ta_kind[k]) lin[n_lin++] = k;
    }
    ta_relative(q, 0, r0, u0);
    for (i = 0; i < TA_N; i++) {
        for (k = 0; k < TA_N; k++) a[i][k] = (i == k) ? 1.0 : 0.0;
        b[i] = 0.0;
    }
    for (i = 0; i < n_lin; i++) {
        double r1[3], u1[3];
        q[lin[i]] = 1.0;
        ta_relative(q, 0, r1, u1);
        q[lin[i]] = 0.0;
        for (k = 0; k < 3; k++) a[k][i] = r1[k] - r0[k];
    }
    for (k = 0; k < 3; k++) b[k] = world[k] - r0[k];
    if (n_lin != 3 || !ta_solve(TA_N, a, b, x)) return -1;
    for (i = 0; i < n_lin; i++) q[lin[i]] = x[i];
    /* the tool axis the program asks for: the nominal one at these joints */
    ta_relative(q, 0, r0, u0);
    ta_across(u0, e1, e2);
    for (k = 0; k < TA_N; k++) free[k] = 1;
    return ta_newton(q, free, 1, world, e1, e2);
}

/* the world pose of the joints q: x y z into world (mm), the rotary axes' nominal positions with the
 * same tool axis into rotary (deg, joint order; linear entries 0). Returns the iterations of the
 * rotary solve, -1 when it does not converge. */
static int ta_forward(const double *q, double world[3], double *rotary) {
    double r[3], u[3], e1[3], e2[3];
    int free[TA_N], k, it = 0;
    ta_relative(q, 1, r, u);
    ta_across(u, e1, e2);
    for (k = 0; k < TA_N; k++) {
        rotary[k] = ta_kind[k] ? q[k] : 0.0;
        free[k] = ta_kind[k];
    }
    if (ta_rotary_count > 0) it = ta_newton(rotary, free, 0, r, e1, e2);
    for (k = 0; k < 3; k++) world[k] = r[k];
    return it;
}
