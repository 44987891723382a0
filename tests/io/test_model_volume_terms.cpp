// Volume terms in model.json and the engine exports: exact round trip, named errors,
// plain models unchanged on disk, and SOFA / MuJoCo refusing what they cannot represent.
#include <gtest/gtest.h>

#include <cmath>

#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_volume.hpp"
#include "isospring/io/export_mjcf.hpp"
#include "isospring/io/export_sofa.hpp"
#include "isospring/io/model_file.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {
using nlohmann::json;

// A unit cube cell (corners in tensor order) with its 12 edge springs and one volume term.
analysis::SpringNetwork cube_cell() {
  analysis::SpringNetwork n;
  n.dimension = 3;
  for (int a = 0; a < 8; ++a) {
    n.positions.emplace_back((a & 1) * 0.1, ((a >> 1) & 1) * 0.1, ((a >> 2) & 1) * 0.1);
    n.masses.push_back(1.0 / 3.0);
    n.fixed.push_back(a % 2 == 0);
  }
  for (int a = 0; a < 8; ++a)
    for (int b = a + 1; b < 8; ++b)
      if (__builtin_popcount(static_cast<unsigned>(a ^ b)) == 1)
        n.springs.push_back({a, b, 1000.0 + a + b / 7.0, 0.0, 0.1, 0});
  analysis::VolumeTerm term;
  for (int a = 0; a < 8; ++a) term.particles[static_cast<size_t>(a)] = a;
  term.rest_volume = analysis::rest_cell_volume(n, term);
  term.modulus = 3456.789012345678;
  term.group = 1;
  n.volumes.push_back(term);
  return n;
}

TEST(ModelVolumeTerms, RoundTripIsExactAndPlainModelsHaveNoVolumesKey) {
  const analysis::SpringNetwork n = cube_cell();
  EXPECT_NEAR(n.volumes[0].rest_volume, 1e-3, 1e-15);
  const json document = model_to_json(n);
  ASSERT_TRUE(document.contains("volumes"));
  EXPECT_EQ(document["volumes"][0]["particles"].size(), 8u);
  const SpringModel m = model_from_json(json::parse(document.dump()), "model.json");
  ASSERT_EQ(m.network.volumes.size(), 1u);
  EXPECT_EQ(m.network.volumes[0].particles, n.volumes[0].particles);
  EXPECT_EQ(m.network.volumes[0].modulus, n.volumes[0].modulus);
  EXPECT_EQ(m.network.volumes[0].rest_volume, n.volumes[0].rest_volume);
  EXPECT_EQ(m.network.volumes[0].group, 1);
  // The model read back is the same mechanical model (the volume term is in its stiffness).
  const Eigen::MatrixXd k_written = Eigen::MatrixXd(analysis::rest_stiffness(n));
  const Eigen::MatrixXd k_read = Eigen::MatrixXd(analysis::rest_stiffness(m.network));
  EXPECT_EQ((k_written - k_read).norm(), 0.0);
  analysis::SpringNetwork springs_only = n;
  springs_only.volumes.clear();
  EXPECT_GT((k_written - Eigen::MatrixXd(analysis::rest_stiffness(springs_only))).norm(), 1.0);
  EXPECT_FALSE(model_to_json(springs_only).contains("volumes"));
}

TEST(ModelVolumeTerms, BadFieldsAreNamed) {
  const json good = model_to_json(cube_cell());
  auto expect_error = [](const json& document, const std::string& fragment) {
    try {
      model_from_json(document, "model.json");
      FAIL() << "no InputError for " << fragment;
    } catch (const nurbs::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  json bad = good;
  bad["volumes"][0]["particles"].erase(7);
  expect_error(bad, "volumes[0].particles");
  bad = good;
  bad["volumes"][0]["particles"][3] = 99;
  expect_error(bad, "volumes[0].particles: particle index 99");
  bad = good;
  bad["volumes"][0]["kappa"] = -1.0;
  expect_error(bad, "volumes[0].kappa");
  bad = good;
  bad["volumes"][0]["V0"] = 0.0;
  expect_error(bad, "volumes[0].V0");
  bad = good;
  bad["volumes"][0]["rest"] = 1.0;
  expect_error(bad, "volumes[0].rest");
}

TEST(ModelVolumeTerms, EnginesWithoutAVolumeElementRefuseAndSaySo) {
  const analysis::SpringNetwork n = cube_cell();
  for (int engine = 0; engine < 2; ++engine) {
    try {
      if (engine == 0)
        (void)sofa_scene(n);
      else
        (void)mjcf_document(n);
      FAIL() << "engine " << engine << " exported a model with volume terms";
    } catch (const nurbs::InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("1 volume terms"), std::string::npos) << what;
      EXPECT_NE(what.find(engine == 0 ? "SOFA" : "MuJoCo"), std::string::npos) << what;
      EXPECT_NE(what.find("model.json"), std::string::npos) << what;
    }
  }
  // The same springs without the volume term export.
  analysis::SpringNetwork plain = n;
  plain.volumes.clear();
  EXPECT_NO_THROW((void)sofa_scene(plain));
  EXPECT_NO_THROW((void)mjcf_document(plain));
}

}  // namespace
}  // namespace isospring::io

// Shear terms (CellEnergy::kShear) are written with "mu" instead of "kappa" and read back as
// shear terms; an entry with both or neither is refused by name.
namespace isospring::io {
namespace {

TEST(ModelVolumeTerms, ShearTermsRoundTripAsMuAndKindsAreNotMixedUp) {
  analysis::SpringNetwork n = cube_cell();
  analysis::VolumeTerm shear = n.volumes[0];
  shear.kind = analysis::CellEnergy::kShear;
  shear.modulus = 1234.5678901234567;
  shear.group = 2;
  n.volumes.push_back(shear);
  const json document = model_to_json(n);
  EXPECT_TRUE(document["volumes"][0].contains("kappa"));
  EXPECT_FALSE(document["volumes"][0].contains("mu"));
  EXPECT_TRUE(document["volumes"][1].contains("mu"));
  EXPECT_FALSE(document["volumes"][1].contains("kappa"));
  const SpringModel m = model_from_json(json::parse(document.dump()), "model.json");
  ASSERT_EQ(m.network.volumes.size(), 2u);
  EXPECT_EQ(m.network.volumes[0].kind, analysis::CellEnergy::kVolume);
  EXPECT_EQ(m.network.volumes[1].kind, analysis::CellEnergy::kShear);
  EXPECT_EQ(m.network.volumes[1].modulus, shear.modulus);
  EXPECT_EQ(m.network.volumes[1].group, 2);
  EXPECT_EQ((Eigen::MatrixXd(analysis::rest_stiffness(n)) -
             Eigen::MatrixXd(analysis::rest_stiffness(m.network)))
                .norm(),
            0.0);
  for (bool both : {true, false}) {
    json bad = document;
    if (both)
      bad["volumes"][1]["kappa"] = 1.0;
    else
      bad["volumes"][1].erase("mu");
    try {
      model_from_json(bad, "model.json");
      FAIL() << "no InputError";
    } catch (const nurbs::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("volumes[1]"), std::string::npos) << e.what();
    }
  }
  json negative = document;
  negative["volumes"][1]["mu"] = -1.0;
  try {
    model_from_json(negative, "model.json");
    FAIL() << "no InputError";
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("volumes[1].mu"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace isospring::io
