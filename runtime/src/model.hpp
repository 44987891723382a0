#pragma once
// The runtime's model: flat arrays laid out for one pass per term kind (runtime.h). Private to
// the library; the C API in runtime.cpp wraps it.
#include <Eigen/Core>
#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace isospring::runtime {

/// A problem with a model file; its message names the file and the field.
class LoadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Names the source (a file, or the builder function) and the field in every LoadError.
class Fields {
 public:
  explicit Fields(std::string source) : source_(std::move(source)) {}
  [[noreturn]] void fail(const std::string& field, const std::string& problem) const {
    throw LoadError(source_ + ": " + field + ": " + problem);
  }

 private:
  std::string source_;
};

struct SpringTerm {
  int i = 0, j = 0;
  double stiffness = 0.0, damping = 0.0, rest_length = 0.0;
};

/// A cell volume term: E = 1/2 factor (V(x) - rest_volume)^2, factor = kappa / |V0|.
struct CellVolumeTerm {
  int corners[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  double factor = 0.0;
  double rest_volume = 0.0;
};

/// A term on a deformation gradient F = sum_a x_{points[first + a]} h_{first + a}^T over
/// `count` particles (h: `dimension` numbers each in Model::gradients). Shear: E = scale |dev G|^2
/// (scale = mu |V0|); volume: E = 1/2 scale (det F - 1)^2 (scale = kappa |V0|). Cell shear terms
/// are of this form too, with h_a = b_a / V0 from the cell's rest volume gradient b.
struct GradientTerm {
  int first = 0;
  int count = 0;
  double scale = 0.0;
};

struct Model {
  int kind = 0;  // isospring_model_kind
  int dimension = 3;
  size_t particles = 0;
  std::vector<double> rest;  // particles * dimension
  std::vector<double> masses;
  std::vector<unsigned char> fixed;
  int mask = 63;  // ISOSPRING_TERM_ALL

  std::vector<SpringTerm> springs;
  std::vector<CellVolumeTerm> cell_volumes;
  std::vector<GradientTerm> cell_shears, point_volumes, point_shears;
  std::vector<int> points;        // particles of the gradient terms
  std::vector<double> gradients;  // their h vectors, dimension numbers each

  // Reduced model (docs/reduced_model.md).
  size_t basis_size = 0;
  double timestep = 0.0;
  std::vector<double> basis;         // (particles * dimension) x basis_size, row-major
  std::vector<double> eigenvalues;   // Lambda
  std::vector<double> damping;       // C_r, row-major
  std::vector<double> step_inverse;  // (I + dt C_r + dt^2 Lambda)^-1, row-major
  std::vector<double> scratch;       // basis_size: the step's right-hand side

  // Corotated reduced model (corotation.hpp): empty corot_offsets for the linear one. Particle
  // i's neighbours are corot_columns[corot_offsets[i] .. corot_offsets[i + 1]); d x d blocks
  // row-major at the same positions; the row sums, rest inverses and scratch per particle.
  std::vector<int> corot_offsets, corot_columns;
  std::vector<double> corot_stiffness, corot_damping;
  std::vector<double> corot_row_stiffness, corot_row_damping, corot_rest_inverse;
  // Scratch of the evaluations: a corotated model must not be evaluated from several threads.
  mutable std::vector<double> corot_x, corot_v, corot_f, corot_g;
  mutable std::vector<Eigen::Matrix3d> corot_rotations;
  bool corotated() const { return !corot_offsets.empty(); }

  size_t state_size() const {
    return kind == 1 ? basis_size : particles * static_cast<size_t>(dimension);
  }
};

/// Checked additions to a network model (model_build.cpp), shared by the file reader and the
/// C builder functions; `path` names the entry ("springs[3]."). Throw LoadError.
void add_particles(Model& model, int dimension, size_t count, const double* rest,
                   const double* masses, const unsigned char* fixed, const Fields& fields);
void add_spring(Model& model, const SpringTerm& spring, const Fields& fields,
                const std::string& path);
/// A cell term over 2^dimension corners (tensor order): volume (kappa) or shear (mu).
void add_cell(Model& model, bool shear, const int* corners, double modulus, double rest_volume,
              const Fields& fields, const std::string& path);
/// A strain point over `count` particles with their gradients (dimension numbers each).
void add_point(Model& model, bool shear, const int* particles, const double* gradients, int count,
               double modulus, double rest_volume, const Fields& fields, const std::string& path);

/// Parses a model document (either format); throws LoadError.
Model parse_model(const std::string& text, const std::string& source);

/// Cell volume V and its gradient b (corner-major, 2^d * d numbers) at the corners' coordinates
/// (corner-major): 2-point Gauss per direction, exact (analysis/spring_volume.hpp).
double cell_volume(const double* corner_x, int dimension, double* gradient);

/// E and f (added) over the selected network terms; jvp: df (added).
double network_forces(const Model& model, const double* x, const double* v, double* f);
void network_force_jvp(const Model& model, const double* x, const double* v, const double* dx,
                       const double* dv, double* df);

/// Copies a message into a caller's buffer, truncated and always terminated.
inline void write_error(char* error, size_t size, const std::string& message) {
  if (!error || size == 0) return;
  const size_t n = std::min(size - 1, message.size());
  std::memcpy(error, message.data(), n);
  error[n] = '\0';
}

}  // namespace isospring::runtime

/// The C API's opaque handle (runtime.h).
struct isospring_model {
  isospring::runtime::Model model;
};
