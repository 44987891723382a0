#pragma once
// Richardson extrapolation of a scalar computed on three meshes refined by a constant ratio: the
// observed order of convergence and the extrapolated (mesh-independent) value, for refinement
// studies of cases without a closed-form solution.
#include <string>

namespace isospring::analysis {

struct Richardson {
  enum class Status {
    kExtrapolated,  // monotone convergence: order and value estimated
    kConverged,     // the last change is at round-off level: value = finest, order unknown
    kOscillating,   // the two changes differ in sign: no asymptotic power law to extrapolate
    kDiverging,     // the changes do not shrink (observed order <= 0)
  } status = Status::kConverged;
  double order = 0.0;           // observed order p (NaN unless kExtrapolated)
  double value = 0.0;           // extrapolated value (the finest value unless kExtrapolated)
  double error_estimate = 0.0;  // |finest - value| (kExtrapolated), else |finest - middle|
  bool extrapolated() const { return status == Status::kExtrapolated; }
};

/// q_coarse, q_middle, q_fine on meshes of size h, h / ratio, h / ratio^2 (ratio > 1), assuming
/// q(h) = q* + C h^p: p = log((q_middle - q_coarse) / (q_fine - q_middle)) / log(ratio) and
/// q* = q_fine + (q_fine - q_middle) / (ratio^p - 1). A last change below `round_off` times
/// |q_fine| counts as converged: a direct solve loses about cond(K) x 1e-16 relative, so with
/// condition numbers up to 1e6 changes of 1e-10 are round-off and carry no power law (measured:
/// a cubic Timoshenko beam at p = 3, whose exact solution is in the space, changes its tip
/// deflection by 6e-12 relative between levels, in no consistent direction).
Richardson richardson_extrapolation(double q_coarse, double q_middle, double q_fine,
                                    double ratio = 2.0, double round_off = 1e-10);

/// "extrapolated", "converged", "oscillating", "diverging".
std::string status_name(Richardson::Status status);

}  // namespace isospring::analysis
