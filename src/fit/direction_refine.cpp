#include "fit/direction_refine.h"

#include <algorithm>
#include <cmath>

#include "core/option_enums.h"
#include "fit/ahd_decode.h"
#include "fit/branchless.h"
#include "fit/refine_objective.h"

namespace ahd {

const char* direction_fit_name(DirectionFit f) { return enum_name(kDirectionFits, f); }

bool parse_direction_fit(const std::string& s, DirectionFit* out) { return parse_enum(kDirectionFits, s, out); }

namespace {

double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Unit tangent vectors u, v of the unit d (any continuous-enough pair; the search is local).
void tangents(const double d[3], double u[3], double v[3]) {
  double R[3][3];
  frame_from_normal(d, R);
  for (int i = 0; i < 3; ++i) u[i] = R[0][i], v[i] = R[1][i];
}

// The direction at tangent offset (a, b) from centre c, after the horizon rule.
void offset_dir(const double c[3], const double u[3], const double v[3], double a, double b, double dz_min,
                double out[3]) {
  double len2 = 0;
  for (int i = 0; i < 3; ++i) out[i] = c[i] + a * u[i] + b * v[i], len2 += out[i] * out[i];
  const double inv = 1.0 / std::sqrt(len2);
  for (int i = 0; i < 3; ++i) out[i] *= inv;
  tilt_above_horizon(out, dz_min);
}

// Unit eigenvector of the largest eigenvalue of the symmetric 3×3 matrix A (closed form: the
// trigonometric eigenvalue solution, then the null space of A − λI as the longest cross product of
// two of its rows), in three parts so that several texels' can run stage by stage (each part's
// divisions and square roots wait on each other; other texels' fill the wait):
//   AxisSolve s; if (s.begin(A)) { while (s.newton_step()) {}  if (s.end(A, v)) … }
// begin is false when A is (nearly) a multiple of I: no axis stands out; end is false when no
// eigenvector could be formed.
struct AxisSolve {
  double q, p, r, x;
  int it;

  bool begin(const double A[3][3]) {
    const double p1 = A[0][1] * A[0][1] + A[0][2] * A[0][2] + A[1][2] * A[1][2];
    q = (A[0][0] + A[1][1] + A[2][2]) / 3.0;
    const double a = A[0][0] - q, b = A[1][1] - q, c = A[2][2] - q;
    p = std::sqrt((a * a + b * b + c * c + 2.0 * p1) / 6.0);
    const double scale = std::fabs(A[0][0]) + std::fabs(A[1][1]) + std::fabs(A[2][2]) + std::sqrt(p1);
    if (!(p > 1e-9 * scale)) return false;
    // det((A − qI)/p)/2 = cos 3φ; the largest eigenvalue is q + 2p cos φ.
    const double ip = 1.0 / p;
    const double B00 = a * ip, B11 = b * ip, B22 = c * ip, B01 = A[0][1] * ip, B02 = A[0][2] * ip, B12 = A[1][2] * ip;
    const double det = B00 * (B11 * B22 - B12 * B12) - B01 * (B01 * B22 - B12 * B02) + B02 * (B01 * B12 - B11 * B02);
    r = std::clamp(det / 2.0, -1.0, 1.0);
    // cos(acos(r)/3) is the largest root x ∈ [½, 1] of 4x³ − 3x = r: Newton's method from
    // ½ + ½√((1+r)/2) (exact at r = ±1, within 0.02 between), four steps, instead of libm's acos and
    // cos (a sixth of the starts' cost).
    x = 0.5 + 0.5 * std::sqrt(0.5 * (1.0 + r));
    it = 0;
    return true;
  }
  // One Newton step; false (and x unchanged) once the four are done or the slope vanishes.
  bool newton_step() {
    if (it >= 4) return false;
    const double dh = 12.0 * x * x - 3.0;
    if (!(dh > 1e-12)) return it = 4, false;
    x -= (4.0 * x * x * x - 3.0 * x - r) / dh;
    ++it;
    return true;
  }
  bool end(const double A[3][3], double v[3]) const {
    const double lambda = q + 2.0 * p * x;
    const double M[3][3] = {{A[0][0] - lambda, A[0][1], A[0][2]},
                            {A[0][1], A[1][1] - lambda, A[1][2]},
                            {A[0][2], A[1][2], A[2][2] - lambda}};
    double best = 0;
    for (int i = 0; i < 3; ++i) {
      const double* x = M[i];
      const double* y = M[(i + 1) % 3];
      const double w[3] = {x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]};
      const double n2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
      if (n2 > best) best = n2, v[0] = w[0], v[1] = w[1], v[2] = w[2];
    }
    if (!(best > 0) || !std::isfinite(best)) return false;
    const double inv = 1.0 / std::sqrt(best);
    for (int i = 0; i < 3; ++i) v[i] *= inv;
    return true;
  }
};

}  // namespace

double constrained_error(const IrradiancePoly p[3], const double iz[3], const double d[3], const FitOptions& opt) {
  return RefineObjective(p, iz, opt.ratio_form).value(d);
}

void refine_direction(const IrradiancePoly p[3], const double iz[3], const FitOptions& opt, double d[3]) {
  refine_direction(p, iz, opt, d, RefineSearch{});
}

namespace {

// The starts of refine_direction for one texel into cand[0..n), n returned; ids[i] says which
// start cand[i] is (RefineSearch's `winner` numbering). cand[0] is d itself.
// The luminance L2 band's quadratic form Σ_c luma_c Q_c, whose principal axis is a start.
void luminance_l2_form(const IrradiancePoly p[3], const FitOptions& opt, double Q[3][3]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) Q[i][j] = 0;
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) Q[i][j] += opt.luma[c] * p[c].q[i][j];
}

// `axis`: the principal axis of luminance_l2_form (AxisSolve), null when there is none or the L2
// starts are off.
int collect_starts(const IrradiancePoly p[3], const FitOptions& opt, const RefineSearch& search, const double d[3],
                   const double* axis, double cand[6][3], int ids[6]) {
  // Cheap global starts: the local search from the linear d misses the better basin on varied
  // lighting (the L1 band averages the lights' directions; the best lobe follows the strongest).
  // Candidates: each channel's own L1 direction and the axis of the luminance L2 band's quadratic
  // form, which points along the dominant light. The best of them and the linear d is polished
  // below. (Which pay: docs/fit.md "Choosing the direction beyond the paper".) All are evaluated in one batch
  // (RefineObjective::values) and the first smallest kept, as trying them one by one would. A
  // start within search.same_start_cos of one already listed is dropped (it would land in the same
  // basin; on near-grey lighting the channels' L1 directions are the linear d).
  int n = 0;
  auto add_start = [&](const double s[3], int id) {
    for (int i = 0; i < 3; ++i) cand[n][i] = s[i];
    if (id) {
      tilt_above_horizon(cand[n], opt.dz_min);
      for (int j = 0; j < n; ++j)
        if (dot3(cand[j], cand[n]) > search.same_start_cos) return;
    }
    ids[n++] = id;
  };
  add_start(d, 0);
  if (search.starts & kStartChannelL1)
    for (int c = 0; c < 3; ++c) {
      double s[3] = {p[c].e[0], p[c].e[1], p[c].e[2]};
      const double len = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
      if (!(len > 0) || !std::isfinite(len)) continue;
      for (double& x : s) x /= len;
      add_start(s, 1 + c);
    }
  if (search.starts & (kStartL2Axis | kStartL2AxisBoth)) {
    if (axis) {
      // The axis has no sign; the lobe should face the light, which the luminance L1 band points
      // toward (with kStartL2AxisBoth both signs are tried).
      double l1 = 0;
      for (int c = 0; c < 3; ++c)
        for (int i = 0; i < 3; ++i) l1 += opt.luma[c] * p[c].e[i] * axis[i];
      const double first = l1 >= 0 ? 1.0 : -1.0;
      for (int k = 0; k < ((search.starts & kStartL2AxisBoth) ? 2 : 1); ++k) {
        const double sign = k ? -first : first;
        const double s[3] = {sign * axis[0], sign * axis[1], sign * axis[2]};
        add_start(s, 4 + k);
      }
    }
  }
  return n;
}

// One texel's state in the lockstep search below.
struct Lane {
  const IrradiancePoly* p;
  RefineObjective f;
  double* d;
  int* winner;
  LuneMoments* moments;
  double* start_value;  // the given d's objective, when not null
  double cand[6][3];
  int ids[6], n;
  double best[3], fbest;
  LuneMoments mbest;
  double centre[3], fcentre, g[3], u[3], v[3], xh[3], cn[3], gl, scale;
  int step;
  bool active;

  void finish() {
    for (int i = 0; i < 3; ++i) d[i] = best[i];
    if (moments) *moments = mbest;
    active = false;
  }
};

constexpr int kMaxStarts = 6;

// The starts of n lanes, all evaluated in one batch (lune_moments_lanes), then each lane's best
// (the first smallest, as trying them one by one would): best, fbest, mbest. A lane whose given d
// has no finite objective is finished there (d unchanged, its moments handed on) and not active.
void pick_starts(Lane* lanes, int n, const FitOptions& opt, const RefineSearch& search) {
  const IrradiancePoly* pp[kRefineLanes * kMaxStarts] = {};
  const double* dd[kRefineLanes * kMaxStarts] = {};
  LuneMoments ms[kRefineLanes * kMaxStarts];
  // The L2 axes of all lanes first, stage by stage (AxisSolve).
  const bool l2 = (search.starts & (kStartL2Axis | kStartL2AxisBoth)) != 0;
  double Q[kRefineLanes][3][3], axis[kRefineLanes][3];
  AxisSolve solve[kRefineLanes];
  bool has_axis[kRefineLanes] = {};
  if (l2) {
    for (int k = 0; k < n; ++k) {
      axis[k][0] = 0, axis[k][1] = 0, axis[k][2] = 1;
      // An L1 texel (every q ±0) has a zero form, which begin() finds has no axis: not built.
      if (!has_l2(lanes[k].p)) continue;
      luminance_l2_form(lanes[k].p, opt, Q[k]);
      has_axis[k] = solve[k].begin(Q[k]);
    }
    for (bool more = true; more;) {
      more = false;
      for (int k = 0; k < n; ++k)
        if (has_axis[k]) more |= solve[k].newton_step();
    }
    for (int k = 0; k < n; ++k)
      if (has_axis[k]) has_axis[k] = solve[k].end(Q[k], axis[k]);
  }
  int total = 0;
  for (int k = 0; k < n; ++k) {
    Lane& l = lanes[k];
    l.n = collect_starts(l.p, opt, search, l.d, has_axis[k] ? axis[k] : nullptr, l.cand, l.ids);
    for (int i = 0; i < l.n; ++i) pp[total] = l.p, dd[total] = l.cand[i], ++total;
  }
  lune_moments_lanes(pp, dd, total, ms);
  const RefineObjective* fo[kRefineLanes * kMaxStarts];
  double dz[kRefineLanes * kMaxStarts], fall[kRefineLanes * kMaxStarts];
  for (int k = 0, t = 0; k < n; ++k)
    for (int i = 0; i < lanes[k].n; ++i, ++t) fo[t] = &lanes[k].f, dz[t] = lanes[k].cand[i][2];
  values_at_lanes(fo, ms, dz, total, fall);
  int at = 0;
  for (int k = 0; k < n; ++k) {
    Lane& l = lanes[k];
    const LuneMoments* m = ms + at;
    const double* fs = fall + at;
    at += l.n;
    for (int i = 0; i < 3; ++i) l.best[i] = l.d[i];
    l.fbest = fs[0];
    if (l.start_value) *l.start_value = fs[0];
    int ib = 0;
    if (l.winner) *l.winner = 0;
    l.active = true;
    if (!std::isfinite(l.fbest)) {
      if (l.moments) *l.moments = m[0];
      l.active = false;
      continue;
    }
    // The first smallest, without branches (which start wins is random on varied lighting).
    for (int i = 1; i < l.n; ++i) {
      ib = fs[i] < l.fbest ? i : ib;
      l.fbest = less_or_second(fs[i], l.fbest);
    }
    for (int i = 0; i < 3; ++i) l.best[i] = l.cand[ib][i];
    if (l.winner) *l.winner = l.ids[ib];
    l.mbest = m[ib];
  }
}

// Polish: Newton steps along the descent direction with the analytic gradient
// (refine_objective.h): the curvature along −∇f from the value at a small step h there (a
// parabola through f and its slope −|∇f| at the centre: one value, half the cost of a second
// gradient), then the 1-D Newton step (a fixed 0.1 rad where the curvature is not positive), at
// most 0.5 rad. The best point seen is kept, so this never loses what the starts found. The
// gradient at the best start comes from its moments of the batch. A further step is taken only
// when the last one lowered f by more than search.next_step_gain of the objective's scale
// Σ_c 2π I_c² (the error of a black lobe): most texels are converged after one.
// The active lanes run in lockstep, their lune moments in one batch per stage: one texel's steps
// are a chain of square roots and divisions waiting on each other, and the other lanes' fill the
// wait. Each lane's arithmetic is the one-lane search's, in the same order (the same bytes).
void line_search(Lane* lanes, int n, const FitOptions& opt, const RefineSearch& search) {
  const double h = 0.05;
  for (int k = 0; k < n; ++k) {
    Lane& l = lanes[k];
    if (!l.active) continue;
    const double* iz = l.f.iz;
    l.scale = 2 * kPi * (iz[0] * iz[0] + iz[1] * iz[1] + iz[2] * iz[2]);
    for (int i = 0; i < 3; ++i) l.centre[i] = l.best[i];
    l.fcentre = l.fbest;
    l.step = 0;
    l.f.gradient_at(l.centre, l.mbest, l.g);
  }
  for (;;) {
    const IrradiancePoly* pp[kRefineLanes];
    const double* dd[kRefineLanes];
    Lane* on[kRefineLanes];
    int na = 0;
    for (int k = 0; k < n; ++k) {
      Lane& l = lanes[k];
      if (!l.active) continue;
      if (l.step >= search.steps) {
        l.finish();
        continue;
      }
      l.gl = std::sqrt(dot3(l.g, l.g));
      if (!(l.gl > 0) || !std::isfinite(l.gl)) {
        l.finish();
        continue;
      }
      for (int i = 0; i < 3; ++i) l.u[i] = -l.g[i] / l.gl, l.v[i] = 0;
      offset_dir(l.centre, l.u, l.v, h, 0, opt.dz_min, l.xh);
      pp[na] = l.p, dd[na] = l.xh, on[na++] = &l;
    }
    if (!na) return;
    LuneMoments mh[kRefineLanes], mc[kRefineLanes];
    const RefineObjective* fo[kRefineLanes];
    double dz[kRefineLanes], fv[kRefineLanes];
    lune_moments_lanes(pp, dd, na, mh);
    for (int j = 0; j < na; ++j) fo[j] = &on[j]->f, dz[j] = on[j]->xh[2];
    values_at_lanes(fo, mh, dz, na, fv);
    for (int j = 0; j < na; ++j) {
      Lane& l = *on[j];
      const double fh = fv[j];
      if (fh < l.fbest) l.fbest = fh, l.best[0] = l.xh[0], l.best[1] = l.xh[1], l.best[2] = l.xh[2], l.mbest = mh[j];
      const double kappa = 2.0 * (fh - l.fcentre + l.gl * h) / (h * h);
      // kappa > 0 ? gl / kappa : 0.1, then std::min(t, 0.5), without branches (fit/branchless.h).
      const double t = less_or_second(0.5, select_greater(kappa, 0.0, l.gl / kappa, 0.1));
      offset_dir(l.centre, l.u, l.v, t, 0, opt.dz_min, l.cn);
      dd[j] = l.cn;
    }
    lune_moments_lanes(pp, dd, na, mc);
    for (int j = 0; j < na; ++j) dz[j] = on[j]->cn[2];
    values_at_lanes(fo, mc, dz, na, fv);
    for (int j = 0; j < na; ++j) {
      Lane& l = *on[j];
      const double fc = fv[j];
      if (!(fc < l.fbest)) {
        l.finish();
        continue;
      }
      const double gain = l.fcentre - fc;
      l.fbest = fc, l.best[0] = l.cn[0], l.best[1] = l.cn[1], l.best[2] = l.cn[2], l.mbest = mc[j];
      l.fcentre = fc;
      for (int i = 0; i < 3; ++i) l.centre[i] = l.cn[i];
      // The next step's gradient only when there is one (most texels stop after the first).
      if (l.step + 1 == search.steps || !(gain > search.next_step_gain * l.scale)) {
        l.finish();
        continue;
      }
      l.f.gradient_at(l.centre, l.mbest, l.g);
      ++l.step;
    }
  }
}

}  // namespace

void refine_direction_lanes(int n, const IrradiancePoly* const* p, const double* const* iz, const FitOptions& opt,
                            double* const* d, LuneMoments* moments, double* start_value) {
  const RefineSearch search;
  Lane lanes[kRefineLanes];
  for (int k = 0; k < n; ++k) {
    lanes[k].p = p[k];
    lanes[k].f = RefineObjective(p[k], iz[k], opt.ratio_form);
    lanes[k].d = d[k];
    lanes[k].winner = nullptr;
    lanes[k].moments = moments ? &moments[k] : nullptr;
    lanes[k].start_value = start_value ? &start_value[k] : nullptr;
  }
  pick_starts(lanes, n, opt, search);
  line_search(lanes, n, opt, search);
}

void refine_direction(const IrradiancePoly p[3], const double iz[3], const FitOptions& opt, double d[3],
                      const RefineSearch& search, int* winner, LuneMoments* moments) {
  // Cheap global starts: the local search from the linear d misses the better basin on varied
  // lighting (the L1 band averages the lights' directions; the best lobe follows the strongest).
  // (collect_starts; which pay: docs/fit.md "Choosing the direction beyond the paper".)
  Lane l;
  l.p = p;
  l.f = RefineObjective(p, iz, opt.ratio_form);
  l.d = d;
  l.winner = winner;
  l.moments = moments;
  l.start_value = nullptr;
  pick_starts(&l, 1, opt, search);
  if (!l.active) return;
  if (search.line) {
    line_search(&l, 1, opt, search);
    return;
  }
  const RefineObjective& f = l.f;
  double best[3] = {l.best[0], l.best[1], l.best[2]};
  double fbest = l.fbest;
  // Polish: Newton steps in the tangent plane with the analytic gradient (refine_objective.h); the
  // 2×2 Hessian from differences of that gradient over a step h along the two tangents, then
  // reused for the following steps (a quasi-Newton step from the new point's gradient). The best
  // point seen is kept, so this never loses what the starts found.
  if (search.steps <= 0) {
    for (int i = 0; i < 3; ++i) d[i] = best[i];
    if (moments) *moments = lune_moments(p, d);
    return;
  }
  const double h = 0.02;
  double g[3];
  f.value_grad(best, g);
  double u[3], v[3];
  tangents(best, u, v);
  double gu = dot3(g, u), gv = dot3(g, v);
  double xu[3], xv[3], g1[3], g2[3];
  offset_dir(best, u, v, h, 0, opt.dz_min, xu);
  offset_dir(best, u, v, 0, h, opt.dz_min, xv);
  const double fu = f.value_grad(xu, g1), fv = f.value_grad(xv, g2);
  const double huu = (dot3(g1, u) - gu) / h, hvv = (dot3(g2, v) - gv) / h;
  const double huv = 0.5 * ((dot3(g1, v) - gv) / h + (dot3(g2, u) - gu) / h);
  const double det = huu * hvv - huv * huv;
  const bool convex = huu > 0 && det > 0;
  double centre[3] = {best[0], best[1], best[2]};
  if (fu < fbest) fbest = fu, best[0] = xu[0], best[1] = xu[1], best[2] = xu[2];
  if (fv < fbest) fbest = fv, best[0] = xv[0], best[1] = xv[1], best[2] = xv[2];
  for (int step = 0; step < search.steps; ++step) {
    double a, b;
    if (convex) {
      a = -(hvv * gu - huv * gv) / det, b = -(huu * gv - huv * gu) / det;
    } else {  // not convex here: go downhill by a fixed length
      const double gl = std::hypot(gu, gv);
      a = gl > 0 ? -0.1 * gu / gl : 0, b = gl > 0 ? -0.1 * gv / gl : 0;
    }
    const double len = std::hypot(a, b), trust = 0.5;
    if (len > trust) a *= trust / len, b *= trust / len;
    double cand[3];
    offset_dir(centre, u, v, a, b, opt.dz_min, cand);
    const bool last = step + 1 == search.steps;
    const double fc = last ? f.value(cand) : f.value_grad(cand, g);
    if (!(fc < fbest)) break;
    fbest = fc, best[0] = cand[0], best[1] = cand[1], best[2] = cand[2];
    if (last) break;
    for (int i = 0; i < 3; ++i) centre[i] = cand[i];
    tangents(centre, u, v);
    gu = dot3(g, u), gv = dot3(g, v);
  }
  for (int i = 0; i < 3; ++i) d[i] = best[i];
  if (moments) *moments = lune_moments(p, d);
}

}  // namespace ahd
