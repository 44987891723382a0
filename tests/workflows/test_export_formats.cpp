// The export format table (export_formats.hpp): every format writes through run_export, each
// extension selects its format, and the --format name, the extension rule and the errors all come
// from the table; what a format writes is its writer's output, byte for byte.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: CTest runs tests in parallel processes

#include <fstream>
#include <set>
#include <sstream>

#include "isospring/io/export_mjcf.hpp"
#include "isospring/io/export_sofa.hpp"
#include "isospring/io/vtk_spring_network.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/export_formats.hpp"

namespace isospring::workflows {
using namespace isospring::io;  // the formats the use cases read and write
namespace {
namespace fs = std::filesystem;

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class ExportFormats : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           (std::string("isospring_test_export_formats-") + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    SpringModel model;
    auto& n = model.network;
    n.dimension = 2;
    n.positions = {{0, 0, 0}, {0.1, 0, 0}, {0.1, 0.1, 0}, {0, 0.1, 0}};
    n.masses = {0.1, 0.1, 0.2, 0.1};
    n.fixed = {true, false, false, true};
    n.springs = {{0, 1, 100, 1, 0.1, 0},
                 {1, 2, 200, 1, 0.1, 0},
                 {2, 3, 100, 1, 0.1, 0},
                 {0, 2, 50, 1, std::sqrt(0.02), 1},
                 {1, 3, 50, 1, std::sqrt(0.02), 1}};
    model.units = {{"length", "m"}};
    model.provenance = {{"case", "square"}};
    model.load_cases = {{"L1", {{2, Eigen::Vector3d(0.0, -1.0, 0.0)}}}};
    write_spring_model_json(dir_ / "model.json", model);
    model_ = read_model_json(dir_ / "model.json");
  }
  void TearDown() override { fs::remove_all(dir_); }
  ExportCommandOptions options(const std::string& output, const std::string& format = "") const {
    ExportCommandOptions o;
    o.input = (dir_ / "model.json").string();
    o.output = (dir_ / output).string();
    o.format = format;
    o.modes = 2;
    return o;
  }
  fs::path dir_;
  SpringModel model_;
};

TEST_F(ExportFormats, EveryFormatWritesThroughRunExport) {
  std::set<std::string> names;
  for (const ExportFormat& format : export_formats()) {
    SCOPED_TRACE(format.name);
    EXPECT_TRUE(names.insert(format.name).second) << "listed twice";
    ASSERT_NE(format.write, nullptr);
    EXPECT_FALSE(format.description.empty());
    const std::string file = "by_name." + format.name;
    const ExportCommandResult r = run_export(options(file, format.name));
    EXPECT_EQ(r.format, format.name);
    EXPECT_GT(fs::file_size(dir_ / file), 0u);
    EXPECT_EQ(r.reduced.has_value(), format.name == "reduced");
    nlohmann::json json;
    MarkdownReport md;
    export_report(r, options(file, format.name), json, md);
    EXPECT_EQ(json["format"], format.name);
    EXPECT_EQ(json.contains("gravity"), format.engine_scene);
  }
  EXPECT_EQ(names, (std::set<std::string>{"json", "mjcf", "sofa", "vtk", "reduced"}));
}

TEST_F(ExportFormats, EachExtensionSelectsItsFormat) {
  std::set<std::string> extensions;
  for (const ExportFormat& format : export_formats())
    for (const std::string& ext : format.extensions) {
      SCOPED_TRACE(ext);
      EXPECT_TRUE(extensions.insert(ext).second) << "claimed by two formats";
      EXPECT_EQ(export_format_of(options("m" + ext)).name, format.name);
      EXPECT_EQ(run_export(options("m" + ext)).format, format.name);
    }
  EXPECT_EQ(extensions, (std::set<std::string>{".json", ".xml", ".mjcf", ".scn", ".vtp", ".vtm"}));
  // --format wins over the extension.
  EXPECT_EQ(export_format_of(options("m.xml", "sofa")).name, "sofa");
}

TEST_F(ExportFormats, UnknownFormatsAndExtensionsAreRefusedByName) {
  try {
    run_export(options("m.txt"));
    FAIL() << "expected an InputError";
  } catch (const nurbs::InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("add --format json|mjcf|sofa|vtk (or use .json, .xml, .mjcf, .scn, "
                        ".vtp, .vtm)"),
              std::string::npos)
        << what;
  }
  // A library caller's unknown --format used to fall through to the VTK writer.
  EXPECT_THROW(run_export(options("m.vtp", "obj")), nurbs::InputError);
  EXPECT_FALSE(fs::exists(dir_ / "m.vtp"));
  EXPECT_THROW(export_format("obj"), nurbs::InputError);
  const std::string help = export_formats_help();
  for (const ExportFormat& format : export_formats())
    EXPECT_NE(help.find(format.name + " (" + format.description + ")"), std::string::npos) << help;
}

// The table only routes: each format's file is its writer's, byte for byte, with the command's
// defaults (gravity from the model, automatic time step, provenance comment).
TEST_F(ExportFormats, OutputIsTheWritersOwn) {
  run_export(options("a.json", "json"));
  write_spring_model_json(dir_ / "b.json", model_);
  EXPECT_EQ(read(dir_ / "a.json"), read(dir_ / "b.json"));

  const std::string comment = "source model.json; provenance " + model_.provenance.dump();
  run_export(options("a.xml"));
  MjcfOptions mjcf;
  mjcf.model_name = "model";
  mjcf.gravity = engine_gravity(model_.network, model_.gravity, std::nullopt);
  mjcf.comment = comment;
  write_mjcf(dir_ / "b.xml", model_.network, mjcf);
  EXPECT_EQ(read(dir_ / "a.xml"), read(dir_ / "b.xml"));

  run_export(options("a.scn"));
  SofaOptions sofa;
  sofa.gravity = mjcf.gravity;
  sofa.comment = comment;
  write_sofa_scene(dir_ / "b.scn", model_.network, sofa);
  EXPECT_EQ(read(dir_ / "a.scn"), read(dir_ / "b.scn"));

  run_export(options("a.vtp"));
  write_spring_network_vtp(dir_ / "b.vtp", model_.network);
  EXPECT_EQ(read(dir_ / "a.vtp"), read(dir_ / "b.vtp"));
}

}  // namespace
}  // namespace isospring::workflows
