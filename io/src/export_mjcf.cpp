#include "isospring/io/export_mjcf.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "export_xml.hpp"
#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/model_file.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {
std::string name(const char* prefix, size_t index) {
  return prefix + std::to_string(index);
}
}  // namespace

Eigen::Vector3d engine_gravity(const analysis::SpringNetwork& network,
                               const Eigen::Vector3d& model_gravity,
                               const std::optional<Eigen::Vector3d>& given) {
  const bool flat = network.dimension == 2;
  if (given) {
    if (flat && given->z() != 0.0)
      throw nurbs::InputError(
          "--gravity: the model is flat (2D, \"dimension\": 2): its particles move in the x-y "
          "plane only, so a gravity with a z component (" +
          std::to_string(given->z()) +
          " m/s^2) would never move it; give an in-plane gravity such as --gravity 0,-9.81,0 (the "
          "default for 2D models)");
    return *given;
  }
  if (!model_gravity.isZero(0.0)) return model_gravity;
  return flat ? Eigen::Vector3d(0.0, -9.81, 0.0) : Eigen::Vector3d(0.0, 0.0, -9.81);
}

namespace {

// Gershgorin's bound on omega_max^2 of M^-1 K with K the whole rest stiffness.
double largest_omega_squared(const analysis::SpringNetwork& network) {
  const Eigen::SparseMatrix<double> k = analysis::rest_stiffness(network);
  Eigen::VectorXd row_sums = Eigen::VectorXd::Zero(k.rows());
  for (Eigen::Index c = 0; c < k.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(k, c); it; ++it)
      row_sums[it.row()] += std::abs(it.value());
  double omega_squared = 0.0;
  for (size_t p = 0; p < network.positions.size(); ++p)
    if (!network.fixed[p] && network.masses[p] > 0)
      for (int c = 0; c < network.dimension; ++c)
        omega_squared =
            std::max(omega_squared, row_sums[static_cast<Eigen::Index>(p) * network.dimension + c] /
                                        network.masses[p]);
  return omega_squared;
}

}  // namespace

double suggested_timestep(const analysis::SpringNetwork& network) {
  if (!network.volumes.empty()) {
    const double omega_squared = largest_omega_squared(network);
    return omega_squared > 0 ? 0.2 * 2.0 / std::sqrt(omega_squared) : 1e-3;
  }
  std::vector<double> stiffness_sum(network.positions.size(), 0.0);
  for (const analysis::Spring& s : network.springs) {
    stiffness_sum[static_cast<size_t>(s.i)] += s.stiffness;
    stiffness_sum[static_cast<size_t>(s.j)] += s.stiffness;
  }
  double omega_squared = 0.0;
  for (size_t p = 0; p < network.positions.size(); ++p)
    if (!network.fixed[p] && network.masses[p] > 0)
      omega_squared = std::max(omega_squared, 2.0 * stiffness_sum[p] / network.masses[p]);
  if (omega_squared <= 0) return 1e-3;  // no springs: any step is stable
  return 0.2 * 2.0 / std::sqrt(omega_squared);
}

std::string mjcf_document(const analysis::SpringNetwork& network, const MjcfOptions& options) {
  if (const std::string problem = check_spring_network(network); !problem.empty())
    throw nurbs::InputError("cannot export to MuJoCo: the spring model is invalid: " + problem);
  if (!network.volumes.empty() && options.runtime_model.empty())
    throw nurbs::InputError(
        "cannot export to MuJoCo: the spring model has " + detail::cell_terms(network) +
        " and MuJoCo 2.2 has no element for them (its tendons are central springs); they run "
        "through MuJoCo's passive-force callback with the isospring runtime, from a model.json "
        "next to the scene: give MjcfOptions::runtime_model, or use write_mjcf / `isospring "
        "export`, which write both files");
  if (network.dimension == 2 && options.gravity.z() != 0.0)
    throw nurbs::InputError(
        "cannot export a flat (2D) spring model to MuJoCo with gravity along z: its particles "
        "have slide joints in x and y only and would never move; give an in-plane gravity (e.g. "
        "0,-9.81,0, the default of `isospring export` for 2D models)");
  using detail::number;
  using detail::vector3;
  double radius = options.particle_radius;
  if (radius <= 0) {
    double shortest = std::numeric_limits<double>::infinity();
    for (const analysis::Spring& s : network.springs) shortest = std::min(shortest, s.rest_length);
    radius = std::isfinite(shortest) ? 0.1 * shortest : 0.01;
  }
  const double timestep = options.timestep > 0 ? options.timestep : suggested_timestep(network);
  const char* axes[3][2] = {{"_x", "1 0 0"}, {"_y", "0 1 0"}, {"_z", "0 0 1"}};

  std::ostringstream out;
  out << "<mujoco model=\"" << detail::xml_escape(options.model_name) << "\">\n";
  out << "  <!-- Exported by isospring from a spring model (model.json schema version 1).\n"
      << "       Particles are bodies with slide joints (their coordinates are displacements),\n"
      << "       springs are spatial tendons with stiffness, damping and springlength = L0.\n"
      << "       Written for MuJoCo 2.2. -->\n";
  if (!options.comment.empty())
    out << "  <!-- " << detail::xml_comment(options.comment) << " -->\n";
  if (!network.volumes.empty())
    out << "  <!-- " << detail::xml_comment(detail::cell_terms(network))
        << " are not in this file: MuJoCo has no element for them. The isospring runtime\n"
        << "       evaluates them from the model.json named below in MuJoCo's passive-force\n"
        << "       callback (mjcb_passive), springs masked out; see examples/mujoco. -->\n"
        << "  <custom>\n    <text name=\"isospring_model\" data=\""
        << detail::xml_escape(options.runtime_model) << "\"/>\n  </custom>\n";
  out << "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
      << "  <option timestep=\"" << number(timestep) << "\" gravity=\"" << vector3(options.gravity)
      << "\" integrator=\"" << (options.implicit_integrator ? "implicit" : "Euler") << "\">\n"
      << "    <flag contact=\"disable\"/>\n  </option>\n"
      << "  <default>\n"
      << "    <geom type=\"sphere\" size=\"" << number(radius)
      << "\" contype=\"0\" conaffinity=\"0\" rgba=\"0.2 0.5 0.9 1\"/>\n"
      << "    <site type=\"sphere\" size=\"" << number(0.5 * radius) << "\"/>\n"
      << "    <joint type=\"slide\" limited=\"false\" damping=\"0\"/>\n"
      << "    <tendon width=\"" << number(0.25 * radius) << "\"/>\n"
      << "  </default>\n  <worldbody>\n";
  for (size_t p = 0; p < network.positions.size(); ++p) {
    const std::string particle = name("particle_", p);
    const std::string position = vector3(network.positions[p]);
    if (network.fixed[p]) {
      out << "    <site name=\"" << particle << "\" pos=\"" << position
          << "\" rgba=\"0.9 0.2 0.2 1\"/>\n";
      continue;
    }
    const double m = network.masses[p];
    const double inertia = 0.4 * m * radius * radius;  // a solid sphere; slide joints ignore it
    out << "    <body name=\"" << particle << "\" pos=\"" << position << "\">\n"
        << "      <inertial pos=\"0 0 0\" mass=\"" << number(m) << "\" diaginertia=\""
        << number(inertia) << " " << number(inertia) << " " << number(inertia) << "\"/>\n";
    for (int a = 0; a < network.dimension; ++a) {
      out << "      <joint name=\"" << particle << axes[a][0] << "\" axis=\"" << axes[a][1] << "\"";
      if (options.particle_damping_rate > 0)
        out << " damping=\"" << number(options.particle_damping_rate * m) << "\"";
      out << "/>\n";
    }
    out << "      <geom/>\n      <site name=\"" << particle << "\" pos=\"0 0 0\"/>\n"
        << "    </body>\n";
  }
  out << "  </worldbody>\n";
  if (!network.springs.empty()) {
    out << "  <tendon>\n";
    for (size_t s = 0; s < network.springs.size(); ++s) {
      const analysis::Spring& spring = network.springs[s];
      out << "    <spatial name=\"" << name("spring_", s) << "\" stiffness=\""
          << number(spring.stiffness) << "\" damping=\"" << number(spring.damping)
          << "\" springlength=\"" << number(spring.rest_length) << "\">\n"
          << "      <site site=\"" << name("particle_", static_cast<size_t>(spring.i))
          << "\"/>\n      <site site=\"" << name("particle_", static_cast<size_t>(spring.j))
          << "\"/>\n    </spatial>\n";
    }
    out << "  </tendon>\n";
  }
  out << "</mujoco>\n";
  return out.str();
}

void write_mjcf(const std::filesystem::path& path, const analysis::SpringNetwork& network,
                const MjcfOptions& options) {
  if (network.volumes.empty()) {
    write_file_atomically(path, mjcf_document(network, options));
    return;
  }
  MjcfOptions with_terms = options;
  with_terms.runtime_model = path.stem().string() + ".isospring.json";
  const std::string document = mjcf_document(network, with_terms);  // checks before writing
  write_model_json(path.parent_path() / with_terms.runtime_model, network);
  write_file_atomically(path, document);
}

}  // namespace isospring::io
