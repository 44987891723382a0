// The single-file commands' use cases as library calls (io/input_file.hpp, info_command.hpp,
// refine_command.hpp, export_command.hpp, import_command.hpp, report_patch.hpp) on shipped files.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: CTest runs tests in parallel processes

#include <filesystem>
#include <fstream>

#include "isospring/io/input_file.hpp"
#include "isospring/io/patch_file.hpp"
#include "isospring/io/report_patch.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/calibrate_command.hpp"
#include "isospring/workflows/export_command.hpp"
#include "isospring/workflows/import_command.hpp"
#include "isospring/workflows/info_command.hpp"
#include "isospring/workflows/refine_command.hpp"

namespace isospring::workflows {
using namespace isospring::io;  // the formats the use cases read and write
namespace {
namespace fs = std::filesystem;

const std::string kExamples = std::string(ISOSPRING_SOURCE_DIR) + "/examples/";
const std::string kPatches = kExamples + "patches/quarter_annulus.json";

fs::path fresh_folder(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("isospring_files_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(InputFile, KindsAndTheFilesTheyRead) {
  EXPECT_EQ(input_kind(kPatches), InputKind::kPatchFile);
  EXPECT_EQ(input_kind(kExamples + "kirsch_plate.json"), InputKind::kCaseFile);
  EXPECT_EQ(input_kind(kExamples + "cad/block.step"), InputKind::kCad);
  const auto inputs = input_files(kExamples + "identify/plate_hidden_gravity.json");
  ASSERT_EQ(inputs.size(), 2u);  // the case and its markers
  EXPECT_EQ(inputs[1].filename(), "markers.csv");
  EXPECT_EQ(read_patches_any(kPatches).size(), read_patch_file(kPatches).size());
}

TEST(InfoUseCase, JsonAndTextDescribeThePatches) {
  const nlohmann::json j = file_info_json(kPatches);
  EXPECT_EQ(j["kind"], "patches");
  const std::vector<nurbs::Patch> patches = read_patch_file(kPatches);
  ASSERT_EQ(j["patches"].size(), patches.size());
  EXPECT_EQ(j["patches"][0], patch_json(patches[0]));
  const std::string text = file_info_text(kPatches);
  EXPECT_NE(text.find("patch 0: parametric dimension"), std::string::npos) << text;
  EXPECT_EQ(file_info_json(kExamples + "kirsch_plate.json")["kind"], "case");
}

TEST(RefineUseCase, SplittingIsExactAndBadOptionsNameThePatch) {
  const std::vector<nurbs::Patch> patches = read_patch_file(kPatches);
  RefineCommandOptions options;
  options.h = 2;
  options.elevate = {1};
  options.input = kPatches;
  const RefineCommandResult r = run_refine(patches, options);
  ASSERT_EQ(r.after.size(), patches.size());
  EXPECT_EQ(r.after[0].num_elements(), 4 * patches[0].num_elements());  // a surface: 2 x 2
  EXPECT_EQ(r.after[0].degree(0), patches[0].degree(0) + 1);
  EXPECT_LT(r.deviation[0], 1e-12);
  nlohmann::json json;
  MarkdownReport md;
  refine_report(r, options, "out.json", json, md);
  EXPECT_EQ(json["largest_geometry_deviation"], r.deviation[0]);
  EXPECT_NE(md.text().find("Written to out.json"), std::string::npos);

  options.insert = {"q=0.5"};
  try {
    run_refine(patches, options);
    FAIL() << "no error";
  } catch (const nurbs::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("patch 0: --insert: direction 'q'", 0), 0u) << e.what();
  }
  options.insert.clear();
  options.h = 1000000;  // 10^12 control points
  EXPECT_THROW(run_refine(patches, options), nurbs::InputError);
}

TEST(ImportUseCase, TheBlockIsOneVolumePatch) {
  ImportCommandOptions options;
  options.input = kExamples + "cad/block.step";
  const ImportCommandResult r = run_import(options, nullptr, nullptr);
  ASSERT_EQ(r.patches.size(), 1u);
  EXPECT_EQ(r.patches[0].param_dim(), 3);
  nlohmann::json json;
  MarkdownReport md;
  import_report(r, options, "block.json", json, md);
  EXPECT_EQ(json["patch_count"], 1);
  EXPECT_NEAR(json["measure_relative_error"].get<double>(), 0.0, 1e-9);
}

TEST(ExportUseCase, FormatsByExtension) {
  const fs::path dir = fresh_folder("export");
  // A model to export: the calibrated square (calibrate_command.hpp).
  const CalibrateCommandResult calibrated =
      run_calibrate(read_case_file(kExamples + "calibrate_square.json"), Progress("t", true));
  write_spring_model_json(dir / "model.json",
                          calibrate_spring_model(calibrated, calibrate_report_json(calibrated)));
  ExportCommandOptions options;
  options.input = (dir / "model.json").string();
  for (const auto& [file, format] : std::vector<std::pair<std::string, std::string>>{
           {"m.xml", "mjcf"}, {"m.scn", "sofa"}, {"m.vtp", "vtk"}, {"m.json", "json"}}) {
    options.output = (dir / file).string();
    const ExportCommandResult r = run_export(options);
    EXPECT_EQ(r.format, format);
    EXPECT_TRUE(fs::exists(dir / file)) << file;
    nlohmann::json json;
    MarkdownReport md;
    export_report(r, options, json, md);
    EXPECT_EQ(json["springs"], r.model.network.springs.size());
  }
  options.output = (dir / "m.txt").string();
  EXPECT_THROW(run_export(options), nurbs::InputError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace isospring::workflows
