// Marker CSV reading: default and mapped headers, units, and every bad-input message.
#include <gtest/gtest.h>

#include <fstream>

#include "isospring/fitting/effect.hpp"
#include "isospring/io/markers.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {

std::filesystem::path write_csv(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("isospring_markers_" + name);
  std::ofstream(path) << text;
  return path;
}

std::string error_of(const std::filesystem::path& path, const MarkerFileOptions& options) {
  try {
    read_markers_csv(path, options);
  } catch (const nurbs::InputError& e) {
    return e.what();
  }
  return "";
}

MarkerFileOptions options_2d() {
  MarkerFileOptions o;
  o.dimension = 2;
  o.load_cases = {"L1", "L2"};
  return o;
}

TEST(Markers, ReadsTheDefaultHeader) {
  const auto path = write_csv("default.csv",
                              "load_case,x,y,z,ux,uy,uz,sigma\n"
                              "L1,0.1,0.2,0.3,1e-6,2e-6,3e-6,1e-7\n\n"
                              "L2,0.1,0.2,0.3,4e-6,5e-6,6e-6,2e-7\n");
  MarkerFileOptions o;
  o.load_cases = {"L1", "L2"};
  const fitting::Measurements m = read_markers_csv(path, o);
  ASSERT_EQ(m.markers.size(), 2u);
  EXPECT_EQ(m.markers[1].load_case, "L2");
  EXPECT_EQ(m.markers[1].row, 4);
  EXPECT_EQ(m.markers[1].displacement, Eigen::Vector3d(4e-6, 5e-6, 6e-6));
  EXPECT_EQ(m.markers[0].sigma, 1e-7);
}

TEST(Markers, MapsTheDicHeaderAndMillimetres) {
  const auto path = write_csv("dic.csv",
                              "x-coordinate [mm],y-coordinate [mm],x-displacement [mm],"
                              "y-displacement [mm]\n"
                              "40.0,10.0,0.5,-0.25\n");
  const nlohmann::json settings = {{"file", "dic.csv"},
                                   {"units", "mm"},
                                   {"load_case", "L2"},
                                   {"noise_sigma", 0.002},
                                   {"columns",
                                    {{"x", "x-coordinate [mm]"},
                                     {"y", "y-coordinate [mm]"},
                                     {"ux", "x-displacement [mm]"},
                                     {"uy", "y-displacement [mm]"}}}};
  const MeasurementSettings s = read_measurement_settings(
      settings, std::filesystem::temp_directory_path(), 2, {"L1", "L2"}, "case.json: measurements");
  EXPECT_DOUBLE_EQ(s.identify.noise_sigma, 2e-6);
  const fitting::Measurements m = read_markers_csv(path, s.file_options);
  ASSERT_EQ(m.markers.size(), 1u);
  EXPECT_EQ(m.markers[0].load_case, "L2");
  EXPECT_DOUBLE_EQ(m.markers[0].position.x(), 0.04);
  EXPECT_DOUBLE_EQ(m.markers[0].displacement.y(), -0.25e-3);
}

TEST(Markers, BadRowsNameFileRowAndColumn) {
  const auto o = options_2d();
  std::string e = error_of(write_csv("nan.csv", "load_case,x,y,ux,uy\nL1,0,0,nan,0\n"), o);
  EXPECT_NE(e.find("row 2"), std::string::npos) << e;
  EXPECT_NE(e.find("\"ux\""), std::string::npos) << e;
  e = error_of(write_csv("text.csv", "load_case,x,y,ux,uy\nL1,0,zero,0,0\n"), o);
  EXPECT_NE(e.find("column \"y\""), std::string::npos) << e;
  e = error_of(write_csv("dup.csv", "load_case,x,y,ux,uy\nL1,0,0,0,0\nL2,0,0,0,0\nL1,0,0,1,1\n"),
               o);
  EXPECT_NE(e.find("row 4"), std::string::npos) << e;
  EXPECT_NE(e.find("row 2"), std::string::npos) << e;
  e = error_of(write_csv("case.csv", "load_case,x,y,ux,uy\nL7,0,0,0,0\n"), o);
  EXPECT_NE(e.find("\"L7\""), std::string::npos) << e;
  EXPECT_NE(e.find("L1, L2"), std::string::npos) << e;
  e = error_of(write_csv("col.csv", "load_case,x,y,ux\nL1,0,0,0\n"), o);
  EXPECT_NE(e.find("no column \"uy\""), std::string::npos) << e;
  e = error_of(write_csv("empty.csv", "load_case,x,y,ux,uy\n"), o);
  EXPECT_NE(e.find("no marker rows"), std::string::npos) << e;
}

TEST(Markers, NulByteIsAnErrorNotATruncatedNumber) {
  // "0.5<NUL>7" used to read as 0.5 (strtod stops at the NUL).
  const auto o = options_2d();
  const std::string text =
      std::string("load_case,x,y,ux,uy\nL1,0,0,0,0\nL1,1,0,0.5") + '\0' + "7,0\n";
  const std::string e = error_of(write_csv("nul.csv", text), o);
  EXPECT_NE(e.find("nul.csv: line 3 holds a NUL byte"), std::string::npos) << e;
}

TEST(Markers, Utf8ByteOrderMarkIsNotPartOfTheFirstColumn) {
  // A spreadsheet's UTF-8 export starts with a byte order mark; it used to be reported as
  // a missing "load_case" column.
  const auto path = write_csv("bom.csv", "\xEF\xBB\xBFload_case,x,y,ux,uy\nL2,0,0,1e-6,0\n");
  const fitting::Measurements m = read_markers_csv(path, options_2d());
  ASSERT_EQ(m.markers.size(), 1u);
  EXPECT_EQ(m.markers[0].load_case, "L2");
}

TEST(Markers, SettingsRejectUnknownFieldsAndEffects) {
  const auto folder = std::filesystem::temp_directory_path();
  EXPECT_THROW(read_measurement_settings({{"file", "a.csv"}, {"noise", 1}}, folder, 2, {"L1"}, "m"),
               nurbs::InputError);
  EXPECT_THROW(read_measurement_settings({{"file", "a.csv"}, {"effects", {"magic"}}}, folder, 2,
                                         {"L1"}, "m"),
               nurbs::InputError);
  EXPECT_THROW(
      read_measurement_settings({{"file", "a.csv"}, {"units", "inch"}}, folder, 2, {"L1"}, "m"),
      nurbs::InputError);
}

// measurements.effects accepts exactly the effect registry (fitting::effect_types()): every
// registered name, in the order given, and nothing else; the refusal lists the registry.
TEST(Markers, EffectsAreExactlyTheRegistry) {
  const auto folder = std::filesystem::temp_directory_path();
  std::vector<std::string> registered;
  for (const auto& type : fitting::effect_types()) registered.push_back(type.name);
  ASSERT_FALSE(registered.empty());
  const std::vector<std::string> reversed(registered.rbegin(), registered.rend());
  const MeasurementSettings s =
      read_measurement_settings({{"file", "a.csv"}, {"effects", reversed}}, folder, 2, {"L1"}, "m");
  ASSERT_TRUE(s.identify.candidates.has_value());
  EXPECT_EQ(*s.identify.candidates, reversed);
  try {
    read_measurement_settings({{"file", "a.csv"}, {"effects", {"magic"}}}, folder, 2, {"L1"}, "m");
    FAIL() << "expected an InputError";
  } catch (const nurbs::InputError& e) {
    std::string list;
    for (const auto& n : registered) list += (list.empty() ? "" : ", ") + n;
    const std::string what = e.what();
    EXPECT_NE(what.find("is not an effect; use: " + list), std::string::npos) << what;
    EXPECT_EQ(what.substr(what.size() - list.size()), list) << what;
  }
}

}  // namespace
}  // namespace isospring::io
