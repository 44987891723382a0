#include "isospring/nurbs/refine.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>

#include "curve_refinement.hpp"
#include "isospring/nurbs/basis.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::nurbs {
namespace {

using HPoint = Eigen::Vector4d;  // homogeneous control point (w x, w y, w z, w)
using Line = std::vector<HPoint>;

/// A 1D refinement of one row of homogeneous control points; the knot vector it produces is the
/// same for every row, so it is returned once.
using LineRefinement = std::function<Line(const Line& row, std::vector<double>* new_knots)>;

/// Applies `refine` to every row of the control net along `dir` (rows of a tensor product are
/// independent, which is what makes tensor-product refinement exact).
Patch refine_along(const Patch& patch, int dir, const LineRefinement& refine) {
  std::array<int, 3> n{patch.num_points(0), patch.num_points(1), patch.num_points(2)};
  std::array<int, 3> others{};
  int m = 0;
  for (int d = 0; d < 3; ++d)
    if (d != dir) others[static_cast<size_t>(m++)] = d;

  std::vector<double> new_knots;
  std::array<int, 3> n_new = n;
  std::vector<HPoint> refined;  // filled once the new row length is known
  Line row(static_cast<size_t>(n[static_cast<size_t>(dir)]));
  for (int b = 0; b < n[static_cast<size_t>(others[1])]; ++b)
    for (int a = 0; a < n[static_cast<size_t>(others[0])]; ++a) {
      std::array<int, 3> ijk{};
      ijk[static_cast<size_t>(others[0])] = a;
      ijk[static_cast<size_t>(others[1])] = b;
      for (int i = 0; i < n[static_cast<size_t>(dir)]; ++i) {
        ijk[static_cast<size_t>(dir)] = i;
        const int index = patch.index(ijk[0], ijk[1], ijk[2]);
        const double w = patch.weight(index);
        row[static_cast<size_t>(i)] << patch.control_point(index) * w, w;
      }
      const Line out = refine(row, refined.empty() ? &new_knots : nullptr);
      if (refined.empty()) {
        n_new[static_cast<size_t>(dir)] = static_cast<int>(out.size());
        refined.resize(static_cast<size_t>(n_new[0]) * n_new[1] * n_new[2]);
      }
      for (int i = 0; i < n_new[static_cast<size_t>(dir)]; ++i) {
        ijk[static_cast<size_t>(dir)] = i;
        refined[static_cast<size_t>(ijk[0] + n_new[0] * (ijk[1] + n_new[1] * ijk[2]))] =
            out[static_cast<size_t>(i)];
      }
    }

  // Degree elevation changes the degree: it is implied by the new knot and point counts.
  const int degree = static_cast<int>(new_knots.size()) - n_new[static_cast<size_t>(dir)] - 1;
  std::vector<KnotVector> knots = patch.all_knots();
  knots[static_cast<size_t>(dir)] = KnotVector(degree, std::move(new_knots), "refined knot vector");
  std::vector<Eigen::Vector3d> points(refined.size());
  std::vector<double> weights(refined.size());
  for (size_t i = 0; i < refined.size(); ++i) {
    weights[i] = refined[i].w();
    points[i] = refined[i].head<3>() / refined[i].w();
  }
  return Patch(std::move(knots), std::move(points), std::move(weights));
}

double binomial(int n, int k) {
  double result = 1.0;
  for (int i = 1; i <= k; ++i) result = result * (n - k + i) / i;
  return result;
}

/// The NURBS Book A5.9 (DegreeElevateCurve): raises the degree of (U, p, Pw) by t.
Line degree_elevate_curve(const std::vector<double>& U, int p, const Line& Pw, int t,
                          std::vector<double>* Uh_out) {
  const int n = static_cast<int>(Pw.size()) - 1;
  const int m = n + p + 1;
  const int ph = p + t;
  const int ph2 = ph / 2;
  // Coefficients for degree-elevating the Bezier segments.
  Eigen::MatrixXd bezalfs = Eigen::MatrixXd::Zero(ph + 1, p + 1);
  bezalfs(0, 0) = bezalfs(ph, p) = 1.0;
  for (int i = 1; i <= ph2; ++i) {
    const double inv = 1.0 / binomial(ph, i);
    for (int j = std::max(0, i - t); j <= std::min(p, i); ++j)
      bezalfs(i, j) = inv * binomial(p, j) * binomial(t, i - j);
  }
  for (int i = ph2 + 1; i <= ph - 1; ++i)
    for (int j = std::max(0, i - t); j <= std::min(p, i); ++j)
      bezalfs(i, j) = bezalfs(ph - i, p - j);

  // Upper bounds on the output sizes: every distinct interior knot adds t points.
  const size_t max_points = Pw.size() + static_cast<size_t>(t) * (U.size());
  Line Qw(max_points, HPoint::Zero());
  std::vector<double> Uh(max_points + static_cast<size_t>(ph) + 1, 0.0);
  Line bpts(static_cast<size_t>(p + 1)), ebpts(static_cast<size_t>(ph + 1)),
      Nextbpts(static_cast<size_t>(std::max(p - 1, 1)));
  std::vector<double> alfs(static_cast<size_t>(std::max(p - 1, 1)));

  int mh = ph, kind = ph + 1, r = -1, a = p, b = p + 1, cind = 1;
  double ua = U[0];
  Qw[0] = Pw[0];
  for (int i = 0; i <= ph; ++i) Uh[static_cast<size_t>(i)] = ua;
  for (int i = 0; i <= p; ++i) bpts[static_cast<size_t>(i)] = Pw[static_cast<size_t>(i)];

  while (b < m) {
    int i = b;
    while (b < m && U[static_cast<size_t>(b)] == U[static_cast<size_t>(b + 1)]) ++b;
    const int mul = b - i + 1;
    mh += mul + t;
    const double ub = U[static_cast<size_t>(b)];
    const int oldr = r;
    r = p - mul;
    const int lbz = oldr > 0 ? (oldr + 2) / 2 : 1;
    const int rbz = r > 0 ? ph - (r + 1) / 2 : ph;
    if (r > 0) {  // insert knot ub r times to get the Bezier segment
      const double numer = ub - ua;
      for (int k = p; k > mul; --k)
        alfs[static_cast<size_t>(k - mul - 1)] = numer / (U[static_cast<size_t>(a + k)] - ua);
      for (int j = 1; j <= r; ++j) {
        const int save = r - j, s = mul + j;
        for (int k = p; k >= s; --k)
          bpts[static_cast<size_t>(k)] =
              alfs[static_cast<size_t>(k - s)] * bpts[static_cast<size_t>(k)] +
              (1.0 - alfs[static_cast<size_t>(k - s)]) * bpts[static_cast<size_t>(k - 1)];
        Nextbpts[static_cast<size_t>(save)] = bpts[static_cast<size_t>(p)];
      }
    }
    for (int ii = lbz; ii <= ph; ++ii) {  // degree-elevate the Bezier segment
      ebpts[static_cast<size_t>(ii)].setZero();
      for (int j = std::max(0, ii - t); j <= std::min(p, ii); ++j)
        ebpts[static_cast<size_t>(ii)] += bezalfs(ii, j) * bpts[static_cast<size_t>(j)];
    }
    if (oldr > 1) {  // remove knot ua oldr-1 times
      int first = kind - 2, last = kind;
      const double den = ub - ua;
      const double bet = (ub - Uh[static_cast<size_t>(kind - 1)]) / den;
      for (int tr = 1; tr < oldr; ++tr) {
        int ii = first, j = last, kj = j - kind + 1;
        while (j - ii > tr) {
          if (ii < cind) {
            const double alf =
                (ub - Uh[static_cast<size_t>(ii)]) / (ua - Uh[static_cast<size_t>(ii)]);
            Qw[static_cast<size_t>(ii)] =
                alf * Qw[static_cast<size_t>(ii)] + (1.0 - alf) * Qw[static_cast<size_t>(ii - 1)];
          }
          if (j >= lbz) {
            if (j - tr <= kind - ph + oldr) {
              const double gam = (ub - Uh[static_cast<size_t>(j - tr)]) / den;
              ebpts[static_cast<size_t>(kj)] = gam * ebpts[static_cast<size_t>(kj)] +
                                               (1.0 - gam) * ebpts[static_cast<size_t>(kj + 1)];
            } else {
              ebpts[static_cast<size_t>(kj)] = bet * ebpts[static_cast<size_t>(kj)] +
                                               (1.0 - bet) * ebpts[static_cast<size_t>(kj + 1)];
            }
          }
          ++ii;
          --j;
          --kj;
        }
        --first;
        ++last;
      }
    }
    if (a != p)  // load the knot ua
      for (int ii = 0; ii < ph - oldr; ++ii) Uh[static_cast<size_t>(kind++)] = ua;
    for (int j = lbz; j <= rbz; ++j)
      Qw[static_cast<size_t>(cind++)] = ebpts[static_cast<size_t>(j)];
    if (b < m) {  // set up for the next pass
      for (int j = 0; j < r; ++j) bpts[static_cast<size_t>(j)] = Nextbpts[static_cast<size_t>(j)];
      for (int j = r; j <= p; ++j)
        bpts[static_cast<size_t>(j)] = Pw[static_cast<size_t>(b - p + j)];
      a = b;
      ++b;
      ua = ub;
    } else {
      for (int ii = 0; ii <= ph; ++ii) Uh[static_cast<size_t>(kind + ii)] = ub;
    }
  }
  const int nh = mh - ph - 1;
  Qw.resize(static_cast<size_t>(nh + 1));
  Uh.resize(static_cast<size_t>(nh + ph + 2));
  if (Uh_out) *Uh_out = std::move(Uh);
  return Qw;
}

void check_direction(const Patch& patch, int dir, const char* what) {
  if (dir < 0 || dir >= patch.param_dim()) {
    std::ostringstream msg;
    msg << what << ": direction " << dir << " does not exist in a patch of parametric dimension "
        << patch.param_dim() << "; use 0.." << patch.param_dim() - 1;
    throw InputError(msg.str());
  }
}

}  // namespace

Patch insert_knot(const Patch& patch, int dir, double u, int times) {
  return refine_knots(patch, dir, std::vector<double>(static_cast<size_t>(std::max(times, 0)), u));
}

Patch refine_knots(const Patch& patch, int dir, std::vector<double> new_knots) {
  check_direction(patch, dir, "knot insertion");
  if (new_knots.empty()) return patch;
  std::sort(new_knots.begin(), new_knots.end());
  const KnotVector& kv = patch.knots(dir);
  for (double x : new_knots) {
    if (!std::isfinite(x) || x <= kv.first() || x >= kv.last()) {
      std::ostringstream msg;
      msg << "knot insertion: " << x << " is not strictly inside the parameter range ["
          << kv.first() << ", " << kv.last() << "] of direction " << dir;
      throw InputError(msg.str());
    }
    const int total =
        kv.multiplicity(x) + static_cast<int>(std::count(new_knots.begin(), new_knots.end(), x));
    if (total > kv.degree()) {
      std::ostringstream msg;
      msg << "knot insertion: knot " << x << " would get multiplicity " << total << " in direction "
          << dir << ", above the degree " << kv.degree() << "; insert it fewer times";
      throw InputError(msg.str());
    }
  }
  return refine_along(patch, dir, [&](const Line& row, std::vector<double>* knots_out) {
    return detail::refine_knot_vector_curve(kv, row, new_knots, knots_out);
  });
}

std::vector<double> uniform_split_knots(const KnotVector& knots, int splits) {
  std::vector<double> inserted;
  const std::vector<double> breaks = knots.unique();
  for (size_t e = 0; e + 1 < breaks.size(); ++e)
    for (int s = 1; s < splits; ++s)
      inserted.push_back(breaks[e] + (breaks[e + 1] - breaks[e]) * s / splits);
  return inserted;
}

Patch refine_uniform(const Patch& patch, int dir, int splits) {
  check_direction(patch, dir, "uniform refinement");
  if (splits < 1)
    throw InputError("uniform refinement: splits must be >= 1, got " + std::to_string(splits));
  return refine_knots(patch, dir, uniform_split_knots(patch.knots(dir), splits));
}

Patch refine_uniform(const Patch& patch, int splits) {
  Patch result = patch;
  for (int d = 0; d < patch.param_dim(); ++d) result = refine_uniform(result, d, splits);
  return result;
}

Patch elevate_degree(const Patch& patch, int dir, int times) {
  check_direction(patch, dir, "degree elevation");
  if (times < 0)
    throw InputError("degree elevation: cannot lower the degree (times = " + std::to_string(times) +
                     ")");
  if (times == 0) return patch;
  const KnotVector& kv = patch.knots(dir);
  if (kv.degree() + times > kMaxDegree)
    throw InputError("degree elevation: degree " + std::to_string(kv.degree() + times) +
                     " is above the supported maximum 20");
  return refine_along(patch, dir, [&](const Line& row, std::vector<double>* knots_out) {
    return degree_elevate_curve(kv.values(), kv.degree(), row, times, knots_out);
  });
}

Patch elevate_degree(const Patch& patch, int times) {
  Patch result = patch;
  for (int d = 0; d < patch.param_dim(); ++d) result = elevate_degree(result, d, times);
  return result;
}

Patch k_refine(const Patch& patch, const std::array<int, 3>& degree,
               const std::array<int, 3>& splits) {
  Patch result = patch;
  for (int d = 0; d < patch.param_dim(); ++d) {
    const int raise = degree[static_cast<size_t>(d)] - patch.degree(d);
    if (raise < 0)
      throw InputError("k-refinement: direction " + std::to_string(d) + " has degree " +
                       std::to_string(patch.degree(d)) + ", above the requested " +
                       std::to_string(degree[static_cast<size_t>(d)]) +
                       "; degrees can only be raised");
    result = elevate_degree(result, d, raise);
    result = refine_uniform(result, d, splits[static_cast<size_t>(d)]);
  }
  return result;
}

}  // namespace isospring::nurbs
