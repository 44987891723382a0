// rigid_offset and rigid_offset_per_load: rigid motion of the specimen in the measuring frame,
// one for all load cases or one per load case (2D: 2 translations + 1 rotation, 3D: 3 + 3).
#include <Eigen/Geometry>
#include <memory>
#include <string>

#include "isospring/fitting/effect.hpp"

namespace isospring::fitting {

namespace {

// A measuring frame's offset does not depend on the load: `shared` is one rigid motion for every
// load case; per load case (shared false) only when the specimen may have moved between them
// (re-clamped, re-seated). The F-test between the two tells a moved frame (shared) from motions
// that change with the load case (a compliant clamp moves in proportion to its load, which a
// shared motion cannot follow).
class RigidOffset : public Effect {
 public:
  RigidOffset(const EffectContext& context, bool shared)
      : dimension_(context.dimension), shared_(shared) {
    const int dim = dimension_;
    const int motions = dim == 2 ? 3 : 6;
    for (size_t l = 0; l < context.marker_positions.size(); ++l) {
      const auto& positions = context.marker_positions[l];
      const Eigen::Index rows = static_cast<Eigen::Index>(positions.size()) * dim;
      std::vector<Eigen::VectorXd> modes(static_cast<size_t>(motions), Eigen::VectorXd::Zero(rows));
      for (size_t m = 0; m < positions.size(); ++m) {
        const Eigen::Vector3d r = positions[m] - context.centre;
        const Eigen::Index row = static_cast<Eigen::Index>(m) * dim;
        for (int c = 0; c < dim; ++c) modes[static_cast<size_t>(c)][row + c] = 1.0;
        // Small rotations omega about the axes through the centre: u = omega x r.
        const int first_rotation = dim;
        for (int a = (dim == 2 ? 2 : 0); a < 3; ++a) {
          const Eigen::Vector3d u = Eigen::Vector3d::Unit(a).cross(r);
          auto& mode = modes[static_cast<size_t>(first_rotation + (dim == 2 ? 0 : a))];
          for (int c = 0; c < dim; ++c) mode[row + c] = u[c];
        }
      }
      modes_.push_back(modes);
      load_case_ids_.push_back(load_case_ids(context)[l]);
    }
  }
  std::string name() const override { return shared_ ? "rigid_offset" : "rigid_offset_per_load"; }
  std::string simpler() const override { return shared_ ? "" : "rigid_offset"; }
  std::vector<std::string> parameter_names() const override {
    std::vector<std::string> names;
    for (size_t l = 0; l < (shared_ ? 1 : load_case_ids_.size()); ++l) {
      const std::string prefix = shared_ ? "" : load_case_ids_[l] + ".";
      for (int c = 0; c < dimension_; ++c) names.push_back(prefix + "t" + "xyz"[c]);
      for (int a = (dimension_ == 2 ? 2 : 0); a < 3; ++a) names.push_back(prefix + "r" + "xyz"[a]);
    }
    return names;
  }
  std::vector<std::string> parameter_units() const override {
    std::vector<std::string> units;
    for (size_t l = 0; l < (shared_ ? 1 : load_case_ids_.size()); ++l) {
      for (int c = 0; c < dimension_; ++c) units.push_back("m");
      for (int a = (dimension_ == 2 ? 2 : 0); a < 3; ++a) units.push_back("rad");
    }
    return units;
  }
  void add_terms(const EffectContext&, int first, ModelTerms& terms) const override {
    const int motions = dimension_ == 2 ? 3 : 6;
    for (size_t l = 0; l < modes_.size(); ++l) {
      int index = first + (shared_ ? 0 : static_cast<int>(l) * motions);
      for (const Eigen::VectorXd& mode : modes_[l])
        terms.offsets.push_back({static_cast<int>(l), mode, linear_coefficient(index++)});
    }
  }

 private:
  int dimension_;
  bool shared_;
  std::vector<std::vector<Eigen::VectorXd>> modes_;  // per load case: observation-space motions
  std::vector<std::string> load_case_ids_;
};

// A measurement artefact: the specimen, not the material or the loads, moved.
CarryOverResult rigid_offset_carry_over(const Eigen::VectorXd&, SpringModelChanges&) {
  return {CarryOver::kNotCarried, "(a measurement-frame effect, not part of the model)"};
}

}  // namespace

EffectType rigid_offset_effect_type() {
  EffectType type;
  type.name = "rigid_offset";
  type.make = [](const EffectContext& context, std::string*) -> std::unique_ptr<Effect> {
    return std::make_unique<RigidOffset>(context, true);
  };
  type.carry_over = rigid_offset_carry_over;
  return type;
}

EffectType rigid_offset_per_load_effect_type() {
  EffectType type;
  type.name = "rigid_offset_per_load";
  type.make = [](const EffectContext& context, std::string* why) -> std::unique_ptr<Effect> {
    if (load_case_ids(context).size() < 2) {
      if (why) *why = "one load case: the same as rigid_offset";
      return nullptr;
    }
    return std::make_unique<RigidOffset>(context, false);
  };
  type.carry_over = rigid_offset_carry_over;
  return type;
}

}  // namespace isospring::fitting
